#include "stage_displace.h"

#include <algorithm>

#include "capacity_bytes.h"
#include "neighbours.h"

namespace shore::terrain {

namespace {

/// Calls f(k) for each index k of `closed`'s columns in rows of `width`, in index order.
template <class F>
void for_each_in(const GridRect& closed, int width, F f) {
  for (int y = 0; y < closed.ny; ++y) {
    const std::size_t row = static_cast<std::size_t>(closed.j0 + y) * static_cast<std::size_t>(width);
    for (int x = 0; x < closed.nx; ++x) f(row + static_cast<std::size_t>(closed.i0 + x));
  }
}

}  // namespace

// Counting sort of the contact columns (level > 0) by level, highest first; within a level
// in index order (rows of `closed` in order, each in order: index order).
void DisplaceStage::sort_by_level(std::span<const int> levels, int width, const GridRect& closed, int top_level) {
  count_.assign(static_cast<std::size_t>(top_level) + 2, 0);
  for_each_in(closed, width, [&](std::size_t k) {
    if (levels[k] > 0) ++count_[static_cast<std::size_t>(top_level - levels[k]) + 1];
  });
  for (std::size_t l = 1; l < count_.size(); ++l) count_[l] += count_[l - 1];
  order_.resize(static_cast<std::size_t>(count_.back()));
  for_each_in(closed, width, [&](std::size_t k) {
    if (levels[k] > 0) order_[static_cast<std::size_t>(count_[static_cast<std::size_t>(top_level - levels[k])]++)] = k;
  });
}

namespace {

// A layered column pressed across its crust's boundary in this step: the part of its
// pressing that lay within the crust (sinkage before it: the sinkage after less the
// displaced height) takes the crust's alpha (upper), the rest the lower layer's. Inline:
// under a wheel on a broken-through rut most contact columns are layered.
inline double layered_alpha(const ColumnLayer& layer, double upper, double lower, double sink, double displaced) {
  if (!(displaced > 0.0)) return upper;
  const double before = sink - displaced;
  const double in_crust = std::clamp(layer.boundary - before, 0.0, displaced);
  if (in_crust == displaced) return upper;
  return (upper * in_crust + lower * (displaced - in_crust)) / displaced;
}

}  // namespace

double DisplaceStage::run(Region& region, std::span<const int> levels, const GridRect& closed,
                          std::span<const double> displaced, std::span<const double> alpha) {
  int top_level = 0;
  for_each_in(closed, region.w, [&](std::size_t k) { top_level = std::max(top_level, levels[k]); });
  if (top_level == 0) return 0.0;
  sort_by_level(levels, region.w, closed, top_level);
  carry_.resize(levels.size());  // only the contact columns' entries are used, each set below

  const auto off = neighbour_offsets(region.w);
  double kept = 0.0;
  for (std::size_t k : order_) carry_[k] = 0.0;
  // Each pressed column's own share goes to the rim (one material: the same for all).
  const auto split = [&](std::size_t k, double a) {
    const double moved = a * displaced[k];
    kept += displaced[k] - moved;
    carry_[k] += moved;
  };
  if (region.mat.empty())
    for (std::size_t k : order_) split(k, alpha[0]);
  else if (region.layer.empty())
    for (std::size_t k : order_) split(k, alpha[region.mat[k]]);
  else {
    // Through raw pointers (carry_'s stores may alias a vector's data pointer), and the
    // two-piece split only where a column is layered: most contact columns are not.
    const std::uint8_t* mat = region.mat.data();
    const double* boundary = region.layer.boundary.data();
    const std::uint8_t* lower = region.layer.lower.data();
    const double* sink = region.sink.data();
    const double* a = alpha.data();
    for (std::size_t k : order_) {
      const ColumnLayer layer{boundary[k], lower[k]};
      split(k, layer.layered() ? layered_alpha(layer, a[mat[k]], a[layer.lower], sink[k], displaced[k]) : a[mat[k]]);
    }
  }
  for (std::size_t k : order_) {
    const double carry = carry_[k];
    if (carry == 0.0) continue;
    const int level = levels[k];
    int lower = 0;
    for (int d = 0; d < 8; ++d)  // contact columns are interior: neighbours exist
      if (levels[k + off[d]] < level) ++lower;
    const double share = carry / lower;
    for (int d = 0; d < 8; ++d) {
      const std::size_t nk = k + off[d];
      if (levels[nk] >= level) continue;
      if (levels[nk] == 0)
        region.ht[nk] += share;
      else
        carry_[nk] += share;
    }
  }
  return kept;
}

std::size_t DisplaceStage::bytes() const { return capacity_bytes(count_, order_, carry_); }

}  // namespace shore::terrain
