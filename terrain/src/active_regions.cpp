#include "active_regions.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "capacity_bytes.h"
#include "region.h"
#include "shore/core/error.h"

namespace shore::terrain {

namespace {

/// Overlapping or adjacent: their halos (a column on every side) would overlap.
bool touches(const GridRect& a, const GridRect& b) { return overlap(a.grown(1), b, /*touching=*/true); }

}  // namespace

// Columns the body overhangs by more than active_reach can neither be pressed this step nor
// catch soil that would reach the body, so they need no work.
GridRect ActiveRegions::reach_box(const TileStore& store, const TerrainSettings& s, const Imprint& im) {
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
std::vector<MarginBox> ActiveRegions::plan(std::span<const MarginBox> reached, std::span<const GridRect> carried,
                                           int margin) {
  std::vector<MarginBox> boxes;  // a carried box's margin 0 until a reach box joins it
  for (const MarginBox& r : reached)
    if (!r.box.empty()) boxes.push_back({r.box.grown(r.margin), r.margin});
  for (const GridRect& r : carried)
    if (!r.empty()) boxes.push_back({r.grown(margin), 0});
  for (bool merged = true; merged;) {
    merged = false;
    for (std::size_t a = 0; a < boxes.size() && !merged; ++a)
      for (std::size_t b = a + 1; b < boxes.size() && !merged; ++b)
        if (touches(boxes[a].box, boxes[b].box)) {
          boxes[a] = {bounding(boxes[a].box, boxes[b].box), std::max(boxes[a].margin, boxes[b].margin)};
          boxes.erase(boxes.begin() + static_cast<std::ptrdiff_t>(b));
          merged = true;
        }
  }
  std::sort(boxes.begin(), boxes.end(), [](const MarginBox& a, const MarginBox& b) {
    return std::tie(a.box.j0, a.box.i0) < std::tie(b.box.j0, b.box.i0);
  });
  for (MarginBox& a : boxes) {
    if (a.margin == 0) a.margin = margin;
    const std::int64_t w = a.box.nx, h = a.box.ny;
    // Each side on its own first: the product of two huge sides would overflow.
    if (w + 2 > kMaxRegionColumns || h + 2 > kMaxRegionColumns || (w + 2) * (h + 2) > kMaxRegionColumns)
      throw InvalidSetting("terrain.Imprint.envelope", detail::to_text(w) + " x " + detail::to_text(h) + " columns",
                           "active region must hold at most " + detail::to_text(kMaxRegionColumns) + " columns");
  }
  return boxes;
}

GridRect ActiveRegions::carry(const GridRect& box, int own, int margin) {
  if (own >= margin || box.empty()) return box.grown(own - margin);
  const int a = std::min(margin - own, (box.nx - 1) / 2), b = std::min(margin - own, (box.ny - 1) / 2);
  return {box.i0 + a, box.j0 + b, box.nx - 2 * a, box.ny - 2 * b};
}

std::size_t ActiveRegions::bytes() const { return capacity_bytes(heights_); }

}  // namespace shore::terrain
