#pragma once
// Private: sets of columns as bit rows, for the erosion stage's work lists. Built and
// combined serially, so the sets never depend on the thread count.

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "capacity_bytes.h"
#include "shore/terrain/terrain.h"

namespace shore::terrain {

/// One bit per column of a w x h region, row by row; bits past a row's end stay clear.
struct ColumnBits {
  int w = 0, h = 0, words = 0;  ///< words: 64-bit words per row
  std::vector<std::uint64_t> bits;

  void reset(int width, int height) {
    w = width, h = height, words = (width + 63) / 64;
    bits.assign(static_cast<std::size_t>(words) * static_cast<std::size_t>(height), 0);
  }
  void clear() { std::fill(bits.begin(), bits.end(), 0); }
  [[nodiscard]] std::uint64_t* row(int y) { return bits.data() + static_cast<std::size_t>(y) * words; }
  [[nodiscard]] const std::uint64_t* row(int y) const { return bits.data() + static_cast<std::size_t>(y) * words; }
  void set(int x, int y) { row(y)[x >> 6] |= bit(x); }
  /// The bit of column x within its word of a row.
  [[nodiscard]] static std::uint64_t bit(int x) { return std::uint64_t{1} << (x & 63); }
  [[nodiscard]] std::uint64_t tail_mask() const {
    return (w & 63) ? (std::uint64_t{1} << (w & 63)) - 1 : ~std::uint64_t{0};
  }
  /// this &= other (same size)
  void keep(const ColumnBits& other) {
    for (std::size_t k = 0; k < bits.size(); ++k) bits[k] &= other.bits[k];
  }
  /// this |= other (same size)
  void add(const ColumnBits& other) {
    for (std::size_t k = 0; k < bits.size(); ++k) bits[k] |= other.bits[k];
  }
  [[nodiscard]] bool any() const {
    return std::any_of(bits.begin(), bits.end(), [](std::uint64_t b) { return b != 0; });
  }
  /// Bounding box of the set columns, in this set's coordinates; nx = 0 if none.
  [[nodiscard]] GridRect bounds() const {
    int x0 = w, y0 = h, x1 = -1, y1 = -1;
    for (int y = 0; y < h; ++y)
      for_each_in_row(y, [&](int x) {
        x0 = std::min(x0, x), x1 = std::max(x1, x);
        y0 = std::min(y0, y), y1 = y;
      });
    if (x1 < 0) return {};
    return {x0, y0, x1 - x0 + 1, y1 - y0 + 1};
  }
  /// Calls fn(x) for every set column of row y, left to right.
  template <class Fn>
  void for_each_in_row(int y, Fn&& fn) const {
    const std::uint64_t* r = row(y);
    for (int i = 0; i < words; ++i)
      for (std::uint64_t word = r[i]; word != 0; word &= word - 1) fn(i * 64 + std::countr_zero(word));
  }
  [[nodiscard]] std::size_t bytes() const { return capacity_bytes(bits); }
};

/// to = from grown by one column in each of the 8 directions.
inline void dilate(const ColumnBits& from, ColumnBits& to) {
  to.reset(from.w, from.h);
  const int words = from.words;
  for (int y = 0; y < from.h; ++y) {
    const std::uint64_t* mid = from.row(y);
    const std::uint64_t* up = y > 0 ? from.row(y - 1) : nullptr;
    const std::uint64_t* down = y + 1 < from.h ? from.row(y + 1) : nullptr;
    std::uint64_t* t = to.row(y);
    for (int i = 0; i < words; ++i) t[i] = mid[i] | (up ? up[i] : 0) | (down ? down[i] : 0);
    std::uint64_t prev = 0;
    for (int i = 0; i < words; ++i) {
      const std::uint64_t cur = t[i], next = i + 1 < words ? t[i + 1] : 0;
      t[i] = cur | (cur << 1) | (prev >> 63) | (cur >> 1) | (next << 63);
      prev = cur;
    }
    t[words - 1] &= from.tail_mask();
  }
}

}  // namespace shore::terrain
