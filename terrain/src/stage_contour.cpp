#include "stage_contour.h"

#include <algorithm>
#include <cstdint>
#include <cstring>

#include "capacity_bytes.h"
#include "flag_lanes.h"
#include "neighbours.h"
#include "stage_imprint.h"

namespace shore::terrain {

// Displaced soil must come out from under the body: a pocket of columns under the body
// that no column in the open can reach through columns out of contact (a gap in the
// contact patch) counts as contact here, so it is passed over, not filled. Otherwise such
// a one-column gap collects the displaced soil of the whole patch around it, rises tens of
// centimetres into the body in one step and is pressed back down the next, its recorded
// sinkage growing by as much each time.
void ContourStage::run(const Region& region, std::span<const unsigned char> flags) {
  find_open(region, flags);
  const int big = region.w + region.h;
  contour_.resize(open_.size());
  // The rows and columns holding a closed column bound what the sweeps change: an open
  // column stays 0 and is only read.
  const auto w = static_cast<std::size_t>(region.w);
  int x0 = region.w, x1 = -1, y0 = region.h, y1 = -1;
  for (int y = 0; y < region.h; ++y) {
    const unsigned char* open = open_.data() + static_cast<std::size_t>(y) * w;
    int* level = contour_.data() + static_cast<std::size_t>(y) * w;
    int first = region.w, last = -1;
    int x = 0;
    if constexpr (flag_lanes::kFlagLanes) {  // eight open columns at once: levels 0, no bound moved
      for (; x + 8 <= region.w; x += 8) {
        if (flag_lanes::eight(open + x) == flag_lanes::kLowBits) {
          std::fill(level + x, level + x + 8, 0);
          continue;
        }
        for (int a = x; a < x + 8; ++a) {
          level[a] = open[a] ? 0 : big;
          if (!open[a]) first = std::min(first, a), last = a;
        }
      }
    }
    for (; x < region.w; ++x) {
      level[x] = open[x] ? 0 : big;
      if (!open[x]) first = std::min(first, x), last = x;
    }
    if (last >= 0) x0 = std::min(x0, first), x1 = std::max(x1, last), y0 = std::min(y0, y), y1 = y;
  }
  closed_ = x1 < 0 ? GridRect{} : GridRect{x0, y0, x1 - x0 + 1, y1 - y0 + 1};
  sweep(region, closed_);
}

// Columns out of contact that soil can reach from the open (8-connected): every column not
// under a body, then the columns under a body but out of contact (pockets; interior, so
// their neighbours exist) next to one already reached. One raster scan opens each pocket
// next to an open column at once, so the pockets after it in the scan see it open; one
// opened beside a pocket before it in the scan that is still closed starts a flood fill
// from there, which reaches what the scan has passed. The open set is the same as a flood
// fill from every pocket next to the open (it is the pockets connected to the open), with
// a flood of the few pockets the scan cannot reach, not of every pocket.
// Eight columns at a time where they can (flag_lanes.h): the open bytes stored eight at
// once, and the scan passing over eight columns none of whose flags are a pocket's (then
// none is a pocket, open or not).
void ContourStage::find_open(const Region& region, std::span<const unsigned char> flags) {
  namespace lanes = flag_lanes;
  std::vector<unsigned char>& open = open_;
  std::vector<std::size_t>& stack = fill_stack_;
  const std::size_t size = flags.size();
  open.resize(size);
  const unsigned char* f = flags.data();
  std::size_t first_left = 0;  // the columns before it stored eight at a time
  if constexpr (lanes::kFlagLanes)
    for (; first_left + 8 <= size; first_left += 8) {
      const std::uint64_t eight = lanes::uncovered(lanes::eight(f + first_left));
      std::memcpy(open.data() + first_left, &eight, sizeof eight);
    }
  for (std::size_t k = first_left; k < size; ++k) open[k] = (f[k] & (kCovered | kContact)) ? 0 : 1;
  const auto off = neighbour_offsets(region.w);
  auto pocket = [&](std::size_t k) { return !open[k] && (flags[k] & (kCovered | kContact)) == kCovered; };
  // The directions of the neighbours before a column in the scan: (-1, 0), (0, -1), (-1, -1), (1, -1).
  constexpr int kBefore[4] = {1, 3, 5, 6};
  stack.clear();
  for (std::size_t k = 0; k < size; ++k) {
    if constexpr (lanes::kFlagLanes)
      if (k % 8 == 0 && k + 8 <= size && lanes::covered_only(lanes::eight(f + k)) == 0) {
        k += 7;  // none of the eight is a pocket
        continue;
      }
    if (!pocket(k)) continue;
    bool reached = false;
    for (int d = 0; d < 8 && !reached; ++d) reached = open[k + off[d]] != 0;
    if (!reached) continue;
    open[k] = 1;
    for (const int d : kBefore)
      if (pocket(k + off[d])) {
        stack.push_back(k);
        break;
      }
  }
  while (!stack.empty()) {
    const std::size_t k = stack.back();
    stack.pop_back();
    for (int d = 0; d < 8; ++d) {
      const std::size_t nk = k + off[d];
      if (!pocket(nk)) continue;
      open[nk] = 1;
      stack.push_back(nk);
    }
  }
}

// Two raster sweeps give the exact chessboard distance. Only contact columns and pockets
// relax, and they are interior: their neighbours exist. Outside `closed` every column is
// open (0, skipped), so the sweeps visit it alone, in the same order.
void ContourStage::sweep(const Region& region, const GridRect& closed) {
  if (closed.empty()) return;
  int* c = contour_.data();
  const std::ptrdiff_t w = region.w;
  const int xa = std::max(1, static_cast<int>(closed.i0)), xb = std::min(region.w - 1, static_cast<int>(closed.i1()));
  const int ya = std::max(1, static_cast<int>(closed.j0)), yb = std::min(region.h - 1, static_cast<int>(closed.j1()));
  for (int y = ya; y < yb; ++y)
    for (int x = xa; x < xb; ++x) {
      int* p = c + y * w + x;
      if (!*p) continue;
      *p = std::min({*p, p[-1] + 1, p[-w - 1] + 1, p[-w] + 1, p[-w + 1] + 1});
    }
  for (int y = yb - 1; y >= ya; --y)
    for (int x = xb - 1; x >= xa; --x) {
      int* p = c + y * w + x;
      if (!*p) continue;
      *p = std::min({*p, p[1] + 1, p[w + 1] + 1, p[w] + 1, p[w - 1] + 1});
    }
}

std::size_t ContourStage::bytes() const { return capacity_bytes(contour_, open_, fill_stack_); }

}  // namespace shore::terrain
