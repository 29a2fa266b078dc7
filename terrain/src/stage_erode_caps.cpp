// Erosion caps: a column under a body but not touching it may receive only the room up to
// the body, split over the columns that will give to it this pass (the same test the
// givers make), so it fills in one pass instead of creeping up on the body.

#include <algorithm>

#include "neighbours.h"
#include "stage_erode.h"
#include "stage_imprint.h"

namespace shore::terrain {

void ErodeStage::compute_caps(const Region& region, std::span<const unsigned char> flags,
                              std::span<const double> body) {
  if (region.mat.empty())
    compute_caps_as<false>(region, flags, body);
  else
    compute_caps_as<true>(region, flags, body);
}

// kMap: each giver's test uses its own material's limit (lims_); else lim_'s.
template <bool kMap>
void ErodeStage::compute_caps_as(const Region& region, std::span<const unsigned char> flags,
                                 std::span<const double> body) {
  const int w = region.w;
  const auto off = neighbour_offsets(w);
  const double eps = lim_.eps, least_axis = lim_.least_give_in[0], least_diagonal = lim_.least_give_in[1];
  double give_in[8];
  std::copy(std::begin(lim_.give_in), std::end(lim_.give_in), give_in);
  // With a map, each palette entry's row of give_in side by side: a giver's limit is read at
  // its index times 8 doubles, not at the stride of a whole ErosionLimits.
  [[maybe_unused]] double give_in_of[Terrain::kMaxMaterials][8];
  if constexpr (kMap)
    for (std::size_t m = 0; m < lims_.size(); ++m)
      std::copy(std::begin(lims_[m].give_in), std::end(lims_[m].give_in), give_in_of[m]);
  region.for_rows(0, region.h, [&](int y) {
    recap_.for_each_in_row(y, [&](int x) {
      const std::size_t k = region.at(x, y);
      const double hk = region.ht[k];
      const double room = body[k] - hk;
      int count = 0;
      const NeighbourExtremes highest =
          neighbour_extremes(&region.ht[k], w, [](double a, double b) { return std::max(a, b); });
      if (room > eps && (highest.axis - hk > least_axis || highest.diagonal - hk > least_diagonal))
#pragma GCC unroll 8
        for (int d = 0; d < 8; ++d) {
          const std::size_t nk = k + off[d];
          if ((flags[nk] & (kInterior | kContact)) != kInterior) continue;
          // The giver's own limit (its material's, with a map).
          const double limit = kMap ? give_in_of[region.mat[nk]][d] : give_in[d];
          if (region.ht[nk] - hk > limit) ++count;
        }
      cap_[k] = count > 0 ? room / count : 0.0;
    });
  });
}

}  // namespace shore::terrain
