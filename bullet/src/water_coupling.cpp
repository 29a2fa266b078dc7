#include "shore/bullet/water_coupling.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "checkpoint_bytes.h"
#include "coupling_directory.h"
#include "coupling_util.h"
#include "envelope_internal.h"
#include "shore/bullet/envelope.h"
#include "shore/core/error.h"
#include "shore/terrain/terrain.h"
#include "water_forces.h"
#include "water_shape.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

using coupling_detail::Clock;
using coupling_detail::seconds_since;
using envelope_detail::Frame;
using envelope_detail::Vec3;
using water_detail::Part;

/// The body's sub-sample envelopes are EnvelopeRasters on the sub-sample grid (sub_grid):
/// sub-sample k (x) of node i = k / S sits at x_i + ((k mod S + 1/2) / S - 1/2) h, likewise
/// l (y). Columns the body does not cover hold lower = +inf.

struct WaterCoupling::Workspace {
  std::vector<Frame> frames;
  std::vector<water_detail::WorldPlanes> planes;
  std::vector<double> heights, velocities, ds, smooth, lo, hi;
};

struct WaterCoupling::Body {
  btRigidBody* body = nullptr;
  bool disturb = true;
  bool seen_in_world = false;  // the world held the body once (lost when it no longer does)
  water_detail::WaterShape shape;
  EnvelopeRaster reference;  // envelopes at the pose the displacement was last taken from
  EnvelopeRaster current;
  btTransform reference_pose;
  bool have_reference = false;
  BodyWater last;
  std::unique_ptr<EnvelopeRasterizer> rasterizer;  // sampled parts only
  water_detail::Submerged wet;
  water_detail::WorldPlanes planes;
};

namespace {

/// The node envelope's nominal solid: buoyancy needs the body's true volume.
EnvelopeOptions nominal_with_upper() {
  EnvelopeOptions o;
  o.upper = true;
  o.include_margin = false;
  return o;
}

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

/// The nodes under the world box, padded by `pad` nodes, clamped to the grid.
GridRect window_under(const water::Surface& s, const btVector3& lo, const btVector3& hi, int pad) {
  const Eigen::Vector2d a = s.grid_coordinates(lo.x(), lo.y()), b = s.grid_coordinates(hi.x(), hi.y());
  const auto clamp = [](double g, int n) { return static_cast<int>(std::clamp(g, 0.0, double(n - 1))); };
  return GridRect::spanning(clamp(std::floor(a.x()) - pad, s.nx()), clamp(std::floor(a.y()) - pad, s.ny()),
                            clamp(std::ceil(b.x()) + pad, s.nx()), clamp(std::ceil(b.y()) + pad, s.ny()));
}

/// The least-squares plane through the heights of the window's nodes outside `inner`
/// (the nodes under the body's bounding box): the level the body sits in, free of the
/// surface under the body itself, which its own displacement raises. Also the mean
/// vertical velocity there.
water_detail::WaterPlane fit_plane(const water::Surface& s, const GridRect& win, const GridRect& inner,
                                   const std::vector<double>& z, const std::vector<double>& vz) {
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
  if (n == 0) return water_detail::make_plane(x0, y0, s.settings().rest_height, 0, 0, 0);
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
  return water_detail::make_plane(x0 + mx * cell, y0 + my * cell, s.settings().rest_height + mz, bx / cell, by / cell,
                                  sv / n);
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
    std::fill(lo.begin(), lo.end(), -std::numeric_limits<double>::infinity());
    std::fill(hi.begin(), hi.end(), std::numeric_limits<double>::infinity());
    if (part.kind == Part::Kind::polyhedron) {
      water_detail::chord_row(planes[p], x0, dx, n, y, lo.data(), hi.data());
    } else {
      const Vec3 c = frames[p].t;
      const double ry = part.radius * part.radius - (y - c.y) * (y - c.y);
      for (int k = 0; k < n; ++k) {
        const double r2 = ry - (x0 + k * dx - c.x) * (x0 + k * dx - c.x);
        const double half = r2 > 0.0 ? std::sqrt(r2) : 0.0;
        lo[std::size_t(k)] = r2 > 0.0 ? c.z - half : 0.0;
        hi[std::size_t(k)] = r2 > 0.0 ? c.z + half : 0.0;
      }
    }
    for (int k = 0; k < n; ++k)
      if (lo[std::size_t(k)] < hi[std::size_t(k)]) {
        lower[k] = std::min(lower[k], lo[std::size_t(k)]);
        upper[k] = std::max(upper[k], hi[std::size_t(k)]);
      }
  }
}

}  // namespace

