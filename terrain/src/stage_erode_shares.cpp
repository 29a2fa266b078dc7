// Erosion shares: from the heights as the pass found them, what each candidate gives each
// of its too-steep downhill neighbours.

#include <algorithm>
#include <bit>

#include "neighbours.h"
#include "stage_erode.h"

namespace shore::terrain {

// A pair is too steep when the drop exceeds its limit by more than eps; the giver moves
// sigma times the average excess, split equally among those neighbours and never more than
// it holds above bedrock (with a map: than its top layer), and only what the receivers'
// caps let through. Sets q_, mask_, out_, givers_ and steep_givers_ (with a map spent_,
// row_cross_ and cross_givers_ too); returns whether anything flows.
bool ErodeStage::compute_shares(const Region& region) {
  return region.mat.empty() ? compute_shares_as<false>(region) : compute_shares_as<true>(region);
}

// kMap: each giver reads its own material's limits (lims_); else every column has lim_'s.
template <bool kMap>
bool ErodeStage::compute_shares_as(const Region& region) {
  const int w = region.w, h = region.h;
  const auto off = neighbour_offsets(w);
  const ErosionLimits one = lim_;
  region.for_rows(0, h, [&](int y) {
    std::uint64_t* giver_row = givers_.row(y);
    std::uint64_t* steep_row = steep_givers_.row(y);
    bool flow = false, cross = false;
    const auto give = [&](int x) __attribute__((always_inline)) {
      const std::size_t k = region.at(x, y);
      const ErosionLimits& lim = kMap ? lims_[region.mat[k]] : one;
      [[maybe_unused]] const std::uint8_t top = kMap ? region.mat[k] : 0;
      const double h0 = region.ht[k];
      const NeighbourExtremes lowest =
          neighbour_extremes(&region.ht[k], w, [](double a, double b) { return std::min(a, b); });
      if (!(h0 - lowest.axis > lim.least_give[0]) && !(h0 - lowest.diagonal > lim.least_give[1])) return;
      double excess_sum = 0.0;
      int count = 0;
      unsigned mk = 0, steep_mk = 0;
      [[maybe_unused]] bool mixed = false;  // a pair of another material or a layered column
#pragma GCC unroll 8
      for (int d = 0; d < 8; ++d) {
        const std::size_t nk = k + off[d];  // interior: neighbours exist
        if (cap_[nk] == 0.0) continue;
        const double diff = h0 - region.ht[nk];
        const int c = cover_[nk];
        if (!(diff > lim.give[d][c])) continue;
        if constexpr (kMap) {
          // The soil keeps its material: a neighbour that may not take it holds the pair.
          // (A rigid column's loose soil lands as the receiver's own, as before maps.)
          if (region.mat[nk] != top) {
            if (!rigid_[top] && !takes(region, nk, top)) continue;
            mixed = true;
          }
          mixed = mixed || kind_[nk] != kUnlayered;
        }
        excess_sum += diff - lim.thr[d][c];
        ++count;
        mk |= 1u << d;
        if (diff > lim.steep_limit[d][c]) steep_mk |= 1u << d;
      }
      if (count == 0) return;
      double share = lim.sigma * (excess_sum / count) / count;
      share = std::min(share, std::max(0.0, h0 - region.bed[k]) / count);
      bool spent = false;  // the top layer bounds the share: all of it goes
      if constexpr (kMap) {
        if (kind_[k] == kCrust && !(share < std::max(0.0, thick_[k]) / count)) {
          share = std::max(0.0, thick_[k]) / count;
          spent = true;
        }
      }
      if (!(share > 0.0)) return;
      double total = 0.0;
      bool steep_here = false;
#pragma GCC unroll 8
      for (int d = 0; d < 8; ++d) {
        if (!(mk & (1u << d))) continue;
        const double cap = cap_[k + off[d]];
        total += std::min(share, cap);
        if constexpr (kMap) spent = spent && cap >= share;
        // A pair whose flow the body caps (the column under it is full) stays steep: the
        // body holds that slope, erosion cannot relax it.
        steep_here = steep_here || ((steep_mk & (1u << d)) && cap >= share);
      }
      if (!(total > 0.0)) return;
      q_[k] = share;
      mask_[k] = static_cast<unsigned char>(mk);
      out_[k] = total;
      if constexpr (kMap) {
        spent_[k] = spent;
        if (mixed || kind_[k] != kUnlayered) {
          cross = true;
          cross_givers_.set(x, y);
        }
      }
      giver_row[x >> 6] |= ColumnBits::bit(x);
      flow = true;
      if (steep_here) steep_row[x >> 6] |= ColumnBits::bit(x);
    };
    // The candidates' bits walked here, not by ColumnBits::for_each_in_row, so the test above
    // is inlined into this row's loop (through a call, each captured value would be read
    // back from memory after every byte store).
    const std::uint64_t* cand_row = cand_.row(y);
    for (int i = 0; i < cand_.words; ++i)
      for (std::uint64_t word = cand_row[i]; word != 0; word &= word - 1) give(i * 64 + std::countr_zero(word));
    row_flow_[static_cast<std::size_t>(y)] = flow;  // only this row's task writes it
    if constexpr (kMap) row_cross_[static_cast<std::size_t>(y)] = cross;
  });
  bool flow = false;
  for (int y = 0; y < h; ++y) flow = flow || row_flow_[static_cast<std::size_t>(y)];
  return flow;
}

}  // namespace shore::terrain
