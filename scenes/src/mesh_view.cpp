#include "shore/scenes/mesh_view.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "shore/core/error.h"

namespace shore::scenes {
namespace {

using Vec = std::array<double, 3>;

Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec unit(const Vec& a) {
  const double n = std::sqrt(dot(a, a));
  return {a[0] / n, a[1] / n, a[2] / n};
}

/// The eye's frame and pinhole projection.
struct Projection {
  Vec eye, right, up, forward;
  double focal = 1.0;  // pixels per unit of x / z at the centre
  double cx = 0.0, cy = 0.0;
  static constexpr double kNear = 0.02;  // m: triangles reaching closer are skipped

  /// Screen x, y (pixels, y down) and depth of a point; depth < kNear: not drawable.
  [[nodiscard]] Vec project(const float* p) const {
    const Vec d = sub({p[0], p[1], p[2]}, eye);
    const double z = dot(d, forward);
    return {cx + focal * dot(d, right) / z, cy - focal * dot(d, up) / z, z};
  }
};

constexpr Rgb kSky{222, 230, 238};
constexpr Rgb kEdge{40, 40, 40};

/// One triangle into the colour and depth buffers (depth test on 1 / z).
void raster(Image& img, std::vector<float>& inv_depth, const std::array<Vec, 3>& s, const std::array<Vec, 3>& n,
            const Vec& light, Rgb colour, bool edges) {
  const double area = (s[1][0] - s[0][0]) * (s[2][1] - s[0][1]) - (s[1][1] - s[0][1]) * (s[2][0] - s[0][0]);
  if (!(std::abs(area) > 1e-12)) return;
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min({s[0][0], s[1][0], s[2][0]}))));
  const int x1 = std::min(img.width() - 1, static_cast<int>(std::ceil(std::max({s[0][0], s[1][0], s[2][0]}))));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min({s[0][1], s[1][1], s[2][1]}))));
  const int y1 = std::min(img.height() - 1, static_cast<int>(std::ceil(std::max({s[0][1], s[1][1], s[2][1]}))));
  std::array<double, 3> edge_len;
  for (int k = 0; k < 3; ++k) {
    const Vec& a = s[static_cast<std::size_t>((k + 1) % 3)];
    const Vec& b = s[static_cast<std::size_t>((k + 2) % 3)];
    edge_len[static_cast<std::size_t>(k)] = std::hypot(b[0] - a[0], b[1] - a[1]);
  }
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      std::array<double, 3> w;
      for (int k = 0; k < 3; ++k) {
        const Vec& a = s[static_cast<std::size_t>((k + 1) % 3)];
        const Vec& b = s[static_cast<std::size_t>((k + 2) % 3)];
        w[static_cast<std::size_t>(k)] = ((b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0])) / area;
      }
      if (w[0] < 0 || w[1] < 0 || w[2] < 0) continue;
      const float inv = static_cast<float>(w[0] / s[0][2] + w[1] / s[1][2] + w[2] / s[2][2]);
      float& zb =
          inv_depth[static_cast<std::size_t>(y) * static_cast<std::size_t>(img.width()) + static_cast<std::size_t>(x)];
      if (inv <= zb) continue;
      zb = inv;
      Vec nrm{0, 0, 0};
      for (std::size_t k = 0; k < 3; ++k)
        for (std::size_t a = 0; a < 3; ++a) nrm[a] += w[k] * n[k][a];
      const double lambert = std::max(0.0, dot(unit(nrm), light));
      Rgb c = shade(colour, 0.45 + 0.75 * lambert);
      if (edges) {
        double near_edge = std::numeric_limits<double>::infinity();  // pixels to the closest edge
        for (std::size_t k = 0; k < 3; ++k) near_edge = std::min(near_edge, w[k] * std::abs(area) / edge_len[k]);
        if (near_edge < 0.6) c = mix(c, kEdge, 0.55);
      }
      img.at(x, y) = c;
    }
}

}  // namespace

Image render_meshes(const std::vector<MeshLayer>& layers, const PerspectiveView& view) {
  view.eye.validate();
  const int h = view.eye.viewport_height;
  const int w = view.width > 0 ? view.width : (h * 16 + 8) / 9;
  const Vec eye{view.eye.x, view.eye.y, view.eye.z};
  const Vec look = sub(view.target, eye);
  const Vec side = cross(look, {0.0, 0.0, 1.0});
  if (!(dot(look, look) > 0.0) || !(dot(side, side) > 1e-12 * dot(look, look)))
    throw InvalidSetting("scenes.PerspectiveView.target", "straight above, below or at the eye",
                         "must lie off the eye's vertical");
  Projection pr;
  pr.eye = eye;
  pr.forward = unit(look);
  pr.right = unit(side);
  pr.up = cross(pr.right, pr.forward);
  pr.focal = view.eye.pixels_per_radian();
  pr.cx = 0.5 * w;
  pr.cy = 0.5 * h;
  const Vec light = unit({-0.4, 0.5, 0.8});

  Image img(w, h, kSky);
  std::vector<float> inv_depth(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0.0f);
  for (const MeshLayer& layer : layers) {
    if (!layer.mesh) continue;
    for (const auto& [key, chunk] : layer.mesh->chunks()) {
      std::vector<Vec> screen(chunk.nodes.size());
      for (std::size_t v = 0; v < chunk.nodes.size(); ++v) screen[v] = pr.project(&chunk.positions[3 * v]);
      for (std::size_t t = 0; t < chunk.triangle_count(); ++t) {
        std::array<Vec, 3> s, n;
        bool drawable = true;
        for (std::size_t k = 0; k < 3; ++k) {
          const std::uint32_t v = chunk.indices[3 * t + k];
          s[k] = screen[v];
          n[k] = {chunk.normals[3 * v], chunk.normals[3 * v + 1], chunk.normals[3 * v + 2]};
          drawable = drawable && s[k][2] > Projection::kNear;
        }
        if (drawable) raster(img, inv_depth, s, n, light, layer.colour, view.edges);
      }
    }
  }
  if (view.title.empty()) return img;
  Image out(w, h + 24, {255, 255, 255});
  out.blit(img, 0, 24);
  draw_text(out, 6, 5, view.title, {30, 30, 30}, 2);
  return out;
}

}  // namespace shore::scenes
