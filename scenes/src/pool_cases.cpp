#include "shore/scenes/pool_cases.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>

#include "shore/bullet/water_coupling.h"
#include "shore/core/det_math.h"
#include "shore/scenes/state.h"
#include "shore/scenes/world.h"

namespace shore::scenes {

namespace {
constexpr double kGravity = 9.81;
constexpr double kWaterDensity = 1000.0;
constexpr double kPi = std::numbers::pi;

constexpr int kPrismSides = 8;

/// The octagon's area for a circumscribed diameter x: (n/2) r^2 sin(2 pi / n).
double prism_area(double across) {
  const double r = 0.5 * across;
  return 0.5 * kPrismSides * r * r * det::sin(2.0 * kPi / kPrismSides);
}

std::unique_ptr<btCollisionShape> prism(const Floater& f) {
  auto hull = std::make_unique<btConvexHullShape>();
  const double r = 0.5 * f.size.x(), h = 0.5 * f.size.z();
  for (int k = 0; k < kPrismSides; ++k) {
    const double a = 2.0 * kPi * (k + 0.5) / kPrismSides;
    for (double z : {-h, h})
      hull->addPoint(btVector3(btScalar(r * det::cos(a)), btScalar(r * det::sin(a)), btScalar(z)), false);
  }
  hull->recalcLocalAabb();
  return hull;
}

}  // namespace

double floater_volume(const Floater& f) {
  switch (f.shape) {
    case FloaterShape::box:
      return double(f.size.x()) * f.size.y() * f.size.z();
    case FloaterShape::sphere:
      return kPi * double(f.size.x()) * f.size.x() * f.size.x() / 6.0;
    case FloaterShape::cylinder:
      return kPi * 0.25 * double(f.size.x()) * f.size.x() * f.size.y();
    case FloaterShape::hull:
      return prism_area(f.size.x()) * f.size.z();
  }
  return 0.0;
}

namespace {

std::unique_ptr<btCollisionShape> shape_of(const Floater& f) {
  switch (f.shape) {
    case FloaterShape::hull:
      return prism(f);
    case FloaterShape::box:
      return std::make_unique<btBoxShape>(f.size * btScalar(0.5));
    case FloaterShape::sphere:
      return std::make_unique<btSphereShape>(f.size.x() * btScalar(0.5));
    case FloaterShape::cylinder:
      return std::make_unique<btCylinderShape>(
          btVector3(f.size.x() * btScalar(0.5), f.size.y() * btScalar(0.5), f.size.x() * btScalar(0.5)));
  }
  return nullptr;
}

/// Bisection on a monotone function f(d) - target over [0, hi].
template <class F>
double solve(F&& f, double target, double hi) {
  double lo = 0.0;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) < target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}
}  // namespace

double archimedes_draft(const Floater& f) {
  const double r = f.density_ratio;
  switch (f.shape) {
    case FloaterShape::box:
    case FloaterShape::hull:
      return r * f.size.z();
    case FloaterShape::sphere: {
      const double R = 0.5 * f.size.x();
      return solve([&](double d) { return kPi * d * d * (3 * R - d) / 3.0; }, r * 4.0 / 3.0 * kPi * R * R * R, 2 * R);
    }
    case FloaterShape::cylinder: {
      const double R = 0.5 * f.size.x();
      auto segment = [&](double d) { return R * R * std::acos((R - d) / R) - (R - d) * std::sqrt(2 * R * d - d * d); };
      return solve(segment, r * kPi * R * R, 2 * R);
    }
  }
  return 0.0;
}

btRigidBody* add_floater(World& world, const Floater& f) {
  btRigidBody* b =
      world.add_body(shape_of(f), f.density_ratio * kWaterDensity * floater_volume(f), f.position, f.rotation);
  b->setLinearVelocity(f.velocity);
  b->setActivationState(DISABLE_DEACTIVATION);
  return b;
}

