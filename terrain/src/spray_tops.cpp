#include "spray_tops.h"

#include <algorithm>
#include <cmath>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include "shore/core/cpu_features.h"
#if defined(SHORE_X86_DISPATCH)
#include <immintrin.h>
#define SHORE_SPRAY_TOPS_AVX 1
#endif

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

double SoilTops::compute_ceiling(std::int64_t most_columns) const {
  ceiling_ = std::numeric_limits<double>::infinity();
  if (nbx_ == 0 || (nbx_ * nby_) << (2 * shift_) > most_columns) return ceiling_;
  double top = -std::numeric_limits<double>::infinity();
  for (std::int64_t y = 0; y < nby_; ++y)
    for (std::int64_t x = 0; x < nbx_; ++x) top = std::max(top, block_bound(x, y));
  return ceiling_ = top;
}

namespace {

#if defined(SHORE_SPRAY_TOPS_AVX)
/// highest() of a width that is a multiple of 8 with four lanes to a register (AVX): the
/// same eight running maxima, each over the same heights in the same order, reduced in the
/// same order, so the same value, in about half the instructions of the SSE2 loop (a
/// block's bound reads its 64 to 4096 heights each step).
__attribute__((target("avx"))) double highest_avx(const double* first, std::size_t stride, int width, int rows) {
  const __m256d lowest = _mm256_set1_pd(-std::numeric_limits<double>::infinity());
  __m256d m0 = lowest, m1 = lowest;
  for (int y = 0; y < rows; ++y) {
    const double* row = first + static_cast<std::size_t>(y) * stride;
    for (int x = 0; x < width; x += 8) {  // _mm256_max_pd(a, b): a > b ? a : b, as _mm_max_pd
      m0 = _mm256_max_pd(_mm256_loadu_pd(row + x), m0);
      m1 = _mm256_max_pd(_mm256_loadu_pd(row + x + 4), m1);
    }
  }
  double lane[8];
  _mm256_storeu_pd(lane, m0), _mm256_storeu_pd(lane + 4, m1);
  double top = -std::numeric_limits<double>::infinity();
  for (const double l : lane) top = l > top ? l : top;
  return top;
}
#endif

/// The highest of `rows` rows of `width` heights starting `stride` apart. Where width is a
/// multiple of 8: eight running maxima side by side (two to a vector register where SSE2
/// is there, four where the CPU has AVX), then the highest of those. The maximum is exact
/// whatever the grouping (a NaN is skipped as before); only which of two equal zeros is
/// kept may differ, and the bound is only ever compared.
double highest(const double* first, std::size_t stride, int width, int rows) {
  constexpr int kLanes = 8;
#if defined(SHORE_SPRAY_TOPS_AVX)
  if (cpu_has_avx() && width % kLanes == 0) return highest_avx(first, stride, width, rows);
#endif
  double top = -std::numeric_limits<double>::infinity();
  if (width % kLanes != 0) {  // a piece of a block over a tile whose side is not a multiple of 8
    for (int y = 0; y < rows; ++y) {
      const double* row = first + static_cast<std::size_t>(y) * stride;
      for (int x = 0; x < width; ++x) top = row[x] > top ? row[x] : top;
    }
    return top;
  }
  double lane[kLanes];
#if defined(__SSE2__)
  const __m128d lowest = _mm_set1_pd(-std::numeric_limits<double>::infinity());
  __m128d m0 = lowest, m1 = lowest, m2 = lowest, m3 = lowest;  // named: kept in registers
  for (int y = 0; y < rows; ++y) {
    const double* row = first + static_cast<std::size_t>(y) * stride;
    for (int x = 0; x < width; x += kLanes) {  // _mm_max_pd(a, b): a > b ? a : b, as below
      m0 = _mm_max_pd(_mm_loadu_pd(row + x), m0);
      m1 = _mm_max_pd(_mm_loadu_pd(row + x + 2), m1);
      m2 = _mm_max_pd(_mm_loadu_pd(row + x + 4), m2);
      m3 = _mm_max_pd(_mm_loadu_pd(row + x + 6), m3);
    }
  }
  _mm_storeu_pd(lane, m0), _mm_storeu_pd(lane + 2, m1), _mm_storeu_pd(lane + 4, m2), _mm_storeu_pd(lane + 6, m3);
#else
  for (double& l : lane) l = -std::numeric_limits<double>::infinity();
  for (int y = 0; y < rows; ++y) {
    const double* row = first + static_cast<std::size_t>(y) * stride;
    for (int x = 0; x < width; x += kLanes)
      for (int l = 0; l < kLanes; ++l) lane[l] = row[x + l] > lane[l] ? row[x + l] : lane[l];
  }
#endif
  for (const double l : lane) top = l > top ? l : top;
  return top;
}

}  // namespace

