#include "shore/scenes/water_view.h"

#include <algorithm>
#include <cmath>

#include "shore/scenes/envelopes.h"
#include "shore/scenes/render.h"

namespace shore::scenes {
namespace {

constexpr Rgb kInk{30, 30, 30};
constexpr Rgb kSand{222, 204, 158};
constexpr Rgb kBody{150, 158, 176};
constexpr int kTitleHeight = 24;  // render_water's title strip (when a title is given)

/// Pixels per water cell render_water uses for this grid and min_pixels (its documented
/// upsampling: the longer side reaches min_pixels, 1..64 pixels per cell).
int pixels_per_cell(int nx, int ny, int min_pixels) {
  const int longest = std::max(std::max(nx, ny) - 1, 1);
  return std::clamp((min_pixels + longest - 1) / longest, 1, 64);
}

/// Which pixels of a (w x h, row 0 = south) grid the bodies cover.
std::vector<std::uint8_t> body_cover(const std::vector<const btRigidBody*>& bodies, double x0, double y0, double pixel,
                                     int w, int h) {
  const BodyEnvelopes e = body_envelopes(bodies, HeightGrid(w, h, pixel, x0, y0));
  std::vector<std::uint8_t> cover(e.bottom.z.size(), 0);
  for (std::size_t k = 0; k < cover.size(); ++k) cover[k] = std::isfinite(e.bottom.z[k]) ? 1 : 0;
  return cover;
}

/// Paints covered pixels with `fill` (mixed with what is there by `opacity`) and outlines them.
void paint(Image& image, int top, int w, int h, const std::vector<std::uint8_t>& cover, Rgb fill, double opacity) {
  auto in = [&](int i, int j) {
    return i >= 0 && j >= 0 && i < w && j < h &&
           cover[static_cast<std::size_t>(j) * static_cast<std::size_t>(w) + static_cast<std::size_t>(i)] != 0;
  };
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      if (!in(i, j)) continue;
      const int row = top + h - 1 - j;
      const bool edge = !in(i - 1, j) || !in(i + 1, j) || !in(i, j - 1) || !in(i, j + 1);
      image.put(i, row, edge ? kInk : mix(image.at(i, row), fill, opacity));
    }
}

}  // namespace

HeightGrid surface_grid(const water::Surface& s) {
  HeightGrid g(s.nx(), s.ny(), s.spacing(), s.node_x(0), s.node_y(0));
  for (int j = 0; j < s.ny(); ++j)
    for (int i = 0; i < s.nx(); ++i) g.at(i, j) = s.height(i, j);
  return g;
}

double max_deviation(const water::Surface& s) {
  const double rest = s.settings().rest_height;
  double m = 0.0;
  for (int j = 0; j < s.ny(); ++j)
    for (int i = 0; i < s.nx(); ++i)
      if (!s.is_fixed(i, j)) m = std::max(m, std::abs(s.height(i, j) - rest));
  return m;
}

Image render_water_scene(const water::Surface& surface, const WaterOverlay& overlay, double scale,
                         const std::string& title, int min_pixels) {
  const HeightGrid g = surface_grid(surface);
  if (!(scale > 0.0)) scale = max_deviation(surface);
  Image image = render_water(g, surface.settings().rest_height, scale, title, min_pixels);
  const int f = pixels_per_cell(g.nx, g.ny, min_pixels);
  const int w = (g.nx - 1) * f + 1, h = (g.ny - 1) * f + 1;
  const double pixel = g.cell / f;
  const int top = title.empty() ? 0 : kTitleHeight;
  if (overlay.land) {
    std::vector<std::uint8_t> land(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0);
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i)
        land[static_cast<std::size_t>(j) * static_cast<std::size_t>(w) + static_cast<std::size_t>(i)] =
            overlay.land(g.x0 + i * pixel, g.y0 + j * pixel) ? 1 : 0;
    paint(image, top, w, h, land, kSand, 0.85);
  }
  if (!overlay.bodies.empty()) paint(image, top, w, h, body_cover(overlay.bodies, g.x0, g.y0, pixel, w, h), kBody, 0.8);
  return image;
}

}  // namespace shore::scenes
