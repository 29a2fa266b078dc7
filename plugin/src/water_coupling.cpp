#include "shore/bullet/water_coupling.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "shore/core/error.h"
#include "shore/terrain/terrain.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

namespace {
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
bool finite(const btVector3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && (a < 0) != (b < 0)) ? q - 1 : q;
}

/// Samples are placed S x S per water cell, centred on the node: sample f belongs to node
/// floor(f / S).
EnvelopeGrid sample_grid_of(const water::Surface& s, int per_cell) {
  const double h = s.spacing(), cell = h / per_cell;
  return {s.settings().origin_x - 0.5 * h + 0.5 * cell, s.settings().origin_y - 0.5 * h + 0.5 * cell, cell};
}

EnvelopeOptions with_upper() {
  EnvelopeOptions o;
  o.upper = true;
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
      if (x > 0) tmp[row + std::size_t(x - 1)] += 0.25 * v; else tmp[row + std::size_t(x)] += 0.25 * v;
      if (x + 1 < nx) tmp[row + std::size_t(x + 1)] += 0.25 * v; else tmp[row + std::size_t(x)] += 0.25 * v;
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
      sample_grid_(sample_grid_of(surface, settings_.fluid.samples_per_cell)),
      rasterizer_(sample_grid_, with_upper()) {
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
  const btTransform& t = body.getWorldTransform();
  if (!finite(t.getOrigin()) || !finite(t.getBasis()[0]) || !finite(t.getBasis()[1]) || !finite(t.getBasis()[2]))
    return false;
  const btVector3& v = body.getLinearVelocity();
  return finite(v) && finite(body.getAngularVelocity()) && v.length() <= settings_.max_speed;
}

void WaterCoupling::rasterize(const btRigidBody& body, EnvelopeRaster& out) {
  rasterizer_.rasterize(*body.getCollisionShape(), body.getWorldTransform(), out);
}

void WaterCoupling::add_body(btRigidBody* body, bool disturb) {
  if (body == nullptr) throw InvalidSetting("bullet.WaterCoupling.add_body(body)", "null", "must be a rigid body");
  remove_body(body);
  Body b;
  b.body = body;
  b.disturb = disturb;
  if (body_is_sane(*body)) rasterize(*body, b.previous);  // tracking starts at this pose
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
  const int S = settings_.fluid.samples_per_cell;
  const double sample_area = sample_grid_.cell * sample_grid_.cell, node_area = surface_.spacing() * surface_.spacing();
  submerged_lengths(b.previous, sample_grid_.origin_x, sample_grid_.origin_y, sample_grid_.cell, sampler_,
                    lengths_old_);
  submerged_lengths(b.current, sample_grid_.origin_x, sample_grid_.origin_y, sample_grid_.cell, sampler_,
                    lengths_new_);
  // Node window covering both rasters, padded by one node per smoothing pass.
  const int pad = settings_.smoothing_passes + 1;
  auto node_lo = [&](std::int64_t f) { return floor_div(f, S); };
  const std::int64_t i0 = std::min(node_lo(b.previous.i0), node_lo(b.current.i0)) - pad;
  const std::int64_t j0 = std::min(node_lo(b.previous.j0), node_lo(b.current.j0)) - pad;
  const std::int64_t i1 = std::max(node_lo(b.previous.i0 + b.previous.nx), node_lo(b.current.i0 + b.current.nx)) + pad;
  const std::int64_t j1 = std::max(node_lo(b.previous.j0 + b.previous.ny), node_lo(b.current.j0 + b.current.ny)) + pad;
  const int nx = int(i1 - i0 + 1), ny = int(j1 - j0 + 1);
  std::vector<double> ds(std::size_t(nx) * std::size_t(ny), 0.0);
  auto accumulate = [&](const EnvelopeRaster& env, const std::vector<double>& len, double sign) {
    for (int bb = 0; bb < env.ny; ++bb)
      for (int aa = 0; aa < env.nx; ++aa) {
        const double s = len[std::size_t(bb) * std::size_t(env.nx) + std::size_t(aa)];
        if (s == 0.0) continue;
        const std::int64_t ni = node_lo(env.i0 + aa) - i0, nj = node_lo(env.j0 + bb) - j0;
        ds[std::size_t(nj) * std::size_t(nx) + std::size_t(ni)] += sign * s * sample_area / node_area;
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
    if (!body_is_sane(body)) {
      ++stats_.skipped_bodies;
      continue;
    }
    try {
      rasterize(body, b.current);
    } catch (const InvalidSetting&) {  // e.g. an absurdly large shape: skip it, never poison the water
      ++stats_.skipped_bodies;
      continue;
    }
    const double mass = body.getInvMass() > 0 ? 1.0 / body.getInvMass() : 0.0;
    if (mass > 0.0) {
      const WaterImpulse w = water_impulse(b.current, sample_grid_.origin_x, sample_grid_.origin_y, sample_grid_.cell,
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