double SoilTops::compute_block(std::int64_t bx, std::int64_t by) const {
  double& b = block_[static_cast<std::size_t>(by * nbx_ + bx)];
  const int side = 1 << shift_;  // shift_ >= 3: a multiple of 8
  const GridRect r{(bx0_ + bx) << shift_, (by0_ + by) << shift_, side, side};
  const int n = store_.n();
  if (side > n) return b = bound_by_tiles(r);
  if (n % side == 0) {  // the block lies in one tile: its rows straight from the tile
    const TileKey key = index_.key_of(r.i0, r.j0);
    if (const Tile* t = store_.find(key); t != nullptr) return b = tile_bound(*t, r);
  }
  if (untiled_ != nullptr && untiled(r)) return b = untiled_bound(r);
  heights_.resize(r.size());
  store_.read(r, heights_, false);
  return b = highest(heights_.data(), static_cast<std::size_t>(side), side, side);
}

double SoilTops::bound_by_tiles(const GridRect& r) const {
  const std::int64_t n = store_.n();
  const TileKey first = index_.key_of(r.i0, r.j0), last = index_.key_of(r.i1() - 1, r.j1() - 1);
  double top = -std::numeric_limits<double>::infinity();
  for (std::int64_t ty = first.ty; ty <= last.ty; ++ty) {
    const std::int64_t j0 = std::max(r.j0, ty * n), j1 = std::min(r.j1(), (ty + 1) * n);
    for (std::int64_t tx = first.tx; tx <= last.tx; ++tx) {
      const std::int64_t i0 = std::max(r.i0, tx * n), i1 = std::min(r.i1(), (tx + 1) * n);
      const GridRect piece{i0, j0, static_cast<int>(i1 - i0), static_cast<int>(j1 - j0)};
      const Tile* t = store_.find(TileKey{tx, ty});
      const double p = t != nullptr ? tile_bound(*t, piece) : untiled_bound(piece);
      top = p > top ? p : top;
    }
  }
  return top;
}

double SoilTops::tile_bound(const Tile& t, const GridRect& r) const {
  // Small blocks are read again: their 64 heights cost about what a lookup does.
  const bool keeps = tiled_ != nullptr && r.size() >= kKeptColumns;
  if (keeps)
    if (const double* kept = tiled_->find(r, t.changed_at)) return *kept;
  const double top =
      highest(t.height.data() + index_.local(r.i0, r.j0), static_cast<std::size_t>(store_.n()), r.nx, r.ny);
  if (keeps) tiled_->keep(r, top, store_.generation());
  return top;
}

double SoilTops::untiled_bound(const GridRect& r) const {
  if (untiled_ != nullptr)
    if (const double* kept = untiled_->find(r)) return *kept;
  heights_.resize(r.size());
  store_.read(r, heights_, false);
  const double top = highest(heights_.data(), static_cast<std::size_t>(r.nx), r.nx, r.ny);
  if (untiled_ != nullptr) untiled_->keep(r, top);
  return top;
}

bool SoilTops::untiled(const GridRect& r) const {
  const TileKey first = index_.key_of(r.i0, r.j0), last = index_.key_of(r.i1() - 1, r.j1() - 1);
  for (std::int64_t ty = first.ty; ty <= last.ty; ++ty)
    for (std::int64_t tx = first.tx; tx <= last.tx; ++tx)
      if (store_.find(TileKey{tx, ty}) != nullptr) return false;
  return true;
}

}  // namespace shore::terrain
