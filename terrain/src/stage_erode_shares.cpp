// Erosion shares: from the heights as the pass found them, what each candidate gives each
// of its too-steep downhill neighbours.

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>

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

namespace {

// Four bytes from p (any alignment).
std::uint32_t four_bytes(const std::uint8_t* p) {
  std::uint32_t v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// Whether interior column k of a region w wide and its 8 neighbours are all of material top
// and none is layered (kind all kUnlayered, 0): then no pair of k's is held or crosses a
// border, and k gives as on one material. Four bytes a row, so it may also look at one
// column beyond the 3 x 3 block on each row (and answer "no" for it: the caller then takes
// the general path, which gives the same result).
bool uniform_around(const std::uint8_t* mat, const unsigned char* kind, std::size_t k, std::size_t w,
                    std::uint8_t top) {
  const std::uint32_t all_top = 0x01010101u * top;
  // Rows y-1 and y from column x-1, row y+1 from x-2: within the region for every
  // interior column (the last row's load ends at x+1).
  const std::size_t a = k - w - 1, b = k - 1, c = k + w - 2;
  const std::uint32_t mats =
      (four_bytes(mat + a) ^ all_top) | (four_bytes(mat + b) ^ all_top) | (four_bytes(mat + c) ^ all_top);
  const std::uint32_t kinds = four_bytes(kind + a) | four_bytes(kind + b) | four_bytes(kind + c);
  return (mats | kinds) == 0;
}

}  // namespace

// kMap: each giver reads its own material's limits (lims_); else every column has lim_'s.
// With a map, a giver whose 3 x 3 block is of its own material and unlayered (most of
// them) takes the one-material body with its material's limits: nothing there reads a
// neighbour's material or layering.
template <bool kMap>
bool ErodeStage::compute_shares_as(const Region& region) {
  const int w = region.w, h = region.h;
  const auto off = neighbour_offsets(w);
  const ErosionLimits one = lim_;
  region.for_rows(0, h, [&](int y) {
    std::uint64_t* giver_row = givers_.row(y);
    std::uint64_t* steep_row = steep_givers_.row(y);
    bool flow = false, cross = false;
    // Raw pointers: the byte stores below may alias anything, so indexing the vectors would
    // reload their data pointers after each.
    const double* ht = region.ht.data();
    const double* caps = cap_.data();
    const unsigned char* cover = cover_.data();
    // kMixed: the general map body (a pair may cross a border or touch a layer).
    const auto give = [&]<bool kMixed>(int x, std::size_t k, const ErosionLimits& lim) __attribute__((always_inline)) {
      [[maybe_unused]] const std::uint8_t top = kMixed ? region.mat[k] : 0;
      const double h0 = ht[k];
      double excess_sum = 0.0;
      int count = 0;
      unsigned mk = 0, steep_mk = 0;
      [[maybe_unused]] bool mixed = false;  // a pair of another material or a layered column
#pragma GCC unroll 8
      for (int d = 0; d < 8; ++d) {
        const std::size_t nk = k + off[d];  // interior: neighbours exist
        if (caps[nk] == 0.0) continue;
        const double diff = h0 - ht[nk];
        const int c = cover[nk];
        if (!(diff > lim.give[d][c])) continue;
        if constexpr (kMixed) {
          // The soil keeps its material: a neighbour that may not take it holds the pair.
          // (A rigid column's loose soil lands as the receiver's own, as before maps.)
          if (region.mat[nk] != top) {
            if (!rigid_[top] && !takes(region, nk, x + kDx[d], y + kDy[d], top)) continue;
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
      if constexpr (kMixed) {
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
        const double cap = caps[k + off[d]];
        total += std::min(share, cap);
        if constexpr (kMixed) spent = spent && cap >= share;
        // A pair whose flow the body caps (the column under it is full) stays steep: the
        // body holds that slope, erosion cannot relax it.
        steep_here = steep_here || ((steep_mk & (1u << d)) && cap >= share);
      }
      if (!(total > 0.0)) return;
      q_[k] = share;
      mask_[k] = static_cast<unsigned char>(mk);
      out_[k] = total;
      if constexpr (kMap) spent_[k] = spent;
      if constexpr (kMixed) {
        if (mixed || kind_[k] != kUnlayered) {
          cross = true;
          cross_givers_.set(x, y);
        }
      }
      giver_row[x >> 6] |= ColumnBits::bit(x);
      flow = true;
      if (steep_here) steep_row[x >> 6] |= ColumnBits::bit(x);
    };
    // Whether the giver at x may have a too-steep pair at all by lim's least limits (a filter
    // only: a column that fails it has none, one that passes may have none either).
    const auto may_give = [&](int x, const ErosionLimits& lim) __attribute__((always_inline)) {
      const std::size_t k = region.at(x, y);
      const double h0 = ht[k];
      const NeighbourExtremes lowest = neighbour_extremes(&ht[k], w, [](double a, double b) { return std::min(a, b); });
      return h0 - lowest.axis > lim.least_give[0] || h0 - lowest.diagonal > lim.least_give[1];
    };
    // The candidates' bits walked here, not by ColumnBits::for_each_in_row, so the tests are
    // inlined into this row's loop (through a call, each captured value would be read back
    // from memory after every byte store). Two walks of each word: first the filter, a loop
    // of loads only whose values stay in registers, then the givers that pass it (with a map,
    // by lim_'s least limits over the palette: one that passes but has no pair too steep by
    // its own material's limits gives nothing in give, as if it had been dismissed).
    const std::uint64_t* cand_row = cand_.row(y);
    // With a map: what the givers that pass the filter read first (raw, as ht above).
    [[maybe_unused]] const std::uint8_t* mat = region.mat.data();
    [[maybe_unused]] const unsigned char* kind = kind_.data();
    [[maybe_unused]] const ErosionLimits* lims = lims_.data();
    for (int i = 0; i < cand_.words; ++i) {
      std::uint64_t pass = 0;
      for (std::uint64_t word = cand_row[i]; word != 0; word &= word - 1)
        if (may_give(i * 64 + std::countr_zero(word), one)) pass |= word & -word;
      for (; pass != 0; pass &= pass - 1) {
        const int x = i * 64 + std::countr_zero(pass);
        const std::size_t k = region.at(x, y);
        if constexpr (kMap) {
          const std::uint8_t top = mat[k];
          const ErosionLimits& lim = lims[top];
          if (uniform_around(mat, kind, k, static_cast<std::size_t>(w), top))
            give.template operator()<false>(x, k, lim);
          else
            give.template operator()<true>(x, k, lim);
        } else {
          give.template operator()<false>(x, k, one);
        }
      }
    }
    row_flow_[static_cast<std::size_t>(y)] = flow;  // only this row's task writes it
    if constexpr (kMap) row_cross_[static_cast<std::size_t>(y)] = cross;
  });
  bool flow = false;
  for (int y = 0; y < h; ++y) flow = flow || row_flow_[static_cast<std::size_t>(y)];
  return flow;
}

}  // namespace shore::terrain
