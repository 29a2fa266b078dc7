// The water a body displaces (water_coupling.h): each substep, the change of its submerged
// length per node between the pose the displacement was last taken from and the present
// one, from sub-sample envelopes, smoothed and added to the surface.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include "water_coupling_parts.h"
#include "water_submersion.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

using envelope_detail::Frame;
using water_detail::Part;

namespace coupling_detail {

/// The node envelope's nominal solid: buoyancy needs the body's true volume.
EnvelopeOptions nominal_with_upper() {
  EnvelopeOptions o;
  o.upper = true;
  o.include_margin = false;
  return o;
}

/// The grid of sub-samples: sub-sample k at origin + (k + 1/2) h / S - h / 2.
EnvelopeGrid sub_grid(const water::Surface& s, int per_cell) {
  const double h = s.spacing(), cell = h / per_cell;
  return {s.settings().origin_x - 0.5 * h + 0.5 * cell, s.settings().origin_y - 0.5 * h + 0.5 * cell, cell};
}

}  // namespace coupling_detail

namespace {

/// One volume-conserving [1 2 1]/4 pass in x then y over a rectangular field (edges fold
/// back onto themselves).
void smooth(std::vector<double>& f, int nx, int ny, std::vector<double>& tmp) {
  tmp.assign(f.size(), 0.0);
  const auto at = [nx](int x, int y) { return std::size_t(y) * std::size_t(nx) + std::size_t(x); };
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      const double v = f[at(x, y)];
      if (v == 0.0) continue;
      tmp[at(x, y)] += 0.5 * v;
      tmp[at(x > 0 ? x - 1 : x, y)] += 0.25 * v;
      tmp[at(x + 1 < nx ? x + 1 : x, y)] += 0.25 * v;
    }
  f.assign(f.size(), 0.0);
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      const double v = tmp[at(x, y)];
      if (v == 0.0) continue;
      f[at(x, y)] += 0.5 * v;
      f[at(x, y > 0 ? y - 1 : y)] += 0.25 * v;
      f[at(x, y + 1 < ny ? y + 1 : y)] += 0.25 * v;
    }
}

/// The body's envelope along a row of sub-samples: every part's chord, merged (min of the
/// lower ends, max of the upper ones where a part covers the point).
void envelope_row(const water_detail::WaterShape& shape, const std::vector<Frame>& frames,
                  const std::vector<water_detail::WorldPlanes>& planes, double x0, double dx, int n, double y,
                  double* lower, double* upper, std::vector<double>& lo, std::vector<double>& hi) {
  lo.resize(std::size_t(n));
  hi.resize(std::size_t(n));
  for (std::size_t p = 0; p < shape.parts.size(); ++p) {
    const Part& part = shape.parts[p];
    if (part.kind == Part::Kind::sampled) continue;  // merged from their raster
    if (part.kind == Part::Kind::polyhedron) {
      water_detail::widen_by_chords(planes[p], x0, dx, n, y, lower, upper);
      continue;
    }
    const Vec3 c = frames[p].t;  // a ball: its chord at every point (lo = hi = 0 outside)
    const double ry = part.radius * part.radius - (y - c.y) * (y - c.y);
    for (int k = 0; k < n; ++k) {
      const double r2 = ry - (x0 + k * dx - c.x) * (x0 + k * dx - c.x);
      const double half = r2 > 0.0 ? std::sqrt(r2) : 0.0;
      lo[std::size_t(k)] = r2 > 0.0 ? c.z - half : 0.0;
      hi[std::size_t(k)] = r2 > 0.0 ? c.z + half : 0.0;
    }
    for (int k = 0; k < n; ++k)
      if (lo[std::size_t(k)] < hi[std::size_t(k)]) {
        lower[k] = std::min(lower[k], lo[std::size_t(k)]);
        upper[k] = std::max(upper[k], hi[std::size_t(k)]);
      }
  }
}

/// Whether two poses differ by less than `tol` (m, and tol / reach in rotation).
bool same_pose(const btTransform& a, const btTransform& b, double tol, double reach) {
  if ((a.getOrigin() - b.getOrigin()).length() > tol) return false;
  for (int r = 0; r < 3; ++r)
    if ((a.getBasis()[r] - b.getBasis()[r]).length() * reach > tol) return false;
  return true;
}

}  // namespace

