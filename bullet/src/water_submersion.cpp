#include "water_submersion.h"

#include <algorithm>
#include <cmath>

#include "bt_convert.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace water_detail {

using envelope_detail::Frame;

GridRect window_under(const water::Surface& s, const btVector3& lo, const btVector3& hi, int pad) {
  const Eigen::Vector2d a = s.grid_coordinates(lo.x(), lo.y()), b = s.grid_coordinates(hi.x(), hi.y());
  const auto clamp = [](double g, int n) { return static_cast<int>(std::clamp(g, 0.0, double(n - 1))); };
  return GridRect::spanning(clamp(std::floor(a.x()) - pad, s.nx()), clamp(std::floor(a.y()) - pad, s.ny()),
                            clamp(std::ceil(b.x()) + pad, s.nx()), clamp(std::ceil(b.y()) + pad, s.ny()));
}

WaterPlane fit_plane(const water::Surface& s, const GridRect& win, const GridRect& inner, const std::vector<double>& z,
                     const std::vector<double>& vz) {
  const int w = win.nx, h = win.ny;
  double n = 0, sx = 0, sy = 0, sz = 0, sxx = 0, syy = 0, sxy = 0, sxz = 0, syz = 0, sv = 0;
  for (int b = 0; b < h; ++b)
    for (int a = 0; a < w; ++a) {
      if (inner.contains(win.i0 + a, win.j0 + b)) continue;
      const double x = a - 0.5 * (w - 1), y = b - 0.5 * (h - 1);
      const double v = z[std::size_t(b) * std::size_t(w) + std::size_t(a)];
      n += 1;
      sx += x;
      sy += y;
      sz += v;
      sxx += x * x;
      syy += y * y;
      sxy += x * y;
      sxz += x * v;
      syz += y * v;
      sv += vz[std::size_t(b) * std::size_t(w) + std::size_t(a)];
    }
  const double cell = s.spacing(), x0 = s.node_x(win.i0) + 0.5 * (w - 1) * cell,
               y0 = s.node_y(win.j0) + 0.5 * (h - 1) * cell;
  if (n == 0) return make_plane(x0, y0, s.settings().rest_height, 0, 0, 0);
  // Normal equations of z = a + b x + c y, centred on the nodes used.
  const double mx = sx / n, my = sy / n, mz = sz / n;
  const double cxx = sxx / n - mx * mx, cyy = syy / n - my * my, cxy = sxy / n - mx * my;
  const double cxz = sxz / n - mx * mz, cyz = syz / n - my * mz;
  const double det = cxx * cyy - cxy * cxy;
  double bx = 0.0, by = 0.0;
  if (det > 1e-12 * (cxx * cyy + 1e-300)) {
    bx = (cxz * cyy - cyz * cxy) / det;
    by = (cyz * cxx - cxz * cxy) / det;
  }
  return make_plane(x0 + mx * cell, y0 + my * cell, s.settings().rest_height + mz, bx / cell, by / cell, sv / n);
}

void part_frames(const WaterShape& shape, const Frame& body, std::vector<Frame>& frames,
                 std::vector<WorldPlanes>& planes) {
  frames.resize(shape.parts.size());
  planes.resize(shape.parts.size());
  for (std::size_t p = 0; p < shape.parts.size(); ++p) {
    const Frame& l = shape.parts[p].local;
    Frame& f = frames[p];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        f.r[i][j] = body.r[i][0] * l.r[0][j] + body.r[i][1] * l.r[1][j] + body.r[i][2] * l.r[2][j];
    f.t = body.to_world(l.t);
    if (shape.parts[p].kind == Part::Kind::polyhedron) world_planes(shape.parts[p].poly, f, planes[p]);
  }
}

btTransform to_transform(const Frame& f) {
  btTransform t;
  t.setBasis(btMatrix3x3(btScalar(f.r[0][0]), btScalar(f.r[0][1]), btScalar(f.r[0][2]), btScalar(f.r[1][0]),
                         btScalar(f.r[1][1]), btScalar(f.r[1][2]), btScalar(f.r[2][0]), btScalar(f.r[2][1]),
                         btScalar(f.r[2][2])));
  t.setOrigin(to_bt(f.t));
  return t;
}

void submerge(const WaterShape& shape, const std::vector<Frame>& frames, const WaterPlane& plane, Submerged& wet) {
  wet.clear();
  for (std::size_t p = 0; p < shape.parts.size(); ++p) {
    const Part& part = shape.parts[p];
    if (part.kind == Part::Kind::polyhedron && part.axis >= 0)
      add_revolution(part.poly, frames[p], part.axis, plane, wet);
    else if (part.kind == Part::Kind::polyhedron)
      add_polyhedron(part.poly, frames[p], plane, wet);
    else if (part.kind == Part::Kind::ball)
      add_ball(frames[p].t, part.radius, plane, wet);
  }
}

void submerge_sampled(const WaterShape& shape, const std::vector<Frame>& frames, const WaterPlane& plane,
                      EnvelopeRasterizer& rasterizer, double& volume, Vec3& moment) {
  EnvelopeRaster r;
  const EnvelopeGrid& g = rasterizer.grid();
  for (std::size_t p = 0; p < shape.parts.size(); ++p) {
    if (shape.parts[p].kind != Part::Kind::sampled) continue;
    rasterizer.rasterize(*shape.parts[p].shape, to_transform(frames[p]), r);
    for (int l = 0; l < r.ny; ++l)
      for (int k = 0; k < r.nx; ++k) {
        const std::size_t q = std::size_t(l) * std::size_t(r.nx) + std::size_t(k);
        if (!r.covers(q)) continue;
        const double x = g.origin_x + double(r.i0 + k) * g.cell, y = g.origin_y + double(r.j0 + l) * g.cell;
        const double top = std::min(r.upper[q], plane.height(x, y));
        if (!(top > r.lower[q])) continue;
        const double dv = (top - r.lower[q]) * g.cell * g.cell;
        volume += dv;
        moment = moment + Vec3{x, y, 0.5 * (top + r.lower[q])} * dv;
      }
  }
}

}  // namespace water_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
