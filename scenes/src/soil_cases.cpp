#include "shore/scenes/soil_cases.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "shore/bullet/terrain_coupling.h"
#include "shore/core/error.h"
#include "shore/scenes/four_wheeler.h"
#include "shore/scenes/state.h"
#include "shore/scenes/world.h"
#include "shore/terrain/bekker.h"
#include "shore/terrain/terrain.h"

namespace shore::scenes {

namespace {
constexpr double kGravity = 9.81;
using Clock = std::chrono::steady_clock;

/// The cases written for a Z-up world alone refuse another ground frame.
void z_up_only(const SoilRun& run, const char* which) {
  if (!run.coupling.frame.identity())
    throw InvalidSetting(std::string("scenes.") + which + ".run.coupling.frame", "not the identity",
                         "this case runs in a Z-up world only (run_plate, run_wheel and run_sphere_drop run in any "
                         "ground frame)");
}

/// The case's soil, prepared (SoilRun::prepare).
terrain::Terrain prepared_soil(const SoilRun& run) {
  terrain::Terrain soil(run.terrain);
  if (run.prepare) run.prepare(soil);
  return soil;
}

/// One soil, a world and their coupling: what every soil case runs on.
struct SoilRig {
  explicit SoilRig(const SoilRun& run)
      : soil(prepared_soil(run)),
        world(kGravity, run.coupling.frame),
        ground(world.world(), soil, run.coupling),
        h(run.substep),
        body_spray(run.body_spray),
        after_substep(run.after_substep),
        substep_seconds(run.substep_seconds) {}

  // A case is written in the ground's coordinates (z up); these take its positions,
  // directions and axis factors into the world's and the body's pose and velocity back. In
  // a Z-up world they are the identity, untouched.
  [[nodiscard]] bool framed() const { return !world.ground().identity(); }
  [[nodiscard]] btVector3 world_dir(const btVector3& v) const {
    return framed() ? world.ground().direction_to_world(v) : v;
  }
  [[nodiscard]] btVector3 ground_dir(const btVector3& v) const {
    return framed() ? world.ground().direction_to_ground(v) : v;
  }
  [[nodiscard]] btVector3 world_axes(const btVector3& factor) const { return world_dir(factor).absolute(); }
  [[nodiscard]] btVector3 ground_position(const btRigidBody& b) const {
    return framed() ? world.ground().to_ground()(b.getCenterOfMassPosition()) : b.getCenterOfMassPosition();
  }

  /// A body that never sleeps, pressing the soil; `at` in the ground's coordinates.
  btRigidBody* add(std::unique_ptr<btCollisionShape> shape, double mass, const btVector3& at) {
    btRigidBody* body =
        framed() ? world.add_body(std::move(shape), mass, world.to_world(btTransform(btQuaternion::getIdentity(), at)))
                 : world.add_body(std::move(shape), mass, at);
    body->setActivationState(DISABLE_DEACTIVATION);
    bullet::TerrainBodySettings b;
    b.spray = body_spray;
    ground.add_body(body, b);
    return body;
  }

  /// A wheel (a cylinder along y) standing on the surface, free only to move up and down.
  btRigidBody* add_held_wheel(double radius, double width, double mass, double cell) {
    btRigidBody* wheel =
        add(std::make_unique<btCylinderShape>(btVector3(btScalar(radius), btScalar(width / 2), btScalar(radius))), mass,
            btVector3(0, btScalar(0.5 * cell), btScalar(radius)));
    wheel->setLinearFactor(world_axes(btVector3(0, 0, 1)));
    wheel->setAngularFactor(btVector3(0, 0, 0));
    return wheel;
  }

  /// `steps` substeps in which the part of the body's weight not yet applied is held up:
  /// the load grows linearly to the whole weight over ramp_seconds (0: all at once).
  void press(btRigidBody& body, double mass, double ramp_seconds, std::int64_t steps, RunStats& stats) {
    for (std::int64_t k = 0; k < steps; ++k) {
      const double t = double(k) * h;
      if (t < ramp_seconds)
        body.applyCentralForce(world_dir(btVector3(0, 0, btScalar(mass * kGravity * (1.0 - t / ramp_seconds)))));
      advance(stats);
    }
  }