void WaterCouplingSettings::validate() const {
  fluid.validate();
  const Check c{"bullet.WaterCouplingSettings"};
  c.in_closed("displacement_gain", displacement_gain, 0.0, 1.0);
  if (smoothing_passes < 0 || smoothing_passes > 8)
    throw InvalidSetting(c.name("smoothing_passes"), detail::to_text(smoothing_passes), "must be in [0, 8]");
  c.positive("max_speed", max_speed);
}

WaterCoupling::WaterCoupling(btDiscreteDynamicsWorld& world, water::Surface& surface, WaterCouplingSettings settings)
    : world_(world), surface_(surface), settings_(std::move(settings)), work_(std::make_unique<Workspace>()) {
  settings_.fluid.density = surface.density();
  settings_.validate();
  world_.addAction(this);
  coupling_detail::WorldDirectory<WaterCoupling>::enter(&world_, this);
}

WaterCoupling::~WaterCoupling() {
  coupling_detail::WorldDirectory<WaterCoupling>::leave(this);
  world_.removeAction(this);
}

namespace {
/// The rectangle a surface covers: node (i, j) stands for the cell of side h around it.
Region area_of(const water::Surface& s) {
  const double h = s.spacing();
  return {s.node_x(0) - 0.5 * h, s.node_y(0) - 0.5 * h, s.node_x(s.nx() - 1) + 0.5 * h, s.node_y(s.ny() - 1) + 0.5 * h};
}
}  // namespace

bool WaterCoupling::holds(const btRigidBody* body) const {
  return std::any_of(bodies_.begin(), bodies_.end(),
                     [body](const std::unique_ptr<Body>& b) { return b->body == body; });
}

void WaterCoupling::refuse_overlapping_coupling(const btRigidBody& body) const {
  coupling_detail::WorldDirectory<WaterCoupling>::for_each_other(&world_, this, [&](const WaterCoupling& other) {
    const Region mine = area_of(surface_), theirs = area_of(other.surface_);
    if (!other.holds(&body) || !theirs.overlaps(mine)) return;
    throw InvalidSetting("bullet.WaterCoupling.add_body(body)",
                         coupling_detail::body_text(body) + ", already in another WaterCoupling of this world whose " +
                             "water " + coupling_detail::region_text(theirs) + " overlaps this one's " +
                             coupling_detail::region_text(mine),
                         "a body may be in several water couplings only if their surfaces do not overlap (else "
                         "both would float it): remove_body it from the other first");
  });
}

namespace {
/// The grid of sub-samples: sub-sample k at origin + (k + 1/2) h / S - h / 2.
EnvelopeGrid sub_grid(const water::Surface& s, int per_cell) {
  const double h = s.spacing(), cell = h / per_cell;
  return {s.settings().origin_x - 0.5 * h + 0.5 * cell, s.settings().origin_y - 0.5 * h + 0.5 * cell, cell};
}

void check_pose(const btRigidBody& body) {
  const btTransform& t = body.getWorldTransform();
  const Frame f = envelope_detail::frame_of(t);
  const auto bad = [](double v) { return !std::isfinite(v); };
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (bad(f.r[r][c]))
        throw InvalidSetting("bullet.WaterCoupling.add_body pose", "rotation " + detail::to_text(f.r[r][c]),
                             "must be finite");
  if (bad(f.t.x) || bad(f.t.y) || bad(f.t.z))
    throw InvalidSetting(
        "bullet.WaterCoupling.add_body pose",
        "position (" + detail::to_text(f.t.x) + ", " + detail::to_text(f.t.y) + ", " + detail::to_text(f.t.z) + ")",
        "must be finite");
  if (!(envelope_detail::basis_deviation(f) <= kMaxBasisDeviation))
    throw InvalidSetting("bullet.WaterCoupling.add_body pose", detail::to_text(envelope_detail::basis_deviation(f)),
                         "the basis must be a rotation (deviation <= " + detail::to_text(kMaxBasisDeviation) + ")");
  if (!coupling_detail::finite(body.getLinearVelocity()) || !coupling_detail::finite(body.getAngularVelocity()))
    throw InvalidSetting("bullet.WaterCoupling.add_body velocity", "not finite", "must be finite");
}
}  // namespace

