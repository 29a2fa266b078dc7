#include "shore/scenes/pool_cases.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>

#include "shore/bullet/water_coupling.h"
#include "shore/scenes/state.h"
#include "shore/scenes/world.h"

namespace shore::scenes {

namespace {
constexpr double kGravity = 9.81;
constexpr double kWaterDensity = 1000.0;
constexpr double kPi = std::numbers::pi;

double volume_of(const Floater& f) {
  switch (f.shape) {
    case FloaterShape::box:
      return double(f.size.x()) * f.size.y() * f.size.z();
    case FloaterShape::sphere:
      return kPi * std::pow(double(f.size.x()), 3) / 6.0;
    case FloaterShape::cylinder:
      return kPi * 0.25 * double(f.size.x()) * f.size.x() * f.size.y();
  }
  return 0.0;
}

std::unique_ptr<btCollisionShape> shape_of(const Floater& f) {
  switch (f.shape) {
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
  btRigidBody* b = world.add_body(shape_of(f), f.density_ratio * kWaterDensity * volume_of(f), f.position, f.rotation);
  b->setLinearVelocity(f.velocity);
  b->setActivationState(DISABLE_DEACTIVATION);
  return b;
}

PoolResult run_pool(const PoolRun& run) {
  PoolResult out;
  const PoolSettings& p = run.pool;
  water::PhysicalParameters phys;
  phys.cell = p.cell;
  phys.depth = p.depth;
  phys.density = kWaterDensity;
  phys.damping_time = p.damping_time;
  water::SurfaceSettings ws = water::SurfaceSettings::physical(phys, p.nodes, p.nodes);
  ws.origin_x = ws.origin_y = -0.5 * (p.nodes - 1) * p.cell;
  ws.rest_height = 0.0;
  ws.mode = p.vertical_only ? water::SurfaceMode::vertical_only : water::SurfaceMode::full_3d;
  ws.boundary = water::Boundary::vertical_only;
  ws.threads = p.threads;
  out.surface = std::make_shared<water::Surface>(ws);

  World world(kGravity);
  const double half = 0.5 * p.nodes * p.cell + 1.0;
  world.add_body(std::make_unique<btBoxShape>(btVector3(btScalar(half), btScalar(half), 0.5f)), 0.0,
                 btVector3(0, 0, btScalar(-p.depth - 0.5)));
  bullet::WaterCoupling coupling(world.world(), *out.surface);
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
    rec.water_energy = out.surface->energy().centred;
    const bool last_second = t > run.seconds - 1.0;
    double level = 0.0;
    if (last_second) {  // the far-field level: mean of the surface
      for (int j = 0; j < p.nodes; ++j)
        for (int i = 0; i < p.nodes; ++i) level += out.surface->height(i, j);
      level /= double(p.nodes) * p.nodes;
      ++draft_samples;
    }
    for (std::size_t n = 0; n < bodies.size(); ++n) {
      const btTransform& tr = bodies[n]->getWorldTransform();
      const double z = tr.getOrigin().z();
      if (k > 0) out.max_z[n] = std::max(out.max_z[n], z);
      rec.z.push_back(z);
      const btVector3 up = tr.getBasis().getColumn(2);
      rec.tilt.push_back(std::acos(std::clamp(double(up.z()), -1.0, 1.0)));
      if (last_second) {
        btVector3 lo, hi;
        bodies[n]->getCollisionShape()->getAabb(tr, lo, hi);
        draft_sum[n] += level - lo.z();
      }
    }
    if (k % run.record_every == 0) out.records.push_back(std::move(rec));
  }
  for (double s : draft_sum) out.final_draft.push_back(draft_samples ? s / double(draft_samples) : 0.0);
  const SceneState state{.waters = {out.surface.get()}, .bodies = {bodies.begin(), bodies.end()}};
  out.state_hash = state_hash(state);
  out.nan_count = non_finite_count(state);
  return out;
}

}  // namespace shore::scenes