  /// One substep, timed, with the coupling's timings.
  void advance(RunStats& stats) {
    const auto t0 = Clock::now();
    world.step(h);
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    stats.wall_seconds += seconds;
    if (substep_seconds != nullptr) substep_seconds->push_back(seconds);
    stats.add_coupling_times(ground.stats());
    ++stats.substeps;
    if (after_substep) after_substep(soil, ground);
  }

  void finish(RunStats& stats, const btRigidBody& body) const {
    stats.state_hash = state_hash({.soils = {&soil}, .bodies = {&body}});
    stats.rescues = ground.stats().rescues;
    stats.soil_work = ground.stats().plastic_work;
    stats.shear_work = ground.stats().shear_work;
    stats.spray = soil.spray_counts();
    stats.spray_seconds = soil.spray_seconds();
  }

  terrain::Terrain soil;
  World world;
  bullet::TerrainCoupling ground;
  double h;  // s, the substep
  bool body_spray;
  std::function<void(const terrain::Terrain&, const bullet::TerrainCoupling&)> after_substep;
  std::vector<double>* substep_seconds;
};

/// Plastic work stored in the soil: sum over columns of cell^2 * integral_0^z p_yield dz,
/// with b the given patch width (rigid-plastic: all of it is dissipated).
double plastic_work_in(const terrain::Terrain& soil, const shore::GridRect& r, double b) {
  const terrain::Material& m = soil.settings().material;
  const double k = m.bekker_kc / b + m.bekker_kphi, n = m.bekker_n, area = soil.settings().cell * soil.settings().cell;
  double w = 0.0;
  for (std::int64_t j = r.j0; j < r.j0 + r.ny; ++j)
    for (std::int64_t i = r.i0; i < r.i0 + r.nx; ++i)  // loose soil (negative sinkage) stores none
      w += area * k * std::pow(std::max(0.0, soil.sinkage(i, j)), n + 1) / (n + 1);
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
  // Edges edge_offset of a cell past column centres (0.5: the footprint covers exactly
  // (width / cell)^2 columns).
  const double cx = c.edge_offset * c.run.terrain.cell + 0.5 * c.width;
  btRigidBody* plate =
      rig.add(std::make_unique<btBoxShape>(btVector3(btScalar(c.width / 2), btScalar(c.width / 2), btScalar(half_h))),
              mass, btVector3(btScalar(cx), btScalar(cx), btScalar(half_h)));
  const double h = c.run.substep;
  const auto steps = static_cast<std::int64_t>(std::lround((c.ramp_seconds + c.settle_seconds) / h));
  if (c.ease && c.ramp_seconds > 0) {
    for (std::int64_t k = 0; k < steps; ++k) {  // the part of the weight not yet applied is held up
      const double u = std::min(1.0, double(k) * h / c.ramp_seconds);
      const double share = std::pow(u * u * (3.0 - 2.0 * u), c.run.terrain.material.bekker_n);
      plate->applyCentralForce(rig.world_dir(btVector3(0, 0, btScalar(mass * kGravity * (1.0 - share)))));
      rig.advance(out.stats);
    }
  } else {
    rig.press(*plate, mass, c.ramp_seconds, steps, out.stats);
  }
  const btVector3 at = rig.ground_position(*plate);
  out.sinkage = -(at.z() - half_h);
  out.drift = double((at - btVector3(btScalar(cx), btScalar(cx), 0)).length() - std::abs(double(at.z())));
  out.reference = c.ramp_seconds > 0
                      ? terrain::bekker::plate_sinkage(c.run.terrain.material, c.width, c.pressure)
                      : terrain::bekker::plate_sinkage_released(c.run.terrain.material, c.width, c.pressure);
  rig.finish(out.stats, *plate);
  return out;
}

WheelResult run_wheel(const WheelCase& c) {
  WheelResult out;
  SoilRig rig(c.run);
  const double R = c.diameter / 2, mass = c.load / kGravity, h = c.run.substep;
  btRigidBody* wheel = rig.add_held_wheel(R, c.width, mass, c.run.terrain.cell);
  // Press: the load ramps in with the wheel held still.
  const auto ramp_steps = static_cast<std::int64_t>(std::lround(c.ramp_seconds / h));
  const auto settle_steps = static_cast<std::int64_t>(std::lround(0.5 / h));
  rig.press(*wheel, mass, c.ramp_seconds, ramp_steps + settle_steps, out.stats);
  if (!c.towed) {
    out.sinkage = -(rig.ground_position(*wheel).z() - R);
    out.reference_sinkage = terrain::bekker::wheel_sinkage_static(c.run.terrain.material, c.load, c.diameter, c.width);
    rig.finish(out.stats, *wheel);
    return out;
  }

  // Tow: free to roll about its axle and move along x; the towing force holds the speed.
  wheel->setLinearFactor(rig.world_axes(btVector3(1, 0, 1)));
  wheel->setAngularFactor(rig.world_axes(btVector3(0, 1, 0)));
  wheel->setLinearVelocity(rig.world_dir(btVector3(btScalar(c.speed), 0, 0)));
  wheel->setAngularVelocity(rig.world_dir(btVector3(0, btScalar(c.speed / R), 0)));
  const auto tow_steps = static_cast<std::int64_t>(std::lround(c.distance / c.speed / h));
  double depth_sum = 0.0, impulse_sum = 0.0, slip_sum = 0.0;
  std::int64_t samples = 0;
  for (std::int64_t k = 0; k < tow_steps; ++k) {
    // Towing impulse that restores the speed lost in the previous substep.
    const double pull = mass * (c.speed - double(rig.ground_dir(wheel->getLinearVelocity()).x()));
    wheel->applyCentralImpulse(rig.world_dir(btVector3(btScalar(pull), 0, 0)));
    rig.advance(out.stats);
    if (k >= tow_steps / 2) {
      depth_sum += -(rig.ground_position(*wheel).z() - R);
      impulse_sum += pull;
      const double rim = double(rig.ground_dir(wheel->getAngularVelocity()).y()) * R;
      slip_sum += rim != 0.0 ? 1.0 - double(rig.ground_dir(wheel->getLinearVelocity()).x()) / rim : 0.0;
      ++samples;
    }
  }
  out.sinkage = depth_sum / double(std::max<std::int64_t>(samples, 1));
  out.resistance = impulse_sum / (double(std::max<std::int64_t>(samples, 1)) * h);
  out.slip = slip_sum / double(std::max<std::int64_t>(samples, 1));
  // The rut: soil depth along the centre line over the middle of the track.
  const double x_end = rig.ground_position(*wheel).x();
  double rut = 0.0;
  int n = 0;
  for (double x = 0.25 * x_end; x <= 0.6 * x_end; x += c.run.terrain.cell) {
    const auto i = rig.soil.column_i(x), j = rig.soil.column_j(0.5 * c.run.terrain.cell);
    rut += rig.soil.base_height(i, j) - rig.soil.height(i, j);
    ++n;
  }
  out.rut_depth = n ? rut / n : 0.0;
  out.reference_sinkage = terrain::bekker::wheel_sinkage_rolling(c.run.terrain.material, c.load, c.diameter, c.width);
  out.reference_resistance =
      terrain::bekker::wheel_compaction_resistance(c.run.terrain.material, out.reference_sinkage, c.width);
  rig.finish(out.stats, *wheel);
  return out;
}

DrivenWheelResult run_driven_wheel(const DrivenWheelCase& c) {
  DrivenWheelResult out;
  z_up_only(c.run, "run_driven_wheel");
  SoilRig rig(c.run);
  const double R = c.diameter / 2, mass = c.load / kGravity, h = c.run.substep;
  btRigidBody* wheel = rig.add_held_wheel(R, c.width, mass, c.run.terrain.cell);
  // Press: the load ramps in with the wheel held still (every step of the ramp is within it).
  rig.press(*wheel, mass, c.ramp_seconds, static_cast<std::int64_t>(std::lround(c.ramp_seconds / h)), out.stats);
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
    const bullet::TerrainForce f = rig.ground.terrain_force(wheel);
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
  ball->setLinearVelocity(rig.world_dir(btVector3(btScalar(c.vx), 0, 0)));
  ball->setAngularVelocity(rig.world_dir(btVector3(0, btScalar(c.spin), 0)));
  const auto steps = static_cast<std::int64_t>(std::lround(c.seconds / h));
  for (std::int64_t k = 0; k < steps; ++k) {
    rig.advance(out.stats);
    out.max_depth = std::max(out.max_depth, -(double(rig.ground_position(*ball).z()) - R));
  }
  out.depth = -(rig.ground_position(*ball).z() - R);
  out.reference = sphere_drop_reference_depth(c.run.terrain.material, c.diameter, c.mass, c.height);
  out.energy_lost = c.mass * kGravity * (c.height + out.depth);
  const double crater =
      out.depth < R ? 2.0 * std::sqrt(std::max(0.0, 2 * R * out.depth - out.depth * out.depth)) : c.diameter;
  const std::int64_t span = rig.soil.column_i(R) + 2;
  out.plastic_work = plastic_work_in(rig.soil, {-span, -span, int(2 * span + 1), int(2 * span + 1)}, crater);
  rig.finish(out.stats, *ball);
  return out;
}

namespace {

/// The shear's share of the work of pressing a column of the crater by its cap depth zc
/// (per unit plan area): the sphere's surface over it is tilted by beta (sin beta = r / R)
/// and slides zc sin(beta) along itself over the soil at rest, as Wong and Reece's rim
/// slides over it; Janosi and Hanamoto's tau on the surface (1 / cos(beta) of the plan area)
/// resists that slide, tau tan(beta) per plan area along the vertical. sigma is Bekker's
/// pressure of the column, normal to the surface, as on the wheels' rims.
double surface_shear_work(const terrain::Material& m, double k, double R, double r, double zc) {
  constexpr int kSteps = 16;  // midpoint rule over the column's sinkage: within 0.01 % of the depth
  const double sin_beta = r / R, tan_beta = r / std::sqrt(R * R - r * r), tan_phi = std::tan(m.friction_angle);
  double w = 0.0;
  for (int q = 0; q < kSteps; ++q) {
    const double u = (q + 0.5) * zc / kSteps;
    const double strength = m.cohesion + k * std::pow(u, m.bekker_n) * tan_phi;
    w += strength * (1.0 - std::exp(-u * sin_beta / m.shear_modulus));
  }
  return w * tan_beta * zc / kSteps;
}

/// Work to press the sphere to depth z, each column loaded up to its cap depth; with_shear:
/// and the surface's shear on each (surface_shear_work, over coarser rings: its depth
/// moves by less than 1e-5 of itself from 400 to 4000), added after the pressure's sum so
/// the pressure's own is the same number either way.
double sphere_press_work(const terrain::Material& m, double R, double z, bool with_shear) {
  const double n = m.bekker_n;
  const double a = z < R ? std::sqrt(2 * R * z - z * z) : R;
  if (a <= 0.0) return 0.0;
  const double k = m.bekker_kc / (2 * a) + m.bekker_kphi;
  const auto cap_depth = [&](double r) { return z - (R - std::sqrt(R * R - r * r)); };
  constexpr int kRings = 4000, kShearRings = 400;
  double w = 0.0, shear = 0.0;
  for (int q = 0; q < kRings; ++q) {
    const double r = (q + 0.5) * a / kRings, zc = cap_depth(r);
    if (zc > 0) w += k * std::pow(zc, n + 1) / (n + 1) * 2 * std::numbers::pi * r * (a / kRings);
  }
  for (int q = 0; with_shear && q < kShearRings; ++q) {
    const double r = (q + 0.5) * a / kShearRings, zc = cap_depth(r);
    if (zc > 0) shear += surface_shear_work(m, k, R, r, zc) * 2 * std::numbers::pi * r * (a / kShearRings);
  }
  return w + shear;
}

/// The depth at which the work of pressing the sphere equals its fall's energy, by bisection.
double sphere_drop_depth(const terrain::Material& m, double diameter, double mass, double height, double gravity,
                         bool with_shear) {
  const double R = diameter / 2;
  double lo = 0.0, hi = 10.0 * diameter;
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    (sphere_press_work(m, R, mid, with_shear) < mass * gravity * (height + mid) ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

double sphere_drop_reference_depth(const terrain::Material& m, double diameter, double mass, double height,
                                   double gravity) {
  return sphere_drop_depth(m, diameter, mass, height, gravity, false);
}

double sphere_drop_reference_depth_with_shear(const terrain::Material& m, double diameter, double mass, double height,
                                              double gravity) {
  return sphere_drop_depth(m, diameter, mass, height, gravity, true);
}

namespace {

/// The soil's rig on a slope: a plane descending along +x (downhill +x) or rising (uphill).
std::shared_ptr<const terrain::HeightSource> plane_descending(double slope) {
  return std::make_shared<terrain::PlaneHeight>(0.0, -std::tan(slope), 0.0);
}

/// Least-squares fit of s(t) = a0 + a1 t + a2 t^2 / 2: returns a2.
double fitted_acceleration(const std::vector<double>& t, const std::vector<double>& s) {
  // Normal equations of the basis (1, t, t^2 / 2), solved by Cramer's rule.
  double m[3][3] = {}, r[3] = {};
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double b[3] = {1.0, t[k], 0.5 * t[k] * t[k]};
    for (int i = 0; i < 3; ++i) {
      r[i] += b[i] * s[k];
      for (int j = 0; j < 3; ++j) m[i][j] += b[i] * b[j];
    }
  }
  auto det3 = [](const double a[3][3]) {
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  };
  double m2[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m2[i][j] = j == 2 ? r[i] : m[i][j];
  const double d = det3(m);
  return d != 0.0 ? det3(m2) / d : 0.0;
}

/// The material for a rigid copy of a case (Bullet's heightfield contact, its friction).
terrain::Material rigid_copy(const terrain::Material& m) {
  terrain::Material r = terrain::Material::rigid_ground();
  r.friction = std::tan(m.friction_angle);
  return r;
}

}  // namespace

SlopeBoxResult run_slope_box(const SlopeBoxCase& c) {
  SlopeBoxResult out;
  SoilRun run = c.run;
  run.terrain.base = plane_descending(c.slope);
  if (c.rigid) run.terrain.material = rigid_copy(c.run.terrain.material);
  z_up_only(run, "run_slope_box");
  SoilRig rig(run);
  const btVector3 normal(btScalar(std::sin(c.slope)), 0, btScalar(std::cos(c.slope)));
  const btVector3 downhill(btScalar(std::cos(c.slope)), 0, btScalar(-std::sin(c.slope)));
  const btQuaternion tilt(btVector3(0, 1, 0), btScalar(c.slope));
  const btScalar half = btScalar(c.size / 2), half_height = btScalar((c.height > 0 ? c.height : c.size) / 2);
  const btVector3 moved = btVector3(0, btScalar(c.offset_across), 0) + downhill * btScalar(c.offset_down);
  btRigidBody* box = rig.world.add_body(std::make_unique<btBoxShape>(btVector3(half, half, half_height)), c.mass,
                                        normal * (half_height + btScalar(1e-3)) + moved, tilt);
  box->setActivationState(DISABLE_DEACTIVATION);
  box->setFriction(1.0f);
  rig.ground.add_body(box);
  const btVector3 start = box->getCenterOfMassPosition();
  const double h = run.substep;
  const auto steps = static_cast<std::int64_t>(std::lround(c.seconds / h));
  std::vector<double> ts, ss;
  for (std::int64_t k = 0; k < steps; ++k) {
    rig.advance(out.stats);
    const btVector3 up = box->getWorldTransform().getBasis().getColumn(2);
    out.max_tilt = std::max(out.max_tilt, double(std::acos(std::clamp(up.dot(normal), btScalar(-1), btScalar(1)))));
    if (k >= steps / 2) {
      ts.push_back(double(k + 1) * h);
      ss.push_back((box->getCenterOfMassPosition() - start).dot(downhill));
    }
  }
  out.acceleration = fitted_acceleration(ts, ss);
  out.end_speed = box->getLinearVelocity().dot(downhill);
  out.distance = (box->getCenterOfMassPosition() - start).dot(downhill);
  rig.finish(out.stats, *box);
  return out;
}

RollingBallResult run_rolling_ball(const RollingBallCase& c) {
  RollingBallResult out;
  SoilRun run = c.run;
  run.terrain.base = plane_descending(c.slope);
  if (c.rigid) run.terrain.material = rigid_copy(c.run.terrain.material);
  z_up_only(run, "run_rolling_ball");
  SoilRig rig(run);
  const double R = c.diameter / 2;
  const btVector3 normal(btScalar(std::sin(c.slope)), 0, btScalar(std::cos(c.slope)));
  const btVector3 downhill(btScalar(std::cos(c.slope)), 0, btScalar(-std::sin(c.slope)));
  btRigidBody* ball = rig.add(std::make_unique<btSphereShape>(btScalar(R)), c.mass, normal * btScalar(R + 1e-3));
  ball->setFriction(1.0f);
  ball->setRollingFriction(0.0f);
  const btVector3 start = ball->getCenterOfMassPosition();
  const auto steps = static_cast<std::int64_t>(std::lround(c.seconds / run.substep));
  double depth = 0.0;
  std::int64_t samples = 0;
  for (std::int64_t k = 0; k < steps; ++k) {
    rig.advance(out.stats);
    if (k < steps / 2) continue;
    depth += R - double(ball->getCenterOfMassPosition().dot(normal));  // the plane passes through the origin
    ++samples;
  }
  out.distance = (ball->getCenterOfMassPosition() - start).dot(downhill);
  out.sinkage = depth / double(std::max<std::int64_t>(samples, 1));
  rig.finish(out.stats, *ball);
  return out;
}

// Bekker's rolling resistance of a ball, by slices. Across the ball's width, a slice at
// lateral offset y is a thin wheel of radius R whose bottom lies z(y) = z0 - y^2 / (2R) deep
// (the ball's cross-section near its bottom). Bekker's rolling wheel, front half bearing,
// carries per unit width w = (3 - n) / 3 k sqrt(2R) z^(n + 1/2) and resists with
// r = k z^(n+1) / (n + 1), k = k_c / b + k_phi with b the patch width 2 sqrt(2 R z0). z0
// makes the slices carry the load normal to the slope, m g cos(theta); the ball then
// rolls with a = (g sin(theta) - R_c / m) / (1 + 2/5) (a solid ball: I = 2/5 m R^2).
RollingBallEstimate rolling_ball_estimate(const terrain::Material& m, double diameter, double mass, double slope,
                                          double seconds, double gravity) {
  const double R = diameter / 2, n = m.bekker_n, load = mass * gravity * std::cos(slope);
  auto integrate = [&](double z0, bool resistance) {
    const double half = std::sqrt(2.0 * R * z0), k = m.bekker_kc / (2.0 * half) + m.bekker_kphi;
    constexpr int kSlices = 2000;
    double sum = 0.0;
    for (int q = 0; q < kSlices; ++q) {
      const double y = -half + (q + 0.5) * 2.0 * half / kSlices;
      const double z = std::max(0.0, z0 - y * y / (2.0 * R));
      sum += resistance ? k * std::pow(z, n + 1.0) / (n + 1.0)
                        : (3.0 - n) / 3.0 * k * std::sqrt(2.0 * R) * std::pow(z, n + 0.5);
    }
    return sum * 2.0 * half / kSlices;
  };
  double lo = 0.0, hi = R;
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    (integrate(mid, false) < load ? lo : hi) = mid;
  }
  RollingBallEstimate e;
  e.sinkage = 0.5 * (lo + hi);
  e.resistance = integrate(e.sinkage, true);
  const double a = (gravity * std::sin(slope) - e.resistance / mass) / 1.4;
  e.distance = a > 0.0 ? 0.5 * a * seconds * seconds : 0.0;
  return e;
}

SidePushResult run_side_push(const SidePushCase& c) {
  SidePushResult out;
  z_up_only(c.run, "run_side_push");
  SoilRig rig(c.run);
  const double R = c.diameter / 2, mass = c.load / kGravity, h = c.run.substep;
  btRigidBody* wheel = rig.add_held_wheel(R, c.width, mass, c.run.terrain.cell);
  rig.press(*wheel, mass, 1.0, std::lround(1.5 / h), out.stats);  // the load in over 1 s, held still
  if (c.in_rut) {                                                 // roll 1.5 m to cut a rut, then stop in it
    wheel->setLinearFactor(btVector3(1, 0, 1));
    wheel->setAngularFactor(btVector3(0, 1, 0));
    const double speed = 1.0;
    for (std::int64_t k = 0, n = std::lround(1.5 / speed / h); k < n; ++k) {
      wheel->setLinearVelocity(btVector3(btScalar(speed), 0, wheel->getLinearVelocity().z()));
      wheel->setAngularVelocity(btVector3(0, btScalar(speed / R), 0));
      rig.advance(out.stats);
    }
    wheel->setLinearFactor(btVector3(0, 0, 1));
    wheel->setAngularFactor(btVector3(0, 0, 0));
    wheel->setLinearVelocity(btVector3(0, 0, 0));
    wheel->setAngularVelocity(btVector3(0, 0, 0));
    for (std::int64_t k = 0, n = std::lround(0.3 / h); k < n; ++k) rig.advance(out.stats);
  }
  out.rut_depth = R - double(wheel->getCenterOfMassPosition().z());
  // Push sideways at a steady speed; the soil's sideways push is the resistance.
  wheel->setLinearFactor(btVector3(0, 1, 1));
  const auto push_steps = static_cast<std::int64_t>(std::lround(c.push_distance / c.push_speed / h));
  double lateral = 0.0;
  std::int64_t samples = 0;
  for (std::int64_t k = 0; k < push_steps; ++k) {
    wheel->setLinearVelocity(btVector3(0, btScalar(c.push_speed), wheel->getLinearVelocity().z()));
    rig.advance(out.stats);
    if (k < push_steps / 2) continue;
    lateral -= rig.ground.terrain_force(wheel).force.y();
    ++samples;
  }
  out.lateral_force = lateral / double(std::max<std::int64_t>(samples, 1));
  rig.finish(out.stats, *wheel);
  return out;
}

double bulldozing_resistance(const terrain::Material& m, double z, double b, double unit_weight) {
  const double phi = m.friction_angle, tan_phi = std::tan(phi), cos2 = std::cos(phi) * std::cos(phi);
  const double nq = std::exp(std::numbers::pi * tan_phi) * std::pow(std::tan(std::numbers::pi / 4 + phi / 2), 2.0);
  const double nc = tan_phi > 0.0 ? (nq - 1.0) / tan_phi : 5.14;
  const double ngamma = 2.0 * (nq + 1.0) * tan_phi;
  const double kpc = (nc - tan_phi) * cos2;
  const double kpgamma = (tan_phi > 0.0 ? 2.0 * ngamma / tan_phi : 0.0) * cos2 + cos2;
  return b * (0.67 * m.cohesion * z * kpc + 0.5 * z * z * unit_weight * kpgamma);
}

VehicleWheel vehicle_wheel() {
  const FourWheelerSettings s;
  return {s.wheel_radius, s.wheel_width, (s.chassis_mass + 4.0 * s.wheel_mass) * kGravity / 4.0};
}

VehicleClimbResult run_vehicle_climb(const VehicleClimbCase& c) {
  VehicleClimbResult out;
  SoilRun run = c.run;
  run.terrain.base = std::make_shared<terrain::PlaneHeight>(0.0, std::tan(c.slope), 0.0);  // rises along +x
  z_up_only(run, "run_vehicle_climb");
  SoilRig rig(run);
  FourWheelerSettings car;
  car.target_speed = c.wheel_speed;
  const btQuaternion tilt(btVector3(0, 1, 0), btScalar(-c.slope));
  const btVector3 normal(btScalar(-std::sin(c.slope)), 0, btScalar(std::cos(c.slope)));
  const btVector3 uphill(btScalar(std::cos(c.slope)), 0, btScalar(std::sin(c.slope)));
  const double rise = car.wheel_radius + 0.25 + 0.01;  // chassis centre above the wheels' bottoms
  bullet::TerrainCoupling* const couplings[] = {&rig.ground};
  const FourWheeler v = build_four_wheeler(rig.world, car, normal * btScalar(rise), tilt, run.substep, couplings);
  const btVector3 start = v.chassis->getCenterOfMassPosition();
  const auto steps = static_cast<std::int64_t>(std::lround(c.seconds / run.substep));
  const auto last = static_cast<std::int64_t>(std::lround(1.0 / run.substep));
  btVector3 at_last = start;
  double slip = 0.0;
  std::int64_t samples = 0;
  for (std::int64_t k = 0; k < steps; ++k) {
    rig.advance(out.stats);
    if (k == steps - last - 1) at_last = v.chassis->getCenterOfMassPosition();
    if (k < steps - last) continue;
    const double ground_speed = double(v.chassis->getLinearVelocity().dot(uphill));
    for (const btRigidBody* w : v.wheels) {
      const double spin = double((w->getAngularVelocity() - v.chassis->getAngularVelocity()).y()) * car.wheel_radius;
      slip += spin > 1e-6 ? 1.0 - ground_speed / spin : 0.0;
      ++samples;
    }
  }
  out.uphill_speed =
      double((v.chassis->getCenterOfMassPosition() - at_last).dot(uphill)) / (double(last) * run.substep);
  out.slip = slip / double(std::max<std::int64_t>(samples, 1));
  out.wheel_load = vehicle_wheel().load;
  rig.finish(out.stats, *v.chassis);
  return out;
}

}  // namespace shore::scenes