void WaterCoupling::add_body(btRigidBody* body, bool disturb) {
  if (body == nullptr) throw InvalidSetting("bullet.WaterCoupling.add_body(body)", "null", "must be a rigid body");
  if (body->getCollisionShape() == nullptr)
    throw InvalidSetting("bullet.WaterCoupling.add_body shape", "null", "the body must have a collision shape");
  check_pose(*body);
  refuse_overlapping_coupling(*body);
  auto b = std::make_unique<Body>();
  b->body = body;
  b->disturb = disturb;
  b->seen_in_world = body->getBroadphaseHandle() != nullptr;
  b->shape = water_detail::prepare_shape(*body->getCollisionShape());
  if (b->shape.sampled) {
    const EnvelopeGrid grid = sub_grid(surface_, settings_.fluid.samples_per_cell);
    (void)check_rasterizable(*body->getCollisionShape(), grid.cell, nominal_with_upper());
    b->rasterizer = std::make_unique<EnvelopeRasterizer>(grid, nominal_with_upper());
  }
  remove_body(body);
  bodies_.push_back(std::move(b));
  Body& added = *bodies_.back();
  if (added.disturb) displace(added);  // tracking starts at this pose
}

void WaterCoupling::remove_body(btRigidBody* body) {
  std::erase_if(bodies_, [body](const std::unique_ptr<Body>& b) { return b->body == body; });
}

std::vector<btRigidBody*> WaterCoupling::bodies() const { return coupling_detail::body_pointers(bodies_); }

double WaterCoupling::submerged_volume(const btRigidBody* body) const {
  for (const auto& b : bodies_)
    if (b->body == body) return b->last.submerged_volume;
  return 0.0;
}

BodyWater WaterCoupling::water_force(const btRigidBody* body) const {
  for (const auto& b : bodies_)
    if (b->body == body) return b->last;
  return {};
}

int WaterCoupling::fix_shoreline(const terrain::Terrain& ground) {
  const double level = surface_.settings().rest_height;
  int fixed = 0;
  for (int j = 0; j < surface_.ny(); ++j)
    for (int i = 0; i < surface_.nx(); ++i) {
      const double x = surface_.node_x(i), y = surface_.node_y(j);
      if (ground.height(ground.column_i(x), ground.column_j(y)) > level) {
        surface_.set_fixed(i, j, true);
        ++fixed;
      }
    }
  return fixed;
}

