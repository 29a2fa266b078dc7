#include "stage_contour.h"

#include <algorithm>

#include "capacity_bytes.h"
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
  for (std::size_t k = 0; k < contour_.size(); ++k) contour_[k] = open_[k] ? 0 : big;
  sweep(region);
}

// Columns out of contact that soil can reach from the open (8-connected): every column not
// under a body, then the columns under a body but out of contact (pockets; interior, so
// their neighbours exist) next to one already reached. One raster scan opens each pocket
// next to an open column at once, so the pockets after it in the scan see it open; one
// opened beside a pocket before it in the scan that is still closed starts a flood fill
// from there, which reaches what the scan has passed. The open set is the same as a flood
// fill from every pocket next to the open (it is the pockets connected to the open), with
// a flood of the few pockets the scan cannot reach, not of every pocket.
void ContourStage::find_open(const Region& region, std::span<const unsigned char> flags) {
  std::vector<unsigned char>& open = open_;
  std::vector<std::size_t>& stack = fill_stack_;
  const std::size_t size = flags.size();
  open.resize(size);
  for (std::size_t k = 0; k < size; ++k) open[k] = (flags[k] & (kCovered | kContact)) ? 0 : 1;
  const auto off = neighbour_offsets(region.w);
  auto pocket = [&](std::size_t k) { return !open[k] && (flags[k] & (kCovered | kContact)) == kCovered; };
  // The directions of the neighbours before a column in the scan: (-1, 0), (0, -1), (-1, -1), (1, -1).
  constexpr int kBefore[4] = {1, 3, 5, 6};
  stack.clear();
  for (std::size_t k = 0; k < size; ++k) {
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
// relax, and they are interior: their neighbours exist.
void ContourStage::sweep(const Region& region) {
  int* c = contour_.data();
  const std::ptrdiff_t w = region.w;
  for (int y = 1; y < region.h - 1; ++y)
    for (int x = 1; x < region.w - 1; ++x) {
      int* p = c + y * w + x;
      if (!*p) continue;
      *p = std::min({*p, p[-1] + 1, p[-w - 1] + 1, p[-w] + 1, p[-w + 1] + 1});
    }
  for (int y = region.h - 2; y >= 1; --y)
    for (int x = region.w - 2; x >= 1; --x) {
      int* p = c + y * w + x;
      if (!*p) continue;
      *p = std::min({*p, p[1] + 1, p[w + 1] + 1, p[w] + 1, p[w - 1] + 1});
    }
}

std::size_t ContourStage::bytes() const { return capacity_bytes(contour_, open_, fill_stack_); }

}  // namespace shore::terrain
