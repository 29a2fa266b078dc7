#include "shore/scenes/multibody_cases.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include "shore/bullet/terrain_coupling.h"
#include "shore/core/error.h"
#include "shore/scenes/validation_matrix.h"
#include "shore/scenes/world.h"
#include "shore/terrain/bekker.h"
#include "shore/terrain/terrain.h"

namespace shore::scenes {
namespace {

constexpr double kGravity = 9.81;
using Clock = std::chrono::steady_clock;

/// A soil, a Featherstone world (its ground the coupling's frame) and their coupling.
struct LinkRig {
  explicit LinkRig(const SoilRun& run)
      : world(kGravity, run.coupling.frame, Dynamics::featherstone),
        soil(run.terrain),
        ground(world.world(), soil, run.coupling) {}
  /// One substep, timed into stats.
  void advance(double h, RunStats& stats) {
    const auto t0 = Clock::now();
    world.step(h);
    stats.wall_seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    stats.add_coupling_times(ground.stats());
    ++stats.substeps;
  }
  World world;
  terrain::Terrain soil;
  bullet::TerrainCoupling ground;
};

/// Finalized, undamped (the soil is the only drag), never asleep: added to the world.
btMultiBody* add_undamped(World& world, std::unique_ptr<btMultiBody> mb) {
  mb->finalizeMultiDof();
  mb->setLinearDamping(0);
  mb->setAngularDamping(0);
  return world.add_multibody(std::move(mb));
}

btVector3 box_inertia(double mass, const btVector3& half) {
  btVector3 inertia;
  btBoxShape(half).calculateLocalInertia(btScalar(mass), inertia);
  return inertia;
}

/// The share of a weight eased in over `ramp` s at time t: smoothstep to the power n (the
/// plate's sinkage then grows evenly and it arrives at rest).
double eased_share(double t, double ramp, double n) {
  const double u = std::min(1.0, t / ramp);
  return std::pow(u * u * (3.0 - 2.0 * u), n);
}

}  // namespace

SoilRun MultiBodyPlateCase::sandy_loam_run() {
  SoilRun run;
  for (const MatrixSoil& s : matrix_soils())
    if (s.name == "sandy loam 22 %") run.terrain.material = s.material;
  return run;
}

MultiBodyPlateResult run_multibody_plate(const MultiBodyPlateCase& c) {
  if (!(c.width > 0.0 && c.pressure > 0.0 && c.ramp_seconds > 0.0 && c.settle_seconds >= 0.0))
    throw InvalidSetting("scenes.run_multibody_plate(case)", "a non-positive width, pressure or time",
                         "width, pressure and ramp_seconds > 0, settle_seconds >= 0");
  LinkRig rig(c.run);
  const bullet::GroundFrame& frame = c.run.coupling.frame;
  const double h = c.run.substep, half_h = 0.05, mass = c.pressure * c.width * c.width / kGravity;
  const double cx = 0.5 * c.run.terrain.cell + 0.5 * c.width;  // edges halfway between column centres
  const btVector3 half(btScalar(c.width / 2), btScalar(c.width / 2), btScalar(half_h));
  auto base = std::make_unique<btMultiBody>(0, btScalar(mass), box_inertia(mass, half), false, false);
  base->setBasePos(frame.to_world()(btVector3(btScalar(cx), btScalar(cx), half.z())));
  base->setWorldToBaseRot(frame.to_world().getRotation().inverse());
  btMultiBody* mb = add_undamped(rig.world, std::move(base));
  btMultiBodyLinkCollider* plate = rig.world.add_collider(mb, -1, std::make_unique<btBoxShape>(half));
  bullet::TerrainBodySettings s;
  s.spray = c.run.body_spray;
  rig.ground.add_link(plate, s);
  const auto steps = static_cast<std::int64_t>(std::lround((c.ramp_seconds + c.settle_seconds) / h));
  RunStats stats;
  for (std::int64_t k = 0; k < steps; ++k) {  // the part of the weight not yet applied is held up
    const double share = eased_share(double(k) * h, c.ramp_seconds, c.run.terrain.material.bekker_n);
    mb->addBaseForce(frame.up() * btScalar(mass * kGravity * (1.0 - share)));
    rig.advance(h, stats);
  }
  MultiBodyPlateResult out;
  out.sinkage = -(double(frame.to_ground()(mb->getBasePos()).z()) - half_h);
  out.bekker = terrain::bekker::plate_sinkage(c.run.terrain.material, c.width, c.pressure);
  out.carried = double(rig.ground.terrain_force(plate).force.dot(frame.up()));
  out.weight = mass * kGravity;
  out.skipped_links = rig.ground.stats().skipped_bodies;
  return out;
}

MultiBodyWheelResult run_multibody_wheel(const WheelCase& c) {
  if (!c.towed)
    throw InvalidSetting("scenes.run_multibody_wheel(case).towed", "false", "the towed case only (towed = true)");
  if (!c.run.coupling.frame.identity())
    throw InvalidSetting("scenes.run_multibody_wheel(case).run.coupling.frame", "not the identity",
                         "this case runs in a Z-up world only");
  LinkRig rig(c.run);
  const double R = c.diameter / 2, mass = c.load / kGravity, h = c.run.substep;
  const double carriage = 0.01 * mass, hanger = 0.01 * mass, wheel_mass = mass - hanger;
  const btVector3 half(btScalar(R), btScalar(c.width / 2), btScalar(R));
  btVector3 inertia;
  btCylinderShape(half).calculateLocalInertia(btScalar(mass), inertia);  // the rigid wheel's
  const btVector3 small(0.01f, 0.01f, 0.01f), zero(0, 0, 0);
  const btQuaternion none = btQuaternion::getIdentity();
  auto chain = std::make_unique<btMultiBody>(3, btScalar(1.0), small, true, false);
  chain->setBasePos(btVector3(0, btScalar(0.5 * c.run.terrain.cell), btScalar(R)));
  chain->setupPrismatic(0, btScalar(carriage), small, -1, none, btVector3(1, 0, 0), zero, zero, true);
  chain->setupPrismatic(1, btScalar(hanger), small, 0, none, btVector3(0, 0, 1), zero, zero, true);
  chain->setupRevolute(2, btScalar(wheel_mass), inertia, 1, none, btVector3(0, 1, 0), zero, zero, true);
  btMultiBody* mb = add_undamped(rig.world, std::move(chain));
  btMultiBodyLinkCollider* wheel = rig.world.add_collider(mb, 2, std::make_unique<btCylinderShape>(half));
  bullet::TerrainBodySettings s;
  s.spray = c.run.body_spray;
  rig.ground.add_link(wheel, s);
  MultiBodyWheelResult out;
  // Press: the load ramps in with the wheel held still.
  const auto press_steps = static_cast<std::int64_t>(std::lround((c.ramp_seconds + 0.5) / h));
  for (std::int64_t k = 0; k < press_steps; ++k) {
    const double t = double(k) * h;
    mb->setJointVel(0, 0);
    mb->setJointVel(2, 0);
    if (t < c.ramp_seconds)
      mb->addLinkForce(2, btVector3(0, 0, btScalar((hanger + wheel_mass) * kGravity * (1.0 - t / c.ramp_seconds))));
    rig.advance(h, out.stats);
  }
  // Tow: the carriage's speed restored at the start of every substep (an impulse along x
  // alone: the chain's mass matrix is diagonal, every centre on the axle).
  mb->setJointVel(0, btScalar(c.speed));
  mb->setJointVel(2, btScalar(c.speed / R));
  const double towed_mass = carriage + hanger + wheel_mass;
  const auto tow_steps = static_cast<std::int64_t>(std::lround(c.distance / c.speed / h));
  double depth = 0.0, impulse = 0.0;
  std::int64_t samples = 0;
  for (std::int64_t k = 0; k < tow_steps; ++k) {
    const double pull = towed_mass * (c.speed - double(mb->getJointVel(0)));
    mb->setJointVel(0, btScalar(c.speed));
    rig.advance(h, out.stats);
    if (k < tow_steps / 2) continue;
    depth += -(double(wheel->getWorldTransform().getOrigin().z()) - R);
    impulse += pull;
    ++samples;
  }
  const double n = double(std::max<std::int64_t>(samples, 1));
  out.sinkage = depth / n;
  out.resistance = impulse / (n * h);
  out.skipped_links = rig.ground.stats().skipped_bodies;
  return out;
}

}  // namespace shore::scenes
