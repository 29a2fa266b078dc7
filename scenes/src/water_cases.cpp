#include "shore/scenes/water_cases.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>

#include <btBulletDynamicsCommon.h>

#include "shore/bullet/water_coupling.h"
#include "shore/scenes/world.h"
#include "shore/water/surface.h"

namespace shore::scenes {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

constexpr double kCell = 0.05, kSigma = 0.1, kAmplitude = 1e-3, kDt = 1.0 / 240;
constexpr int kDistance = 30;  // nodes from the source to the edge of the water

water::SurfaceSettings patch(const EchoCase& c, water::Boundary b, int margin_west, int nx, int ny) {
  water::PhysicalParameters p;
  p.cell = kCell;
  p.depth = 0.5;
  p.damping_time = std::numeric_limits<double>::infinity();
  water::SurfaceSettings s = water::SurfaceSettings::physical(p, nx, ny);
  s.mode = c.mode;
  s.boundary = b;
  s.open.width = c.width;
  s.open.strength = c.strength;
  s.sleep.enabled = false;  // the edge's echo alone, not sleeping's
  s.threads = 1;
  s.origin_x = -kCell * margin_west;  // the source sits at x = 0
  s.origin_y = -kCell * (ny / 2);
  return s;
}

/// Heights at the source (x = 0) and at x = 2 d over the echo's window.
struct Trace {
  std::vector<double> source, probe;
};
Trace trace(const water::SurfaceSettings& s, double window_end) {
  water::Surface surf(s);
  surf.disturb(water::Disturbance::point_height(0.0, 0.0, kSigma, kAmplitude));
  const double cw = s.lattice.wave_speed(), d = kDistance * kCell;
  Trace t;
  for (int k = 1; k * kDt * cw < window_end; ++k) {
    surf.step(kDt);
    if (k * kDt * cw < 2.0 * d - 5.0 * kSigma) continue;  // before any echo can arrive
    t.source.push_back(surf.height_at(0.0, 0.0));
    t.probe.push_back(surf.height_at(2.0 * d, 0.0));
  }
  return t;
}

}  // namespace

EchoResult measure_echo(const EchoCase& c) {
  const int layer = c.boundary == water::Boundary::open ? c.width : 0;
  const int west = kDistance + layer, ny = 2 * (2 * kDistance + layer) + 21;
  // The window closes after echoes from deep in the layer could come back.
  const double window_end = 2.0 * (kDistance + layer) * kCell + 6.0 * kSigma;
  const Trace with_edge = trace(patch(c, c.boundary, west, west + 3 * kDistance + layer, ny), window_end);
  const int far = std::max(kDistance + layer, 2 * kDistance) + 20;  // no echo within the window
  const Trace free_space = trace(patch(c, water::Boundary::vertical_only, far, 2 * far, 2 * far + 1), window_end);
  EchoResult e;
  for (std::size_t k = 0; k < with_edge.source.size(); ++k) {
    e.reflected = std::max(e.reflected, std::abs(with_edge.source[k] - free_space.source[k]));
    e.direct = std::max(e.direct, std::abs(free_space.probe[k]));
  }
  return e;
}

DriftResult run_closed_pool(const DriftCase& c) {
  water::PhysicalParameters p;
  p.cell = kCell;
  p.depth = 0.5;
  p.damping_time = 2.0;
  water::SurfaceSettings s = water::SurfaceSettings::physical(p, c.nodes, c.nodes);
  s.mode = c.mode;
  s.boundary = water::Boundary::vertical_only;
  s.sleep.enabled = c.sleep;
  s.threads = c.threads;
  water::Surface surf(s);
  const double sigma = 3.0 * kCell, amplitude = 0.01;
  surf.disturb(water::Disturbance::point_height(surf.node_x(c.nodes / 3), surf.node_y(c.nodes / 2), sigma, amplitude));
  const double bump = amplitude * 2.0 * 3.141592653589793 * sigma * sigma;  // m^3
  const double v0 = surf.volume();
  DriftResult r;
  r.exact = true;
  const auto t0 = Clock::now();
  for (long k = 1; k <= c.steps; ++k) {
    surf.step(kDt);
    if (k % 100 == 0 || k == c.steps) {
      const double v = surf.volume();
      r.volume_drift = std::max(r.volume_drift, std::abs(v - v0) / bump);
      r.exact = r.exact && v == v0;
    }
  }
  r.seconds = seconds_since(t0);
  return r;
}

