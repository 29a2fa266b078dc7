#include "water_scene_util.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "shore/bullet/envelope.h"
#include "shore/demo/render.h"

namespace shore::demo::water_scene {
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

bool finite(const btVector3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

/// Calls fn(i, j, raster, k) for every pixel (i, j) of a w x h grid that a finite body's
/// envelope covers; k indexes that body's raster. A body whose envelope cannot be drawn (far
/// outside the picture) is skipped: there is nothing to draw.
template <class Fn>
void for_each_covered_pixel(const std::vector<const btRigidBody*>& bodies, const bullet::EnvelopeGrid& grid,
                            const bullet::EnvelopeOptions& options, std::int64_t w, std::int64_t h, Fn&& fn) {
  EnvelopeRaster raster;
  for (const btRigidBody* b : bodies) {
    if (non_finite_state(*b) != 0) continue;
    try {
      bullet::rasterize_envelope(*b->getCollisionShape(), b->getWorldTransform(), grid, options, raster);
    } catch (const std::exception&) {
      continue;
    }
    for (int jj = 0; jj < raster.ny; ++jj)
      for (int ii = 0; ii < raster.nx; ++ii) {
        const std::int64_t i = raster.i0 + ii, j = raster.j0 + jj;
        const std::size_t k =
            static_cast<std::size_t>(jj) * static_cast<std::size_t>(raster.nx) + static_cast<std::size_t>(ii);
        if (i < 0 || j < 0 || i >= w || j >= h || !raster.covers(k)) continue;
        fn(static_cast<int>(i), static_cast<int>(j), raster, k);
      }
  }
}

/// Which pixels of a (w x h, row 0 = south) grid the bodies cover.
std::vector<std::uint8_t> body_cover(const std::vector<const btRigidBody*>& bodies, double x0, double y0, double pixel,
                                     int w, int h) {
  std::vector<std::uint8_t> cover(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0);
  bullet::EnvelopeOptions options;
  options.include_margin = false;
  for_each_covered_pixel(bodies, {x0, y0, pixel}, options, w, h, [&](int i, int j, const EnvelopeRaster&, std::size_t) {
    cover[static_cast<std::size_t>(j) * static_cast<std::size_t>(w) + static_cast<std::size_t>(i)] = 1;
  });
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

long non_finite_heights(const water::Surface& s) {
  long bad = 0;
  for (int j = 0; j < s.ny(); ++j)
    for (int i = 0; i < s.nx(); ++i)
      if (!std::isfinite(s.height(i, j))) ++bad;
  return bad;
}

long non_finite_state(const btRigidBody& b) {
  const btTransform& t = b.getWorldTransform();
  long bad = 0;
  for (const btVector3& v : {t.getOrigin(), t.getBasis()[0], t.getBasis()[1], t.getBasis()[2], b.getLinearVelocity(),
                             b.getAngularVelocity()})
    if (!finite(v)) ++bad;
  return bad;
}

void hash_body(StateHash& hash, const btRigidBody& b) {
  const btTransform& t = b.getWorldTransform();
  const btQuaternion q = t.getRotation();
  for (int a = 0; a < 3; ++a) {
    hash.add(static_cast<double>(t.getOrigin()[a]));
    hash.add(static_cast<double>(b.getLinearVelocity()[a]));
    hash.add(static_cast<double>(b.getAngularVelocity()[a]));
  }
  for (int a = 0; a < 4; ++a) hash.add(static_cast<double>(q[a]));
}

BodyEnvelopes body_envelopes(const std::vector<const btRigidBody*>& bodies, const HeightGrid& like) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  BodyEnvelopes e{HeightGrid(like.nx, like.ny, like.cell, like.x0, like.y0, nan),
                  HeightGrid(like.nx, like.ny, like.cell, like.x0, like.y0, nan)};
  bullet::EnvelopeOptions options;
  options.upper = true;
  options.include_margin = false;
  for_each_covered_pixel(bodies, {like.x0, like.y0, like.cell}, options, like.nx, like.ny,
                         [&](int i, int j, const EnvelopeRaster& raster, std::size_t k) {
                           double& top = e.top.at(i, j);
                           double& bottom = e.bottom.at(i, j);
                           top = std::isfinite(top) ? std::max(top, raster.upper[k]) : raster.upper[k];
                           bottom = std::isfinite(bottom) ? std::min(bottom, raster.lower[k]) : raster.lower[k];
                         });
  return e;
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

double level_around(const water::Surface& surface, double x, double y, double radius) {
  constexpr int kPoints = 32;
  double sum = 0.0;
  for (int k = 0; k < kPoints; ++k) {
    const double a = 2.0 * std::numbers::pi * k / kPoints;
    sum += surface.height_at(x + radius * std::cos(a), y + radius * std::sin(a));
  }
  return sum / kPoints;
}

std::string time_label(double seconds) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "t = %.2f s", seconds);
  return buf;
}

}  // namespace shore::demo::water_scene