namespace {

/// The pool's water, centred on the origin, walls at the edges, and a rigid floor at -depth.
struct Pool {
  std::shared_ptr<water::Surface> surface;
  World world{kGravity};
  std::unique_ptr<bullet::WaterCoupling> coupling;
};

std::unique_ptr<Pool> make_pool(const PoolSettings& p) {
  auto pool = std::make_unique<Pool>();
  water::PhysicalParameters phys;
  phys.cell = p.cell;
  phys.depth = p.depth;
  phys.density = kWaterDensity;
  phys.damping_time = p.damping_time;
  const int ny = p.nodes_y > 0 ? p.nodes_y : p.nodes;
  water::SurfaceSettings ws = water::SurfaceSettings::physical(phys, p.nodes, ny);
  ws.origin_x = -0.5 * (p.nodes - 1) * p.cell;
  ws.origin_y = -0.5 * (ny - 1) * p.cell;
  ws.rest_height = 0.0;
  ws.mode = p.vertical_only ? water::SurfaceMode::vertical_only : water::SurfaceMode::full_3d;
  ws.boundary = water::Boundary::vertical_only;
  ws.threads = p.threads;
  ws.sleep.enabled = p.sleep;
  if (p.parallel_min_nodes >= 0) ws.parallel_min_nodes = p.parallel_min_nodes;
  pool->surface = std::make_shared<water::Surface>(ws);
  const double half_x = 0.5 * p.nodes * p.cell + 1.0, half_y = 0.5 * ny * p.cell + 1.0;
  pool->world.add_body(std::make_unique<btBoxShape>(btVector3(btScalar(half_x), btScalar(half_y), 0.5f)), 0.0,
                       btVector3(0, 0, btScalar(-p.depth - 0.5)));
  bullet::WaterCouplingSettings cs;
  cs.fluid = p.fluid;
  pool->coupling = std::make_unique<bullet::WaterCoupling>(pool->world.world(), *pool->surface, cs);
  return pool;
}

}  // namespace

double bottom_of(const Floater& f, const btTransform& pose) {
  switch (f.shape) {
    case FloaterShape::box:
    case FloaterShape::hull:
      return double((pose.getOrigin() - pose.getBasis().getColumn(2) * (btScalar(0.5) * f.size.z())).z());
    case FloaterShape::sphere:
    case FloaterShape::cylinder:
      break;
  }
  return double(pose.getOrigin().z()) - 0.5 * f.size.x();
}

PoolResult run_pool(const PoolRun& run) {
  PoolResult out;
  const PoolSettings& p = run.pool;
  const std::unique_ptr<Pool> pool = make_pool(p);
  out.surface = pool->surface;
  World& world = pool->world;
  bullet::WaterCoupling& coupling = *pool->coupling;
  std::vector<btRigidBody*> bodies;
  for (const Floater& f : run.floaters) {
    btRigidBody* b = add_floater(world, f);
    coupling.add_body(b);
    bodies.push_back(b);
  }
  out.max_z.assign(bodies.size(), std::numeric_limits<double>::lowest());
  std::vector<double> draft_sum(bodies.size(), 0.0);
  std::int64_t draft_samples = 0;

  const double frame = p.substep * run.substeps_per_step;
  const auto frames = static_cast<std::int64_t>(std::lround(run.seconds / frame));
  using Clock = std::chrono::steady_clock;
  for (std::int64_t k = 0; k < frames; ++k) {
    const auto t0 = Clock::now();
    world.world().stepSimulation(btScalar(frame), run.substeps_per_step, btScalar(p.substep));
    out.wall_seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    out.coupling_seconds += coupling.stats().coupling_seconds;
    out.water_seconds += coupling.stats().water_seconds;
    out.substeps += run.substeps_per_step;
    const double t = double(k + 1) * frame;
    PoolRecord rec;
    rec.t = t;
    const bool recorded = k % run.record_every == 0;
    if (recorded) rec.water_energy = out.surface->energy().centred;
    const bool last_second = t > run.seconds - 1.0;
    double level = 0.0;
    if (last_second) {  // the far-field level: mean of the surface
      level = out.surface->mean_level();
      ++draft_samples;
    }
    for (std::size_t n = 0; n < bodies.size(); ++n) {
      const btTransform& tr = bodies[n]->getWorldTransform();
      const double z = tr.getOrigin().z();
      if (k > 0) out.max_z[n] = std::max(out.max_z[n], z);
      rec.z.push_back(z);
      const btVector3 up = tr.getBasis().getColumn(2);
      rec.tilt.push_back(std::acos(std::clamp(double(up.z()), -1.0, 1.0)));
      if (last_second) draft_sum[n] += level - bottom_of(run.floaters[n], tr);
    }
    if (recorded) out.records.push_back(std::move(rec));
  }
  for (double s : draft_sum) out.final_draft.push_back(draft_samples ? s / double(draft_samples) : 0.0);
  const SceneState state{.waters = {out.surface.get()}, .bodies = {bodies.begin(), bodies.end()}};
  out.state_hash = state_hash(state);
  out.nan_count = non_finite_count(state);
  return out;
}