namespace {

/// Frames of the parts at the body's pose, and the polyhedra's world face planes.
void part_frames(const water_detail::WaterShape& shape, const Frame& body, std::vector<Frame>& frames,
                 std::vector<water_detail::WorldPlanes>& planes) {
  frames.resize(shape.parts.size());
  planes.resize(shape.parts.size());
  for (std::size_t p = 0; p < shape.parts.size(); ++p) {
    const Frame& l = shape.parts[p].local;
    Frame& f = frames[p];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        f.r[i][j] = body.r[i][0] * l.r[0][j] + body.r[i][1] * l.r[1][j] + body.r[i][2] * l.r[2][j];
    f.t = body.to_world(l.t);
    if (shape.parts[p].kind == Part::Kind::polyhedron) water_detail::world_planes(shape.parts[p].poly, f, planes[p]);
  }
}

/// A part's frame as a Bullet transform (for the rasterizer).
btTransform to_transform(const Frame& f) {
  btTransform t;
  t.setBasis(btMatrix3x3(btScalar(f.r[0][0]), btScalar(f.r[0][1]), btScalar(f.r[0][2]), btScalar(f.r[1][0]),
                         btScalar(f.r[1][1]), btScalar(f.r[1][2]), btScalar(f.r[2][0]), btScalar(f.r[2][1]),
                         btScalar(f.r[2][2])));
  t.setOrigin(to_bt(f.t));
  return t;
}

/// The analytic parts below the plane.
void submerge(const water_detail::WaterShape& shape, const std::vector<Frame>& frames,
              const water_detail::WaterPlane& plane, water_detail::Submerged& wet) {
  wet.clear();
  for (std::size_t p = 0; p < shape.parts.size(); ++p) {
    const Part& part = shape.parts[p];
    if (part.kind == Part::Kind::polyhedron && part.axis >= 0)
      water_detail::add_revolution(part.poly, frames[p], part.axis, plane, wet);
    else if (part.kind == Part::Kind::polyhedron)
      water_detail::add_polyhedron(part.poly, frames[p], plane, wet);
    else if (part.kind == Part::Kind::ball)
      water_detail::add_ball(frames[p].t, part.radius, plane, wet);
  }
}

/// Meshes: the wet length of every sub-sample column under the plane, into volume and
/// first moment.
void submerge_sampled(const water_detail::WaterShape& shape, const std::vector<Frame>& frames,
                      const water_detail::WaterPlane& plane, EnvelopeRasterizer& rasterizer, double& volume,
                      Vec3& moment) {
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

/// Whether two poses differ by less than `tol` (m, and tol / reach in rotation).
bool same_pose(const btTransform& a, const btTransform& b, double tol, double reach) {
  if ((a.getOrigin() - b.getOrigin()).length() > tol) return false;
  for (int r = 0; r < 3; ++r)
    if ((a.getBasis()[r] - b.getBasis()[r]).length() * reach > tol) return false;
  return true;
}

}  // namespace

void WaterCoupling::sample_envelopes(Body& b) {
  const btTransform& pose = b.body->getWorldTransform();
  btVector3 lo, hi;
  b.body->getCollisionShape()->getAabb(pose, lo, hi);
  const int per = settings_.fluid.samples_per_cell;
  const EnvelopeGrid grid = sub_grid(surface_, per);
  const auto sub = [&](double x, double origin) { return (x - origin) / grid.cell; };
  const std::int64_t kmax = std::int64_t(surface_.nx()) * per - 1, lmax = std::int64_t(surface_.ny()) * per - 1;
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
  Workspace& w = *work_;
  part_frames(b.shape, envelope_detail::frame_of(pose), w.frames, w.planes);
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
      b.rasterizer->accumulate(*b.shape.parts[p].shape, to_transform(w.frames[p]), r);
  for (std::size_t k = 0; k < n; ++k) {
    e.lower[k] = std::min(e.lower[k], r.lower[k]);
    e.upper[k] = std::max(e.upper[k], r.upper[k]);
  }
}

void WaterCoupling::displace(Body& b) {
  const btTransform& pose = b.body->getWorldTransform();
  btVector3 lo, hi;
  b.body->getCollisionShape()->getAabb(pose, lo, hi);
  // At rest (within a thousandth of a cell of the pose the displacement was last taken
  // from) nothing is swept: the motion is taken, whole, once it exceeds that.
  if (b.have_reference &&
      same_pose(pose, b.reference_pose, 1e-3 * surface_.spacing(), 0.5 * double((hi - lo).length())))
    return;
  sample_envelopes(b);
  if (b.have_reference) {
    // Nodes of both envelopes, padded for the smoothing.
    const int per = settings_.fluid.samples_per_cell, pad = settings_.smoothing_passes + 1;
    const EnvelopeRaster& e = b.current;
    const auto node0 = [per](std::int64_t k) { return int(k / per); };
    const GridRect win =
        GridRect::spanning(std::max(0, std::min(node0(e.i0), node0(b.reference.i0)) - pad),
                           std::max(0, std::min(node0(e.j0), node0(b.reference.j0)) - pad),
                           std::min(surface_.nx() - 1, std::max(node0(e.i1() - 1), node0(b.reference.i1() - 1)) + pad),
                           std::min(surface_.ny() - 1, std::max(node0(e.j1() - 1), node0(b.reference.j1() - 1)) + pad));
    Workspace& w = *work_;
    surface_.heights_above_rest(win.i0, win.j0, win.nx, win.ny, w.heights);
    w.ds.assign(w.heights.size(), 0.0);
    const double rest = surface_.settings().rest_height, share = 1.0 / (double(per) * per);
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
    for (int p = 0; p < settings_.smoothing_passes; ++p) smooth(w.ds, win.nx, win.ny, w.smooth);
    for (double& d : w.ds) d *= settings_.displacement_gain;
    stats_.displaced_volume += surface_.add_heights(win.i0, win.j0, win.nx, win.ny, w.ds);
  }
  std::swap(b.reference, b.current);
  b.reference_pose = pose;
  b.have_reference = true;
}

void WaterCoupling::float_body(Body& b, double h) {
  btRigidBody& body = *b.body;
  const Frame f = envelope_detail::frame_of(body.getWorldTransform());
  if (!coupling_detail::body_is_sane(body, settings_.max_speed) ||
      !(envelope_detail::basis_deviation(f) <= kMaxBasisDeviation)) {  // never poison the water
    ++stats_.skipped_bodies;
    return;
  }
  btVector3 lo, hi;
  body.getCollisionShape()->getAabb(body.getWorldTransform(), lo, hi);
  const GridRect inner = window_under(surface_, lo, hi, 0), win = window_under(surface_, lo, hi, 2);
  Workspace& w = *work_;
  surface_.heights_above_rest(win.i0, win.j0, win.nx, win.ny, w.heights);
  surface_.vertical_velocities(win.i0, win.j0, win.nx, win.ny, w.velocities);
  const water_detail::WaterPlane plane = fit_plane(surface_, win, inner, w.heights, w.velocities);
  part_frames(b.shape, f, w.frames, w.planes);
  submerge(b.shape, w.frames, plane, b.wet);
  double sampled_volume = 0.0;
  Vec3 sampled_moment{};
  if (b.shape.sampled) submerge_sampled(b.shape, w.frames, plane, *b.rasterizer, sampled_volume, sampled_moment);
  water_detail::Motion m;
  m.com = to_vec3(body.getCenterOfMassPosition());
  m.v = to_vec3(body.getLinearVelocity());
  m.w = to_vec3(body.getAngularVelocity());
  m.mass = body.getInvMass() > 0 ? 1.0 / double(body.getInvMass()) : 0.0;
  m.inv_inertia = body.getInvInertiaTensorWorld();
  b.last = water_detail::water_forces(b.wet, sampled_volume, sampled_moment, plane, settings_.fluid, m, h);
  if (m.mass > 0.0 && b.last.submerged_volume > 0.0) {  // kinematic and static bodies: reported, not applied
    body.applyCentralImpulse(b.last.force * btScalar(h));
    body.applyTorqueImpulse(b.last.torque * btScalar(h));
    body.activate(true);
  }
  surface_.wake(lo.x(), lo.y(), hi.x(), hi.y());
  if (b.disturb) displace(b);
}

void WaterCoupling::updateAction(btCollisionWorld*, btScalar substep) {
  ++stats_.substeps;
  // First: nothing below may read a body the world no longer holds.
  stats_.lost_bodies +=
      coupling_detail::forget_bodies_out_of(world_, bodies_, [](std::unique_ptr<Body>& b) -> Body& { return *b; });
  const auto t0 = Clock::now();
  for (const auto& b : bodies_) float_body(*b, substep);
  stats_.coupling_seconds = seconds_since(t0);
  if (settings_.step_water) {
    const auto t1 = Clock::now();
    stats_.water_substeps = surface_.step(substep).substeps;
    stats_.water_seconds = seconds_since(t1);
  }
}

namespace {
constexpr char kWaterMagic[8] = {'S', 'H', 'W', 'A', 'T', 'R', 'C', 'P'};
constexpr std::uint32_t kWaterVersion = 1;
using coupling_detail::shape_type;

void put_body_water(ByteWriter& w, const BodyWater& b) {
  w.put(b.submerged_volume);
  for (const btVector3* v : {&b.centre_of_buoyancy, &b.buoyancy, &b.drag, &b.force, &b.torque})
    coupling_detail::put_vector(w, *v);
  w.put(b.projected_area), w.put(b.water_level);
}

BodyWater get_body_water(ByteReader& r) {
  BodyWater b;
  b.submerged_volume = r.get<double>("water force");
  for (btVector3* v : {&b.centre_of_buoyancy, &b.buoyancy, &b.drag, &b.force, &b.torque})
    *v = coupling_detail::get_vector(r, "water force");
  b.projected_area = r.get<double>("water force"), b.water_level = r.get<double>("water force");
  return b;
}

void put_sub_envelope(ByteWriter& w, const EnvelopeRaster& e) { coupling_detail::put_window(w, e); }

EnvelopeRaster get_sub_envelope(ByteReader& r) {
  EnvelopeRaster e;
  coupling_detail::get_window(r, e);
  const std::size_t n = std::size_t(e.nx) * std::size_t(e.ny);
  if (e.lower.size() != n || e.upper.size() != n)
    r.fail("envelope holds " + std::to_string(e.lower.size()) + " samples, its window " + std::to_string(n));
  return e;
}

}  // namespace

std::vector<unsigned char> WaterCoupling::save_state() const {
  ByteWriter w;
  coupling_detail::put_header(w, kWaterMagic, kWaterVersion);
  w.put(stats_.substeps), w.put(stats_.skipped_bodies), w.put(stats_.displaced_volume);  // totals, not timings
  w.put(static_cast<std::uint32_t>(bodies_.size()));
  for (const auto& b : bodies_) {
    w.put(static_cast<std::int32_t>(shape_type(*b->body))), w.put(static_cast<std::uint8_t>(b->disturb));
    put_sub_envelope(w, b->reference);
    coupling_detail::put_transform(w, b->reference_pose);
    w.put(static_cast<std::uint8_t>(b->have_reference));
    put_body_water(w, b->last);
  }
  return std::move(w.bytes);
}

void WaterCoupling::restore_state(std::span<const unsigned char> bytes, const std::string& source) {
  ByteReader r(bytes, source);
  coupling_detail::check_header(r, kWaterMagic, kWaterVersion, "a water coupling's state");
  WaterCouplingStats stats;
  stats.substeps = r.get<std::int64_t>("statistics"), stats.skipped_bodies = r.get<std::int64_t>("statistics");
  stats.displaced_volume = r.get<double>("statistics");
  const auto count = r.get<std::uint32_t>("body count");
  if (count != bodies_.size())
    r.fail("holds " + std::to_string(count) + " bodies, the coupling has " + std::to_string(bodies_.size()) +
           " (add the same bodies in the same order)");
  struct Saved {
    EnvelopeRaster reference;
    btTransform pose;
    bool have_reference = false;
    BodyWater last;
  };
  std::vector<Saved> saved(count);  // read whole before anything changes
  for (std::uint32_t k = 0; k < count; ++k) {
    const auto type = r.get<std::int32_t>("body shape type");
    const bool disturb = r.get<std::uint8_t>("body settings") != 0;
    if (type != shape_type(*bodies_[k]->body) || disturb != bodies_[k]->disturb)
      r.fail("body " + std::to_string(k) + " was saved with shape type " + std::to_string(type) +
             (disturb ? "" : " not") + " disturbing; the coupling's has " +
             std::to_string(shape_type(*bodies_[k]->body)) + (bodies_[k]->disturb ? "" : " not") + " disturbing");
    saved[k].reference = get_sub_envelope(r);
    const EnvelopeRaster& e = saved[k].reference;
    const int per = settings_.fluid.samples_per_cell;
    if (!e.lower.empty() && (e.i0 < 0 || e.j0 < 0 || e.i0 + e.nx > std::int64_t(surface_.nx()) * per ||
                             e.j0 + e.ny > std::int64_t(surface_.ny()) * per))
      r.fail("body " + std::to_string(k) + "'s envelope lies outside the water grid");
    saved[k].pose = coupling_detail::get_transform(r, "envelope pose");
    if (!coupling_detail::finite(saved[k].pose)) r.fail("body " + std::to_string(k) + "'s envelope pose is not finite");
    saved[k].have_reference = r.get<std::uint8_t>("envelope flag") != 0;
    saved[k].last = get_body_water(r);
  }
  if (r.remaining() != 0) r.fail("bytes after the last body (corrupt)");
  stats_ = stats;
  for (std::uint32_t k = 0; k < count; ++k) {
    Body& b = *bodies_[k];
    b.reference = std::move(saved[k].reference);
    b.reference_pose = saved[k].pose;
    b.have_reference = saved[k].have_reference;
    b.last = saved[k].last;
  }
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
