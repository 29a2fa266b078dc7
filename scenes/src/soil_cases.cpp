#include "shore/scenes/soil_cases.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "shore/bullet/terrain_coupling.h"
#include "shore/scenes/state.h"
#include "shore/scenes/world.h"
#include "shore/terrain/bekker.h"
#include "shore/terrain/terrain.h"

namespace shore::scenes {

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

bullet::TerrainCouplingSettings coupling_settings(const SoilRun& run) {
  bullet::TerrainCouplingSettings s;
  s.contact = run.contact;
  return s;
}

/// One soil, a world and their coupling: what every soil case runs on.
struct SoilRig {
  explicit SoilRig(const SoilRun& run)
      : soil(soil_settings(run)),
        world(kGravity),
        ground(world.world(), soil, coupling_settings(run)),
        h(run.substep) {}

  /// A body that never sleeps, pressing the soil.
  btRigidBody* add(std::unique_ptr<btCollisionShape> shape, double mass, const btVector3& at) {
    btRigidBody* body = world.add_body(std::move(shape), mass, at);
    body->setActivationState(DISABLE_DEACTIVATION);
    ground.add_body(body);
    return body;
  }

  /// One substep, timed, with the coupling's timings.
  void advance(RunStats& stats) {
    const auto t0 = Clock::now();
    world.step(h);
    stats.wall_seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    stats.add_coupling_times(ground.stats());
    ++stats.substeps;
  }

  void finish(RunStats& stats, const btRigidBody& body) const {
    stats.state_hash = state_hash({.soils = {&soil}, .bodies = {&body}});
    stats.rescues = ground.stats().rescues;
    stats.soil_work = ground.stats().plastic_work;
    stats.shear_work = ground.stats().shear_work;
  }