double energy_gain(const EnergyCase& c) {
  water::PhysicalParameters p;
  p.cell = kCell;
  p.depth = 0.5;
  p.damping_time = std::numeric_limits<double>::infinity();
  water::SurfaceSettings s = water::SurfaceSettings::physical(p, 65, 65);
  s.mode = water::SurfaceMode::full_3d;
  s.boundary = water::Boundary::fixed;
  s.sleep.enabled = false;
  s.threads = 1;
  water::Surface surf(s);
  surf.disturb(
      water::Disturbance::point_height(surf.node_x(0) + 1.18, surf.node_y(0) + 1.31, 3.0 * kCell, c.amplitude));
  surf.step(kDt);
  const double e0 = surf.energy().centred;
  double worst = 0.0;
  const long every = std::max(1L, c.steps / 50);
  for (long k = 1; k <= c.steps; ++k) {
    surf.step(kDt);
    if (k % every == 0) worst = std::max(worst, surf.energy().centred / e0 - 1.0);
  }
  return worst;
}

water::SurfaceSettings lake_surface(const LakeCase& c) {
  water::PhysicalParameters p;
  p.cell = c.cell;
  p.depth = c.depth;
  const int n = static_cast<int>(std::lround(c.side / c.cell)) + 1;
  water::SurfaceSettings s = water::SurfaceSettings::physical(p, n, n);
  s.mode = water::SurfaceMode::vertical_only;
  s.boundary = water::Boundary::open;
  s.threads = c.threads;
  return s;
}

LakeResult run_lake(const LakeCase& c) {
  LakeResult out;
  const water::SurfaceSettings s = lake_surface(c);
  const auto t0 = Clock::now();
  auto lake = std::make_unique<water::Surface>(s);
  out.creation_ms = 1e3 * seconds_since(t0);
  out.empty_memory_bytes = lake->tile_stats().memory_bytes;
  out.virtual_nodes = static_cast<std::int64_t>(s.nx) * s.ny;
  World world(9.81);
  bullet::WaterCoupling coupling(world.world(), *lake);
  const double draft = 0.3;
  btRigidBody* boat = world.add_body(std::make_unique<btBoxShape>(btVector3(1.0f, 0.5f, 0.3f)), 0.0,
                                     btVector3(btScalar(0.5 * c.side), btScalar(0.5 * c.side), btScalar(0.3 - draft)));
  boat->setCollisionFlags(boat->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
  boat->setActivationState(DISABLE_DEACTIVATION);
  coupling.add_body(boat);
  btTransform pose = boat->getWorldTransform();
  const auto steps = static_cast<long>(std::lround(c.seconds / c.substep));
  const long every = std::max(1L, static_cast<long>(std::lround(1.0 / c.substep)));
  double busy = 0.0, awake_sum = 0.0;  // awake nodes summed over the substeps since the last sample
  for (long k = 1; k <= steps; ++k) {
    pose.setOrigin(pose.getOrigin() + btVector3(btScalar(c.speed * c.substep), 0, 0));
    boat->getMotionState()->setWorldTransform(pose);
    const auto awake_before = double(lake->tile_stats().awake_nodes);
    world.step(c.substep);
    busy += coupling.stats().coupling_seconds + coupling.stats().water_seconds;
    // The nodes a substep stepped: between those awake before it and after it (a wake grows).
    awake_sum += 0.5 * (awake_before + double(lake->tile_stats().awake_nodes));
    if (k % every == 0 || k == steps) {
      const water::TileStats st = lake->tile_stats();
      LakeSample sample;
      sample.t = double(k) * c.substep;
      sample.awake_nodes = st.awake_nodes;
      sample.woken_nodes = st.ever_awake * st.tile * st.tile;
      sample.memory_bytes = st.memory_bytes;
      const double substeps = double(k % every == 0 ? every : k % every);
      sample.step_ms = 1e3 * busy / substeps;
      sample.mean_awake_nodes = awake_sum / substeps;
      out.samples.push_back(sample);
      busy = awake_sum = 0.0;
    }
  }
  return out;
}

}  // namespace shore::scenes