void WaterCoupling::Parts::sample_envelopes(Entry& entry) {
  coupling_detail::WaterBody& b = entry.record;
  const btTransform& pose = entry.body->pose();
  btVector3 lo, hi;
  entry.body->shape()->getAabb(pose, lo, hi);
  const int per = settings.fluid.samples_per_cell;
  const EnvelopeGrid grid = coupling_detail::sub_grid(surface, per);
  const auto sub = [&](double x, double origin) { return (x - origin) / grid.cell; };
  const std::int64_t kmax = std::int64_t(surface.nx()) * per - 1, lmax = std::int64_t(surface.ny()) * per - 1;
  EnvelopeRaster& e = b.current;
  e.i0 = std::clamp<std::int64_t>(std::int64_t(std::floor(sub(lo.x(), grid.origin_x))), 0, kmax);
  e.j0 = std::clamp<std::int64_t>(std::int64_t(std::floor(sub(lo.y(), grid.origin_y))), 0, lmax);
  const std::int64_t k1 = std::clamp<std::int64_t>(std::int64_t(std::ceil(sub(hi.x(), grid.origin_x))), 0, kmax);
  const std::int64_t l1 = std::clamp<std::int64_t>(std::int64_t(std::ceil(sub(hi.y(), grid.origin_y))), 0, lmax);
  e.nx = int(k1 - e.i0 + 1);
  e.ny = int(l1 - e.j0 + 1);
  const std::size_t n = std::size_t(e.nx) * std::size_t(e.ny);
  e.lower.assign(n, EnvelopeRaster::kNoLower);
  e.upper.assign(n, EnvelopeRaster::kNoUpper);
  coupling_detail::WaterWorkspace& w = work;
  water_detail::part_frames(b.shape, envelope_detail::frame_of(pose), w.frames, w.planes);
  for (int l = 0; l < e.ny; ++l) {
    const std::size_t row = std::size_t(l) * std::size_t(e.nx);
    envelope_row(b.shape, w.frames, w.planes, grid.origin_x + double(e.i0) * grid.cell, grid.cell, e.nx,
                 grid.origin_y + double(e.j0 + l) * grid.cell, e.lower.data() + row, e.upper.data() + row, w.lo, w.hi);
  }
  if (!b.rasterizer) return;
  EnvelopeRaster r;  // sampled parts: their raster on the same grid, merged
  r.resize(e.i0, e.j0, e.nx, e.ny, true);
  for (std::size_t p = 0; p < b.shape.parts.size(); ++p)
    if (b.shape.parts[p].kind == Part::Kind::sampled)
      b.rasterizer->accumulate(*b.shape.parts[p].shape, water_detail::to_transform(w.frames[p]), r);
  for (std::size_t k = 0; k < n; ++k) {
    e.lower[k] = std::min(e.lower[k], r.lower[k]);
    e.upper[k] = std::max(e.upper[k], r.upper[k]);
  }
}

void WaterCoupling::Parts::displace(Entry& entry) {
  coupling_detail::WaterBody& b = entry.record;
  const btTransform& pose = entry.body->pose();
  btVector3 lo, hi;
  entry.body->shape()->getAabb(pose, lo, hi);
  // At rest (within a thousandth of a cell of the pose the displacement was last taken
  // from) nothing is swept: the motion is taken, whole, once it exceeds that.
  if (b.have_reference && same_pose(pose, b.reference_pose, 1e-3 * surface.spacing(), 0.5 * double((hi - lo).length())))
    return;
  sample_envelopes(entry);
  if (b.have_reference) {
    // Nodes of both envelopes, padded for the smoothing.
    const int per = settings.fluid.samples_per_cell, pad = settings.smoothing_passes + 1;
    const EnvelopeRaster& e = b.current;
    const auto node0 = [per](std::int64_t k) { return int(k / per); };
    const GridRect win =
        GridRect::spanning(std::max(0, std::min(node0(e.i0), node0(b.reference.i0)) - pad),
                           std::max(0, std::min(node0(e.j0), node0(b.reference.j0)) - pad),
                           std::min(surface.nx() - 1, std::max(node0(e.i1() - 1), node0(b.reference.i1() - 1)) + pad),
                           std::min(surface.ny() - 1, std::max(node0(e.j1() - 1), node0(b.reference.j1() - 1)) + pad));
    coupling_detail::WaterWorkspace& w = work;
    surface.heights_above_rest(win.i0, win.j0, win.nx, win.ny, w.heights);
    w.ds.assign(w.heights.size(), 0.0);
    const double rest = surface.settings().rest_height, share = 1.0 / (double(per) * per);
    const auto accumulate = [&](const EnvelopeRaster& s, double sign) {
      for (int l = 0; l < s.ny; ++l) {
        const int j = node0(s.j0 + l) - win.j0;
        const double* lower = s.lower.data() + std::size_t(l) * std::size_t(s.nx);
        const double* upper = s.upper.data() + std::size_t(l) * std::size_t(s.nx);
        double* out = w.ds.data() + std::size_t(j) * std::size_t(win.nx);
        const double* water = w.heights.data() + std::size_t(j) * std::size_t(win.nx);
        for (int k = 0; k < s.nx; ++k) {
          if (!(lower[k] < EnvelopeRaster::kNoLower)) continue;
          const int i = node0(s.i0 + k) - win.i0;
          out[i] += sign * share * std::clamp(rest + water[i] - lower[k], 0.0, upper[k] - lower[k]);
        }
      }
    };
    accumulate(e, 1.0);
    accumulate(b.reference, -1.0);
    for (int p = 0; p < settings.smoothing_passes; ++p) smooth(w.ds, win.nx, win.ny, w.smooth);
    for (double& d : w.ds) d *= settings.displacement_gain;
    stats.displaced_volume += surface.add_heights(win.i0, win.j0, win.nx, win.ny, w.ds);
  }
  std::swap(b.reference, b.current);
  b.reference_pose = pose;
  b.have_reference = true;
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
