#include "spray_tops.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace shore::terrain {

void SoilTops::cover(std::int64_t i0, std::int64_t j0, std::int64_t i1, std::int64_t j1) {
  constexpr std::int64_t kMostBlocks = 64;
  shift_ = 3;
  while ((((i1 - i0) >> shift_) + 2 > kMostBlocks || ((j1 - j0) >> shift_) + 2 > kMostBlocks) && shift_ < 40) ++shift_;
  bx0_ = i0 >> shift_, by0_ = j0 >> shift_;  // arithmetic shifts: floor divisions
  nbx_ = (i1 >> shift_) - bx0_ + 1, nby_ = (j1 >> shift_) - by0_ + 1;
  if (nbx_ > kMostBlocks + 1 || nby_ > kMostBlocks + 1) nbx_ = nby_ = 0;  // a window beyond 2^40 columns
  block_.assign(static_cast<std::size_t>(nbx_ * nby_), std::numeric_limits<double>::quiet_NaN());
  ceiling_ = std::numeric_limits<double>::quiet_NaN();
}

double SoilTops::ceiling(std::int64_t most_columns) const {
  if (!std::isnan(ceiling_)) return ceiling_;
  ceiling_ = std::numeric_limits<double>::infinity();
  if (nbx_ == 0 || (nbx_ * nby_) << (2 * shift_) > most_columns) return ceiling_;
  double top = -std::numeric_limits<double>::infinity();
  for (std::int64_t y = 0; y < nby_; ++y)
    for (std::int64_t x = 0; x < nbx_; ++x) top = std::max(top, block_bound(x, y));
  return ceiling_ = top;
}

double SoilTops::block_bound(std::int64_t bx, std::int64_t by) const {
  double& b = block_[static_cast<std::size_t>(by * nbx_ + bx)];
  if (!std::isnan(b)) return b;
  const int side = 1 << shift_;
  const ColumnRect r{(bx0_ + bx) << shift_, (by0_ + by) << shift_, side, side};
  double top = -std::numeric_limits<double>::infinity();
  const int n = store_.n();
  if (n % side == 0) {  // the block lies in one tile: its rows straight from the tile
    const TileKey key = store_.key_of(r.i0, r.j0);
    if (const Tile* t = store_.find(key); t != nullptr) {
      const std::size_t first = store_.local(r.i0, r.j0);
      for (int y = 0; y < side; ++y) {
        const double* row = t->height.data() + first + static_cast<std::size_t>(y) * static_cast<std::size_t>(n);
        for (int x = 0; x < side; ++x) top = row[x] > top ? row[x] : top;
      }
      return b = top;
    }
  }
  heights_.resize(static_cast<std::size_t>(side) * static_cast<std::size_t>(side));
  store_.read(r, heights_, false);
  for (const double h : heights_) top = h > top ? h : top;
  return b = top;
}

double SoilTops::bound(std::int64_t i0, std::int64_t j0, std::int64_t i1, std::int64_t j1) const {
  const std::int64_t x0 = (i0 >> shift_) - bx0_, x1 = (i1 >> shift_) - bx0_;
  const std::int64_t y0 = (j0 >> shift_) - by0_, y1 = (j1 >> shift_) - by0_;
  if (x0 < 0 || y0 < 0 || x1 >= nbx_ || y1 >= nby_) return std::numeric_limits<double>::infinity();
  double top = -std::numeric_limits<double>::infinity();
  for (std::int64_t y = y0; y <= y1; ++y)
    for (std::int64_t x = x0; x <= x1; ++x) top = std::max(top, block_bound(x, y));
  return top;
}

void SoilTops::raised(std::int64_t i, std::int64_t j, double height) {
  if (!std::isnan(ceiling_)) ceiling_ = std::max(ceiling_, height);
  const std::int64_t x = (i >> shift_) - bx0_, y = (j >> shift_) - by0_;
  if (x < 0 || y < 0 || x >= nbx_ || y >= nby_) return;
  double& b = block_[static_cast<std::size_t>(y * nbx_ + x)];
  if (!std::isnan(b)) b = std::max(b, height);
}

}  // namespace shore::terrain