  terrain::Terrain soil;
  World world;
  bullet::TerrainCoupling ground;
  double h;  // s, the substep
};

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

void RunStats::add_coupling_times(const bullet::TerrainCouplingStats& g) {
  envelope_seconds += g.envelope_seconds;
  terrain_seconds += g.terrain_seconds;
  push_seconds += g.push_seconds;
  plugin_seconds += g.envelope_seconds + g.terrain_seconds + g.push_seconds + g.reaction_seconds;
}

PlateResult run_plate(const PlateCase& c) {
  PlateResult out;
  SoilRig rig(c.run);
  const double half_h = 0.05, mass = c.pressure * c.width * c.width / kGravity;
  // Edges halfway between columns, so the footprint covers exactly (width / cell)^2 columns.
  const double cx = 0.5 * c.run.cell + 0.5 * c.width;
  btRigidBody* plate =
      rig.add(std::make_unique<btBoxShape>(btVector3(btScalar(c.width / 2), btScalar(c.width / 2), btScalar(half_h))),
              mass, btVector3(btScalar(cx), btScalar(cx), btScalar(half_h)));
  const double h = c.run.substep;
  const auto steps = static_cast<std::int64_t>(std::lround((c.ramp_seconds + c.settle_seconds) / h));
  for (std::int64_t k = 0; k < steps; ++k) {
    const double t = double(k) * h;
    if (t < c.ramp_seconds)  // the part of the weight not yet applied is held up
      plate->applyCentralForce(btVector3(0, 0, btScalar(mass * kGravity * (1.0 - t / c.ramp_seconds))));
    rig.advance(out.stats);
  }
  out.sinkage = -(plate->getCenterOfMassPosition().z() - half_h);
  out.reference = c.ramp_seconds > 0 ? terrain::bekker::plate_sinkage(c.run.material, c.width, c.pressure)
                                     : terrain::bekker::plate_sinkage_released(c.run.material, c.width, c.pressure);
  rig.finish(out.stats, *plate);
  return out;
}

WheelResult run_wheel(const WheelCase& c) {
  WheelResult out;
  SoilRig rig(c.run);
  const double R = c.diameter / 2, mass = c.load / kGravity, h = c.run.substep;
  btRigidBody* wheel =
      rig.add(std::make_unique<btCylinderShape>(btVector3(btScalar(R), btScalar(c.width / 2), btScalar(R))), mass,
              btVector3(0, btScalar(0.5 * c.run.cell), btScalar(R)));
  wheel->setLinearFactor(btVector3(0, 0, 1));
  wheel->setAngularFactor(btVector3(0, 0, 0));

  // Press: the load ramps in with the wheel held still.
  const auto ramp_steps = static_cast<std::int64_t>(std::lround(c.ramp_seconds / h));
  const auto settle_steps = static_cast<std::int64_t>(std::lround(0.5 / h));
  for (std::int64_t k = 0; k < ramp_steps + settle_steps; ++k) {
    const double t = double(k) * h;
    if (t < c.ramp_seconds)
      wheel->applyCentralForce(btVector3(0, 0, btScalar(mass * kGravity * (1.0 - t / c.ramp_seconds))));
    rig.advance(out.stats);
  }
  if (!c.towed) {
    out.sinkage = -(wheel->getCenterOfMassPosition().z() - R);
    out.reference_sinkage = terrain::bekker::wheel_sinkage_static(c.run.material, c.load, c.diameter, c.width);
    rig.finish(out.stats, *wheel);
    return out;
  }

  // Tow: free to roll about its axle and move along x; the towing force holds the speed.
  wheel->setLinearFactor(btVector3(1, 0, 1));
  wheel->setAngularFactor(btVector3(0, 1, 0));
  wheel->setLinearVelocity(btVector3(btScalar(c.speed), 0, 0));
  wheel->setAngularVelocity(btVector3(0, btScalar(c.speed / R), 0));
  const auto tow_steps = static_cast<std::int64_t>(std::lround(c.distance / c.speed / h));
  double depth_sum = 0.0, impulse_sum = 0.0, slip_sum = 0.0;
  std::int64_t samples = 0;
  for (std::int64_t k = 0; k < tow_steps; ++k) {
    // Towing impulse that restores the speed lost in the previous substep.
    const double pull = mass * (c.speed - double(wheel->getLinearVelocity().x()));
    wheel->applyCentralImpulse(btVector3(btScalar(pull), 0, 0));
    rig.advance(out.stats);
    if (k >= tow_steps / 2) {
      depth_sum += -(wheel->getCenterOfMassPosition().z() - R);
      impulse_sum += pull;
      const double rim = double(wheel->getAngularVelocity().y()) * R;
      slip_sum += rim != 0.0 ? 1.0 - double(wheel->getLinearVelocity().x()) / rim : 0.0;
      ++samples;
    }
  }
  out.sinkage = depth_sum / double(std::max<std::int64_t>(samples, 1));
  out.resistance = impulse_sum / (double(std::max<std::int64_t>(samples, 1)) * h);
  out.slip = slip_sum / double(std::max<std::int64_t>(samples, 1));
  // The rut: soil depth along the centre line over the middle of the track.
  const double x_end = wheel->getCenterOfMassPosition().x();
  double rut = 0.0;
  int n = 0;
  for (double x = 0.25 * x_end; x <= 0.6 * x_end; x += c.run.cell) {
    const auto i = rig.soil.column_i(x), j = rig.soil.column_j(0.5 * c.run.cell);
    rut += rig.soil.base_height(i, j) - rig.soil.height(i, j);
    ++n;
  }
  out.rut_depth = n ? rut / n : 0.0;
  out.reference_sinkage = terrain::bekker::wheel_sinkage_rolling(c.run.material, c.load, c.diameter, c.width);
  out.reference_resistance =
      terrain::bekker::wheel_compaction_resistance(c.run.material, out.reference_sinkage, c.width);
  rig.finish(out.stats, *wheel);
  return out;
}

DrivenWheelResult run_driven_wheel(const DrivenWheelCase& c) {
  DrivenWheelResult out;
  SoilRig rig(c.run);
  const double R = c.diameter / 2, mass = c.load / kGravity, h = c.run.substep;
  btRigidBody* wheel =
      rig.add(std::make_unique<btCylinderShape>(btVector3(btScalar(R), btScalar(c.width / 2), btScalar(R))), mass,
              btVector3(0, btScalar(0.5 * c.run.cell), btScalar(R)));
  // Press: the load ramps in with the wheel held still.
  wheel->setLinearFactor(btVector3(0, 0, 1));
  wheel->setAngularFactor(btVector3(0, 0, 0));
  const auto ramp_steps = static_cast<std::int64_t>(std::lround(c.ramp_seconds / h));
  for (std::int64_t k = 0; k < ramp_steps; ++k) {
    const double t = double(k) * h;
    wheel->applyCentralForce(btVector3(0, 0, btScalar(mass * kGravity * (1.0 - t / c.ramp_seconds))));
    rig.advance(out.stats);
  }
  // Drive: omega and the carrier's speed held at the start of every substep. The wheel's
  // inertia about its axle is made huge, so the soil's torque cannot slow it within a
  // substep either: omega is what the rig imposes, the driving torque what the soil takes.
  wheel->setLinearFactor(btVector3(1, 0, 1));
  wheel->setAngularFactor(btVector3(0, 1, 0));
  const btVector3 inertia = wheel->getLocalInertia();
  wheel->setMassProps(btScalar(mass), btVector3(inertia.x(), inertia.y() * btScalar(1e6), inertia.z()));
  wheel->updateInertiaTensor();
  const double omega = c.rim_speed / R, v = (1.0 - c.slip) * c.rim_speed;
  const auto drive_steps = static_cast<std::int64_t>(std::lround(c.distance / v / h));
  double depth = 0.0, pull = 0.0, torque = 0.0, resistance = 0.0;
  std::int64_t samples = 0;
  for (std::int64_t k = 0; k < drive_steps; ++k) {
    const btVector3 u = wheel->getLinearVelocity();
    wheel->setLinearVelocity(btVector3(btScalar(v), 0, u.z()));
    wheel->setAngularVelocity(btVector3(0, btScalar(omega), 0));
    rig.advance(out.stats);
    if (k < drive_steps / 2) continue;
    const bullet::SoilForce f = rig.ground.soil_force(wheel);
    depth += -(wheel->getCenterOfMassPosition().z() - R);
    pull += f.force.x();
    resistance -= f.normal_force.x();
    torque -= f.torque.y();
    ++samples;
  }
  const double n = double(std::max<std::int64_t>(samples, 1));
  out.sinkage = depth / n, out.drawbar_pull = pull / n, out.torque = torque / n, out.resistance = resistance / n;
  rig.finish(out.stats, *wheel);
  return out;
}

SphereDropResult run_sphere_drop(const SphereDropCase& c) {
  SphereDropResult out;
  SoilRig rig(c.run);
  const double R = c.diameter / 2, h = c.run.substep;
  btRigidBody* ball =
      rig.add(std::make_unique<btSphereShape>(btScalar(R)), c.mass, btVector3(0, 0, btScalar(R + c.height)));
  const auto steps = static_cast<std::int64_t>(std::lround(c.seconds / h));
  for (std::int64_t k = 0; k < steps; ++k) rig.advance(out.stats);
  out.depth = -(ball->getCenterOfMassPosition().z() - R);
  out.reference = sphere_drop_reference_depth(c.run.material, c.diameter, c.mass, c.height);
  out.energy_lost = c.mass * kGravity * (c.height + out.depth);
  const double crater =
      out.depth < R ? 2.0 * std::sqrt(std::max(0.0, 2 * R * out.depth - out.depth * out.depth)) : c.diameter;
  const std::int64_t span = rig.soil.column_i(R) + 2;
  out.plastic_work = plastic_work_in(rig.soil, {-span, -span, int(2 * span + 1), int(2 * span + 1)}, crater);
  rig.finish(out.stats, *ball);
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

}  // namespace shore::scenes
