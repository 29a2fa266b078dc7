#include "shore/cases/soil_cases.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "shore/bullet/terrain_coupling.h"
#include "shore/cases/bullet_world.h"
#include "shore/core/hash.h"
#include "shore/terrain/bekker.h"
#include "shore/terrain/terrain.h"

namespace shore::cases {

namespace {
constexpr double kGravity = 9.81;
using Clock = std::chrono::steady_clock;

terrain::TerrainSettings soil_settings(const SoilRun& run) {
  terrain::TerrainSettings s;
  s.cell = run.cell;
  s.material = run.material;
  s.threads = run.threads;
  s.max_erosion_passes = run.max_erosion_passes;
  s.active_reach = run.active_reach;
  return s;
}

/// Steps the world n substeps, accumulating timings of the whole step and of the plugin.
void advance(BulletWorld& world, const bullet::TerrainCoupling& ground, double h, RunStats& stats) {
  const auto t0 = Clock::now();
  world.step(h);
  stats.wall_seconds += std::chrono::duration<double>(Clock::now() - t0).count();
  const bullet::TerrainCouplingStats& g = ground.stats();
  stats.envelope_seconds += g.envelope_seconds;
  stats.terrain_seconds += g.terrain_seconds;
  stats.push_seconds += g.push_seconds;
  stats.plugin_seconds += g.envelope_seconds + g.terrain_seconds + g.push_seconds + g.reaction_seconds;
  ++stats.substeps;
}

void finish(RunStats& stats, const terrain::Terrain& soil, const bullet::TerrainCoupling& ground,
            const btRigidBody& body) {
  StateHash h;
  h.add(soil.state_hash());
  const btTransform& t = body.getWorldTransform();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) h.add(double(t.getBasis()[r][c]));
  for (int c = 0; c < 3; ++c) h.add(double(t.getOrigin()[c]));
  stats.state_hash = h.value();
  stats.rescues = ground.stats().rescues;
}

/// Plastic work stored in the soil: sum over columns of cell^2 * integral_0^z p_yield dz,
/// with b the given patch width (rigid-plastic: all of it is dissipated).
double plastic_work_in(const terrain::Terrain& soil, const terrain::ColumnRect& r, double b) {
  const terrain::Material& m = soil.settings().material;
  const double k = m.bekker_kc / b + m.bekker_kphi, n = m.bekker_n, area = soil.settings().cell * soil.settings().cell;
  double w = 0.0;
  for (std::int64_t j = r.j0; j < r.j0 + r.ny; ++j)
    for (std::int64_t i = r.i0; i < r.i0 + r.nx; ++i) w += area * k * std::pow(soil.sinkage(i, j), n + 1) / (n + 1);
  return w;
}
}  // namespace

PlateResult run_plate(const PlateCase& c) {
  PlateResult out;
  terrain::Terrain soil(soil_settings(c.run));
  BulletWorld world(kGravity);
  bullet::TerrainCoupling ground(world.world(), soil);
  const double half_h = 0.05, mass = c.pressure * c.width * c.width / kGravity;
  // Edges halfway between columns, so the footprint covers exactly (width / cell)^2 columns.
  const double cx = 0.5 * c.run.cell + 0.5 * c.width;
  btRigidBody* plate = world.add_body(
      std::make_unique<btBoxShape>(btVector3(btScalar(c.width / 2), btScalar(c.width / 2), btScalar(half_h))), mass,
      btVector3(btScalar(cx), btScalar(cx), btScalar(half_h)));
  plate->setActivationState(DISABLE_DEACTIVATION);
  ground.add_body(plate);
  const double h = c.run.substep;
  const auto steps = static_cast<std::int64_t>(std::lround((c.ramp_seconds + c.settle_seconds) / h));
  for (std::int64_t k = 0; k < steps; ++k) {
    const double t = double(k) * h;
    if (t < c.ramp_seconds)  // the part of the weight not yet applied is held up
      plate->applyCentralForce(btVector3(0, 0, btScalar(mass * kGravity * (1.0 - t / c.ramp_seconds))));
    advance(world, ground, h, out.stats);
  }
  out.sinkage = -(plate->getCenterOfMassPosition().z() - half_h);
  out.reference = c.ramp_seconds > 0 ? terrain::bekker::plate_sinkage(c.run.material, c.width, c.pressure)
                                     : terrain::bekker::plate_sinkage_released(c.run.material, c.width, c.pressure);
  finish(out.stats, soil, ground, *plate);
  return out;
}