namespace {
/// The frontal area of a floater towed along x at draft d: box width times d; ball the wet
/// circular segment; others the wet volume over the length along x (a prism's mean).
double frontal_area(const Floater& f, double draft) {
  switch (f.shape) {
    case FloaterShape::box:
      return double(f.size.y()) * std::clamp(draft, 0.0, double(f.size.z()));
    case FloaterShape::sphere: {
      const double r = 0.5 * f.size.x(), x = std::clamp(draft, 0.0, 2 * r) - r;  // level above the centre
      return r * r * (kPi - std::acos(x / r)) + x * std::sqrt(std::max(0.0, r * r - x * x));
    }
    default:
      return 0.0;
  }
}
}  // namespace

TowResult run_tow(const TowRun& run) {
  TowResult out;
  const std::unique_ptr<Pool> pool = make_pool(run.pool);
  // Kinematic, at its Archimedes draft: moved at the speed whatever the water does.
  Floater f = run.floater;
  const double draft = archimedes_draft(f);
  f.position.setZ(btScalar(f.shape == FloaterShape::box ? 0.5 * f.size.z() - draft : 0.5 * f.size.x() - draft));
  btRigidBody* b = add_floater(pool->world, f);
  b->setMassProps(0, btVector3(0, 0, 0));
  b->setCollisionFlags(b->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
  pool->coupling->add_body(b, {.disturb = run.disturb});
  const double h = run.pool.substep;
  const auto steps = static_cast<std::int64_t>(std::lround(run.seconds / h));
  const std::int64_t window = std::min<std::int64_t>(steps, std::lround(1.0 / h));
  double force = 0.0, level = 0.0;
  btTransform pose = b->getWorldTransform();
  for (std::int64_t k = 0; k < steps; ++k) {
    pose.setOrigin(pose.getOrigin() + btVector3(btScalar(run.speed * h), 0, 0));
    b->getMotionState()->setWorldTransform(pose);
    pool->world.step(h);
    out.coupling_seconds += pool->coupling->stats().coupling_seconds;
    ++out.substeps;
    if (k < steps - window) continue;
    force += -double(pool->coupling->water_force(b).drag.x());
    level += pool->coupling->water_force(b).water_level;
  }
  out.drag = force / double(window);
  out.draft = draft + level / double(window);  // the level it tows in, less its bottom
  out.area = frontal_area(run.floater, out.draft);
  const bullet::FluidSettings& fl = run.pool.fluid;
  const double v = run.speed;
  out.reference =
      0.5 * kWaterDensity * fl.quadratic_drag * out.area * v * v + kWaterDensity * fl.linear_drag * out.area * v;
  const SceneState state{.waters = {pool->surface.get()}, .bodies = {b}};
  out.nan_count = non_finite_count(state);
  return out;
}

SinkResult run_sink(const SinkRun& run) {
  SinkResult out;
  const std::unique_ptr<Pool> pool = make_pool(run.pool);
  Floater f;
  f.shape = FloaterShape::sphere;
  f.size = btVector3(btScalar(run.diameter), btScalar(run.diameter), btScalar(run.diameter));
  f.density_ratio = run.density_ratio;
  f.position = btVector3(0, 0, btScalar(-0.6 * run.diameter));  // just under the surface
  btRigidBody* b = add_floater(pool->world, f);
  pool->coupling->add_body(b);
  const double h = run.pool.substep, depth = run.pool.depth;
  const auto steps = static_cast<std::int64_t>(std::lround(run.seconds / h));
  double t_in = -1.0, t_out = -1.0, z_in = 0.0, z_out = 0.0;
  for (std::int64_t k = 0; k < steps && t_out < 0.0; ++k) {
    pool->world.step(h);
    const double z = b->getWorldTransform().getOrigin().z(), t = double(k + 1) * h;
    if (t_in < 0.0 && z < -0.4 * depth) {
      t_in = t;
      z_in = z;
    }
    if (t_out < 0.0 && z < -0.8 * depth) {
      t_out = t;
      z_out = z;
    }
  }
  out.terminal = t_out > t_in && t_in > 0.0 ? (z_in - z_out) / (t_out - t_in) : 0.0;
  // (rho_b - rho) V g = 1/2 rho C_d A v^2 + rho k A v.
  const bullet::FluidSettings& fl = run.pool.fluid;
  const double r = 0.5 * run.diameter, area = kPi * r * r, volume = 4.0 / 3.0 * kPi * r * r * r;
  const double weight = (run.density_ratio - 1.0) * kWaterDensity * volume * kGravity;
  const double a = 0.5 * kWaterDensity * fl.quadratic_drag * area, bl = kWaterDensity * fl.linear_drag * area;
  out.reference = a > 0.0 ? (-bl + std::sqrt(bl * bl + 4.0 * a * weight)) / (2.0 * a) : weight / bl;
  const SceneState state{.waters = {pool->surface.get()}, .bodies = {b}};
  out.nan_count = non_finite_count(state);
  return out;
}

}  // namespace shore::scenes
