#include "shore/bullet/water_coupling.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <utility>

#include "coupling_util.h"
#include "shore/core/error.h"
#include "shore/terrain/terrain.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

namespace {
using coupling_detail::Clock;
using coupling_detail::seconds_since;

/// Both envelopes of the nominal solid: buoyancy needs the body's true volume (Bullet's
/// contact solid rounds cylinder rims and inflates hulls by the margin).
EnvelopeOptions with_upper() {
  EnvelopeOptions o;
  o.upper = true;
  o.include_margin = false;
  return o;
}

/// One volume-conserving [1 2 1]/4 pass in x then y over a rectangular field.
void smooth(std::vector<double>& f, int nx, int ny, std::vector<double>& tmp) {
  tmp.assign(f.size(), 0.0);
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      const double v = f[std::size_t(y) * std::size_t(nx) + std::size_t(x)];
      if (v == 0.0) continue;
      const std::size_t row = std::size_t(y) * std::size_t(nx);
      tmp[row + std::size_t(x)] += 0.5 * v;
      if (x > 0)
        tmp[row + std::size_t(x - 1)] += 0.25 * v;
      else
        tmp[row + std::size_t(x)] += 0.25 * v;
      if (x + 1 < nx)
        tmp[row + std::size_t(x + 1)] += 0.25 * v;
      else
        tmp[row + std::size_t(x)] += 0.25 * v;
    }
  f.assign(f.size(), 0.0);
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      const double v = tmp[std::size_t(y) * std::size_t(nx) + std::size_t(x)];
      if (v == 0.0) continue;
      auto at = [&](int yy) -> double& { return f[std::size_t(yy) * std::size_t(nx) + std::size_t(x)]; };
      at(y) += 0.5 * v;
      (y > 0 ? at(y - 1) : at(y)) += 0.25 * v;
      (y + 1 < ny ? at(y + 1) : at(y)) += 0.25 * v;
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
    : world_(world),
      surface_(surface),
      settings_(std::move(settings)),
      sample_cell_(surface.spacing() / settings_.fluid.samples_per_cell) {
  settings_.fluid.density = surface.density();
  settings_.validate();
  sampler_.height = [this](double x, double y) { return surface_.height_at(x, y); };
  sampler_.velocity = [this](double x, double y) {
    return btVector3(0, 0, btScalar(surface_.vertical_velocity_at(x, y)));
  };
  world_.addAction(this);
}

WaterCoupling::~WaterCoupling() { world_.removeAction(this); }

bool WaterCoupling::body_is_sane(const btRigidBody& body) const {
  return coupling_detail::body_is_sane(body, settings_.max_speed);
}

void WaterCoupling::rasterize(const btRigidBody& body, Sampled& out) const {
  const btVector3 com = body.getCenterOfMassPosition();
  out.origin_x = com.x() + 0.5 * sample_cell_;  // samples at com +- (k + 1/2) cell
  out.origin_y = com.y() + 0.5 * sample_cell_;
  rasterize_envelope(*body.getCollisionShape(), body.getWorldTransform(),
                     EnvelopeGrid{out.origin_x, out.origin_y, sample_cell_}, with_upper(), out.raster);
}

bool WaterCoupling::can_rasterize(const Body& b) const {
  const btVector3 com = b.body->getCenterOfMassPosition();
  return pose_rasterizable(b.body->getWorldTransform(), b.reach,
                           EnvelopeGrid{com.x() + 0.5 * sample_cell_, com.y() + 0.5 * sample_cell_, sample_cell_});
}

void WaterCoupling::add_body(btRigidBody* body, bool disturb) {
  if (body == nullptr) throw InvalidSetting("bullet.WaterCoupling.add_body(body)", "null", "must be a rigid body");
  Body b;
  b.body = body;
  b.disturb = disturb;
  // Once: then rasterizing it never fails for a sane pose.
  b.reach = check_rasterizable(*body->getCollisionShape(), sample_cell_, with_upper());
  remove_body(body);
  if (body_is_sane(*body) && can_rasterize(b)) rasterize(*body, b.previous);  // tracking starts at this pose
  bodies_.push_back(std::move(b));
}

void WaterCoupling::remove_body(btRigidBody* body) {
  std::erase_if(bodies_, [body](const Body& b) { return b.body == body; });
}

double WaterCoupling::submerged_volume(const btRigidBody* body) const {
  for (const Body& b : bodies_)
    if (b.body == body) return b.submerged;
  return 0.0;
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

void WaterCoupling::displace(Body& b) {
  const double node_area = surface_.spacing() * surface_.spacing();
  const double sample_area = sample_cell_ * sample_cell_;
  const double inv_h = 1.0 / surface_.spacing();
  // Node of a sample: the nearest one.
  auto node_of = [&](const Sampled& s, std::int64_t fi, std::int64_t fj) {
    const double x = s.origin_x + double(fi) * sample_cell_, y = s.origin_y + double(fj) * sample_cell_;
    return std::pair<std::int64_t, std::int64_t>{
        std::int64_t(std::floor((x - surface_.settings().origin_x) * inv_h + 0.5)),
        std::int64_t(std::floor((y - surface_.settings().origin_y) * inv_h + 0.5))};
  };
  submerged_lengths(b.previous.raster, b.previous.origin_x, b.previous.origin_y, sample_cell_, sampler_, lengths_old_);
  submerged_lengths(b.current.raster, b.current.origin_x, b.current.origin_y, sample_cell_, sampler_, lengths_new_);
  // Node window covering both rasters, padded by one node per smoothing pass.
  const int pad = settings_.smoothing_passes + 1;
  std::int64_t i0 = INT64_MAX, j0 = INT64_MAX, i1 = INT64_MIN, j1 = INT64_MIN;
  for (const Sampled* s : {&b.previous, &b.current}) {
    const EnvelopeRaster& r = s->raster;
    if (r.nx == 0 || r.ny == 0) continue;
    const auto [a0, c0] = node_of(*s, r.i0, r.j0);
    const auto [a1, c1] = node_of(*s, r.i0 + r.nx - 1, r.j0 + r.ny - 1);
    i0 = std::min(i0, a0 - pad);
    j0 = std::min(j0, c0 - pad);
    i1 = std::max(i1, a1 + pad);
    j1 = std::max(j1, c1 + pad);
  }
  if (i0 > i1 || j0 > j1) return;
  const int nx = int(i1 - i0 + 1), ny = int(j1 - j0 + 1);
  std::vector<double> ds(std::size_t(nx) * std::size_t(ny), 0.0);
  auto accumulate = [&](const Sampled& s, const std::vector<double>& len, double sign) {
    const EnvelopeRaster& r = s.raster;
    for (int bb = 0; bb < r.ny; ++bb)
      for (int aa = 0; aa < r.nx; ++aa) {
        const double l = len[std::size_t(bb) * std::size_t(r.nx) + std::size_t(aa)];
        if (l == 0.0) continue;
        const auto [ni, nj] = node_of(s, r.i0 + aa, r.j0 + bb);
        ds[std::size_t(nj - j0) * std::size_t(nx) + std::size_t(ni - i0)] += sign * l * sample_area / node_area;
      }
  };
  accumulate(b.current, lengths_new_, 1.0);
  accumulate(b.previous, lengths_old_, -1.0);
  for (int p = 0; p < settings_.smoothing_passes; ++p) smooth(ds, nx, ny, scratch_);
  const double gain = settings_.displacement_gain;
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      const double d = gain * ds[std::size_t(y) * std::size_t(nx) + std::size_t(x)];
      const std::int64_t i = i0 + x, j = j0 + y;
      if (d == 0.0 || i < 0 || j < 0 || i >= surface_.nx() || j >= surface_.ny()) continue;
      if (surface_.add_height(int(i), int(j), d)) stats_.displaced_volume += d * node_area;
    }
}

void WaterCoupling::updateAction(btCollisionWorld*, btScalar substep) {
  const double h = substep;
  ++stats_.substeps;
  const auto t0 = Clock::now();
  for (Body& b : bodies_) {
    btRigidBody& body = *b.body;
    if (!body_is_sane(body) || !can_rasterize(b)) {  // never poison the water
      ++stats_.skipped_bodies;
      continue;
    }
    rasterize(body, b.current);
    const double mass = body.getInvMass() > 0 ? 1.0 / body.getInvMass() : 0.0;
    if (mass > 0.0) {
      const WaterImpulse w = water_impulse(b.current.raster, b.current.origin_x, b.current.origin_y, sample_cell_,
                                           sampler_, settings_.fluid, body.getCenterOfMassPosition(),
                                           body.getLinearVelocity(), body.getAngularVelocity(), mass, h);
      b.submerged = w.submerged_volume;
      if (w.submerged_volume > 0.0) {
        body.applyCentralImpulse(w.linear);
        body.applyTorqueImpulse(w.angular);
        body.activate(true);
      }
    }
    if (b.disturb) displace(b);
    std::swap(b.previous, b.current);
  }
  stats_.coupling_seconds = seconds_since(t0);
  if (settings_.step_water) {
    const auto t1 = Clock::now();
    stats_.water_substeps = surface_.step(h).substeps;
    stats_.water_seconds = seconds_since(t1);
  }
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