WheelResult run_wheel(const WheelCase& c) {
  WheelResult out;
  terrain::Terrain soil(soil_settings(c.run));
  BulletWorld world(kGravity);
  bullet::TerrainCoupling ground(world.world(), soil);
  const double R = c.diameter / 2, mass = c.load / kGravity, h = c.run.substep;
  btRigidBody* wheel =
      world.add_body(std::make_unique<btCylinderShape>(btVector3(btScalar(R), btScalar(c.width / 2), btScalar(R))),
                     mass, btVector3(0, btScalar(0.5 * c.run.cell), btScalar(R)));
  wheel->setActivationState(DISABLE_DEACTIVATION);
  wheel->setLinearFactor(btVector3(0, 0, 1));
  wheel->setAngularFactor(btVector3(0, 0, 0));
  ground.add_body(wheel);

  // Press: the load ramps in with the wheel held still.
  const auto ramp_steps = static_cast<std::int64_t>(std::lround(c.ramp_seconds / h));
  const auto settle_steps = static_cast<std::int64_t>(std::lround(0.5 / h));
  for (std::int64_t k = 0; k < ramp_steps + settle_steps; ++k) {
    const double t = double(k) * h;
    if (t < c.ramp_seconds)
      wheel->applyCentralForce(btVector3(0, 0, btScalar(mass * kGravity * (1.0 - t / c.ramp_seconds))));
    advance(world, ground, h, out.stats);
  }
  if (!c.towed) {
    out.sinkage = -(wheel->getCenterOfMassPosition().z() - R);
    out.reference_sinkage = terrain::bekker::wheel_sinkage_static(c.run.material, c.load, c.diameter, c.width);
    finish(out.stats, soil, ground, *wheel);
    return out;
  }

  // Tow: free to roll about its axle and move along x; the towing force holds the speed.
  wheel->setLinearFactor(btVector3(1, 0, 1));
  wheel->setAngularFactor(btVector3(0, 1, 0));
  wheel->setLinearVelocity(btVector3(btScalar(c.speed), 0, 0));
  wheel->setAngularVelocity(btVector3(0, btScalar(c.speed / R), 0));
  const auto tow_steps = static_cast<std::int64_t>(std::lround(c.distance / c.speed / h));
  double depth_sum = 0.0, impulse_sum = 0.0;
  std::int64_t samples = 0;
  for (std::int64_t k = 0; k < tow_steps; ++k) {
    // Towing impulse that restores the speed lost in the previous substep.
    const double pull = mass * (c.speed - double(wheel->getLinearVelocity().x()));
    wheel->applyCentralImpulse(btVector3(btScalar(pull), 0, 0));
    advance(world, ground, h, out.stats);
    if (k >= tow_steps / 2) {
      depth_sum += -(wheel->getCenterOfMassPosition().z() - R);
      impulse_sum += pull;
      ++samples;
    }
  }
  out.sinkage = depth_sum / double(std::max<std::int64_t>(samples, 1));
  out.resistance = impulse_sum / (double(std::max<std::int64_t>(samples, 1)) * h);
  // The rut: soil depth along the centre line over the middle of the track.
  const double x_end = wheel->getCenterOfMassPosition().x();
  double rut = 0.0;
  int n = 0;
  for (double x = 0.25 * x_end; x <= 0.6 * x_end; x += c.run.cell) {
    const auto i = soil.column_i(x), j = soil.column_j(0.5 * c.run.cell);
    rut += soil.base_height(i, j) - soil.height(i, j);
    ++n;
  }
  out.rut_depth = n ? rut / n : 0.0;
  out.reference_sinkage = terrain::bekker::wheel_sinkage_rolling(c.run.material, c.load, c.diameter, c.width);
  out.reference_resistance =
      terrain::bekker::wheel_compaction_resistance(c.run.material, out.reference_sinkage, c.width);
  finish(out.stats, soil, ground, *wheel);
  return out;
}

SphereDropResult run_sphere_drop(const SphereDropCase& c) {
  SphereDropResult out;
  terrain::Terrain soil(soil_settings(c.run));
  BulletWorld world(kGravity);
  bullet::TerrainCoupling ground(world.world(), soil);
  const double R = c.diameter / 2, h = c.run.substep;
  btRigidBody* ball =
      world.add_body(std::make_unique<btSphereShape>(btScalar(R)), c.mass, btVector3(0, 0, btScalar(R + c.height)));
  ball->setActivationState(DISABLE_DEACTIVATION);
  ground.add_body(ball);
  const auto steps = static_cast<std::int64_t>(std::lround(c.seconds / h));
  for (std::int64_t k = 0; k < steps; ++k) advance(world, ground, h, out.stats);
  out.depth = -(ball->getCenterOfMassPosition().z() - R);
  out.reference = sphere_drop_reference_depth(c.run.material, c.diameter, c.mass, c.height);
  out.energy_lost = c.mass * kGravity * (c.height + out.depth);
  const double crater =
      out.depth < R ? 2.0 * std::sqrt(std::max(0.0, 2 * R * out.depth - out.depth * out.depth)) : c.diameter;
  const std::int64_t span = soil.column_i(R) + 2;
  out.plastic_work = plastic_work_in(soil, {-span, -span, int(2 * span + 1), int(2 * span + 1)}, crater);
  finish(out.stats, soil, ground, *ball);
  return out;
}

double sphere_drop_reference_depth(const terrain::Material& m, double diameter, double mass, double height,
                                   double gravity) {
  const double R = diameter / 2, n = m.bekker_n;
  // Work to press the sphere to depth z, each column loaded up to its cap depth.
  auto work = [&](double z) {
    const double a = z < R ? std::sqrt(2 * R * z - z * z) : R;
    if (a <= 0.0) return 0.0;
    const double k = m.bekker_kc / (2 * a) + m.bekker_kphi;
    constexpr int kRings = 4000;
    double w = 0.0;
    for (int q = 0; q < kRings; ++q) {
      const double r = (q + 0.5) * a / kRings;
      const double zc = z - (R - std::sqrt(R * R - r * r));
      if (zc > 0) w += k * std::pow(zc, n + 1) / (n + 1) * 2 * std::numbers::pi * r * (a / kRings);
    }
    return w;
  };
  double lo = 0.0, hi = 10.0 * diameter;
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    (work(mid) < mass * gravity * (height + mid) ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace shore::cases
