#include "active_regions.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "capacity_bytes.h"
#include "region.h"
#include "shore/core/error.h"

namespace shore::terrain {

namespace {

struct Box {
  std::int64_t i0, j0, i1, j1;        // inclusive
  bool touches(const Box& o) const {  // overlapping or adjacent (their halos would overlap)
    return i0 <= o.i1 + 2 && o.i0 <= i1 + 2 && j0 <= o.j1 + 2 && o.j0 <= j1 + 2;
  }
};

}  // namespace

// Columns the body overhangs by more than active_reach can neither be pressed this step nor
// catch soil that would reach the body, so they need no work.
ColumnRect ActiveRegions::reach_box(const TileStore& store, const TerrainSettings& s, const Imprint& im) {
  const EnvelopeRaster& env = *im.envelope;
  const bool all = std::isinf(s.active_reach);
  if (!all) {
    heights_.resize(env.lower.size());
    store.read({env.i0, env.j0, env.nx, env.ny}, heights_, false);
  }
  int x0 = env.nx, y0 = env.ny, x1 = -1, y1 = -1;
  for (int y = 0; y < env.ny; ++y)
    for (int x = 0; x < env.nx; ++x) {
      const std::size_t k =
          static_cast<std::size_t>(y) * static_cast<std::size_t>(env.nx) + static_cast<std::size_t>(x);
      const double lower = env.lower[k];
      if (lower == kInf || (!all && lower - im.offset > heights_[k] + s.active_reach)) continue;
      x0 = std::min(x0, x), x1 = std::max(x1, x);
      y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  if (x1 < 0) return {};
  return {env.i0 + x0, env.j0 + y0, x1 - x0 + 1, y1 - y0 + 1};
}

// Sorted, so the processing order never depends on the order of the imprints.
std::vector<ColumnRect> ActiveRegions::plan(std::span<const ColumnRect> reached, std::span<const ColumnRect> carried,
                                            int margin) {
  std::vector<Box> boxes;
  const std::int64_t m = margin;
  auto add = [&](const ColumnRect& r) {
    if (r.nx > 0 && r.ny > 0) boxes.push_back({r.i0 - m, r.j0 - m, r.i0 + r.nx - 1 + m, r.j0 + r.ny - 1 + m});
  };
  for (const ColumnRect& r : reached) add(r);
  for (const ColumnRect& r : carried) add(r);
  for (bool merged = true; merged;) {
    merged = false;
    for (std::size_t a = 0; a < boxes.size() && !merged; ++a)
      for (std::size_t b = a + 1; b < boxes.size() && !merged; ++b)
        if (boxes[a].touches(boxes[b])) {
          boxes[a] = {std::min(boxes[a].i0, boxes[b].i0), std::min(boxes[a].j0, boxes[b].j0),
                      std::max(boxes[a].i1, boxes[b].i1), std::max(boxes[a].j1, boxes[b].j1)};
          boxes.erase(boxes.begin() + static_cast<std::ptrdiff_t>(b));
          merged = true;
        }
  }
  std::sort(boxes.begin(), boxes.end(),
            [](const Box& a, const Box& b) { return std::tie(a.j0, a.i0) < std::tie(b.j0, b.i0); });
  std::vector<ColumnRect> regions;
  for (const Box& b : boxes) {
    const std::int64_t w = b.i1 - b.i0 + 1, h = b.j1 - b.j0 + 1;
    // Each side on its own first: the product of two huge sides would overflow.
    if (w + 2 > kMaxRegionColumns || h + 2 > kMaxRegionColumns || (w + 2) * (h + 2) > kMaxRegionColumns)
      throw InvalidSetting("terrain.Imprint.envelope", detail::to_text(w) + " x " + detail::to_text(h) + " columns",
                           "active region must hold at most " + detail::to_text(kMaxRegionColumns) + " columns");
    regions.push_back({b.i0, b.j0, static_cast<int>(w), static_cast<int>(h)});
  }
  return regions;
}

std::size_t ActiveRegions::bytes() const { return capacity_bytes(heights_); }

}  // namespace shore::terrain
