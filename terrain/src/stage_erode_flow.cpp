// Erosion flow: every giver and receiver takes what it gave off and gathers what its
// neighbours gave it. In place: a column's update reads only its own height and the shares,
// caps and masks fixed before.

#include <algorithm>
#include <bit>

#include "neighbours.h"
#include "stage_erode.h"

namespace shore::terrain {

// The columns that change: the givers and the neighbours they give to.
void ErodeStage::mark_receivers(const Region& region) {
  near_.clear();
  for (int y = 0; y < region.h; ++y)
    givers_.for_each_in_row(y, [&](int x) {
      near_.set(x, y);
      for (unsigned mk = mask_[region.at(x, y)]; mk != 0; mk &= mk - 1) {
        const int d = std::countr_zero(mk);
        near_.set(x + kDx[d], y + kDy[d]);
      }
    });
}

void ErodeStage::move_soil(Region& region) {
  const int w = region.w, h = region.h;
  const auto off = neighbour_offsets(w);
  changed_.clear();
  region.for_rows(0, h, [&](int y) {
    std::uint64_t* changed_row = changed_.row(y);
    const bool edge_row = y == 0 || y == h - 1;
    near_.for_each_in_row(y, [&](int x) {
      const std::size_t k = region.at(x, y);
      const double old = region.ht[k];
      double hk = old - out_[k];
      const double cap = cap_[k];
      if (cap > 0.0) {
        if (!edge_row && x > 0 && x < w - 1) {
#pragma GCC unroll 8
          for (int d = 0; d < 8; ++d) {
            const std::size_t nk = k + off[d];
            // neighbour nk gives toward k along the opposite direction
            if (mask_[nk] & (1u << (d ^ 1))) hk += std::min(q_[nk], cap);
          }
        } else {
#pragma GCC unroll 8
          for (int d = 0; d < 8; ++d) {
            const int nx = x + kDx[d], ny = y + kDy[d];
            if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
            const std::size_t nk = region.at(nx, ny);
            if (mask_[nk] & (1u << (d ^ 1))) hk += std::min(q_[nk], cap);
          }
        }
      }
      if (hk != old) {
        region.ht[k] = hk;
        changed_row[x >> 6] |= ColumnBits::bit(x);
      }
    });
  });
}

void ErodeStage::clear_givers(const Region& region) {
  for (int y = 0; y < region.h; ++y)
    givers_.for_each_in_row(y, [&](int x) {
      const std::size_t k = region.at(x, y);
      mask_[k] = 0;
      out_[k] = 0.0;
    });
  givers_.clear();
}

}  // namespace shore::terrain
