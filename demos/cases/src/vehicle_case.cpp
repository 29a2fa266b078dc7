#include "shore/cases/vehicle_case.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

#include "shore/bullet/terrain_coupling.h"
#include "shore/cases/bullet_world.h"
#include "shore/core/hash.h"

namespace shore::cases {

namespace {
constexpr double kGravity = 9.81;
constexpr int kTileCells = 64;
constexpr double kWheelRadius = 0.3, kWheelWidth = 0.25, kWheelMass = 25.0;
constexpr double kChassisMass = 400.0;
constexpr double kMotorTorque = 600.0;  // N m per wheel

std::shared_ptr<terrain::Terrain> make_soil(const VehicleCase& c, const terrain::Material& m) {
  terrain::TerrainSettings s;
  s.cell = c.cell;
  s.material = m;
  s.threads = c.threads;
  s.tile_columns = kTileCells;
  return std::make_shared<terrain::Terrain>(s);
}
}  // namespace

VehicleResult run_vehicle(const VehicleCase& c, const VehicleFrameCallback& on_substep) {
  VehicleResult out;
  const double tile = kTileCells * c.cell;
  out.sand_x0 = 0.0;
  out.sand_x1 = c.sand_tiles * tile;
  out.mud_x1 = out.sand_x1 + c.mud_tiles * tile;

  BulletWorld world(kGravity);
  // Rigid ground before and after the soft strips: static boxes with their top at z = 0.
  const double half_y = 5.0;
  world.add_body(std::make_unique<btBoxShape>(btVector3(10, btScalar(half_y), 1)), 0.0, btVector3(-10, 0, -1))
      ->setFriction(0.9f);
  world
      .add_body(std::make_unique<btBoxShape>(btVector3(10, btScalar(half_y), 1)), 0.0,
                btVector3(btScalar(out.mud_x1 + 10), 0, -1))
      ->setFriction(0.9f);

  out.soils = {make_soil(c, terrain::Material::sand()), make_soil(c, terrain::Material::mud())};
  bullet::TerrainCouplingSettings sand_settings, mud_settings;
  sand_settings.region = {out.sand_x0, -half_y, out.sand_x1, half_y};
  mud_settings.region = {out.sand_x1, -half_y, out.mud_x1, half_y};
  bullet::TerrainCoupling sand(world.world(), *out.soils[0], sand_settings);
  bullet::TerrainCoupling mud(world.world(), *out.soils[1], mud_settings);

  const double z0 = kWheelRadius + 0.02;
  btRigidBody* chassis = world.add_body(std::make_unique<btBoxShape>(btVector3(1.0f, 0.5f, 0.15f)), kChassisMass,
                                        btVector3(btScalar(c.start_x), 0, btScalar(z0 + 0.25)));
  chassis->setActivationState(DISABLE_DEACTIVATION);
  std::array<btRigidBody*, 4> wheels{};
  std::vector<std::unique_ptr<btHingeConstraint>> hinges;
  const std::array<btVector3, 4> mounts = {btVector3(0.75f, 0.65f, -0.25f), btVector3(0.75f, -0.65f, -0.25f),
                                           btVector3(-0.75f, 0.65f, -0.25f), btVector3(-0.75f, -0.65f, -0.25f)};
  for (int k = 0; k < 4; ++k) {
    const btVector3 at = chassis->getCenterOfMassPosition() + mounts[k];
    wheels[k] = world.add_body(std::make_unique<btCylinderShape>(btVector3(
                                   btScalar(kWheelRadius), btScalar(kWheelWidth / 2), btScalar(kWheelRadius))),
                               kWheelMass, at);
    wheels[k]->setActivationState(DISABLE_DEACTIVATION);
    wheels[k]->setFriction(1.0f);
    hinges.push_back(std::make_unique<btHingeConstraint>(*chassis, *wheels[k], mounts[k], btVector3(0, 0, 0),
                                                         btVector3(0, 1, 0), btVector3(0, 1, 0)));
    // Bullet's hinge motor drives the velocity of body A (chassis) relative to body B (wheel)
    // about the axis; the wheel rolls forward (+x) spinning at +v/R about +y relative to the
    // chassis, so the target is -v/R.
    hinges.back()->enableAngularMotor(true, btScalar(-c.target_speed / kWheelRadius),
                                      btScalar(kMotorTorque * c.substep));
    world.world().addConstraint(hinges.back().get(), true);
    sand.add_body(wheels[k]);
    mud.add_body(wheels[k]);
  }

  const auto steps = static_cast<std::int64_t>(std::lround(c.seconds / c.substep));
  double sand_time = 0, sand_dist = 0, mud_time = 0, mud_dist = 0;
  using Clock = std::chrono::steady_clock;
  for (std::int64_t k = 0; k < steps; ++k) {
    const double x_before = chassis->getCenterOfMassPosition().x();
    const auto t0 = Clock::now();
    world.step(c.substep);
    out.stats.wall_seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    for (const bullet::TerrainCoupling* g : {&sand, &mud}) {
      const auto& s = g->stats();
      out.stats.envelope_seconds += s.envelope_seconds;
      out.stats.terrain_seconds += s.terrain_seconds;
      out.stats.push_seconds += s.push_seconds;
      out.stats.plugin_seconds += s.envelope_seconds + s.terrain_seconds + s.push_seconds + s.reaction_seconds;
    }
    ++out.stats.substeps;
    const double x = chassis->getCenterOfMassPosition().x();
    if (x >= out.sand_x0 && x < out.sand_x1) {
      sand_time += c.substep;
      sand_dist += x - x_before;
    } else if (x >= out.sand_x1 && x < out.mud_x1) {
      mud_time += c.substep;
      mud_dist += x - x_before;
    }
    if (on_substep) {
      VehicleFrame f;
      f.substep = k + 1;
      f.substeps = steps;
      f.time = double(k + 1) * c.substep;
      f.chassis = chassis;
      for (int w = 0; w < 4; ++w) f.wheels[w] = wheels[w];
      f.soils = &out.soils;
      on_substep(f);
    }
  }
  out.sim_seconds = double(steps) * c.substep;
  out.distance = chassis->getCenterOfMassPosition().x() - c.start_x;
  out.mean_speed_sand = sand_time > 0 ? sand_dist / sand_time : 0.0;
  out.mean_speed_mud = mud_time > 0 ? mud_dist / mud_time : 0.0;

  StateHash hash;
  for (const auto& soil : out.soils) hash.add(soil->state_hash());
  for (btRigidBody* b : {chassis, wheels[0], wheels[1], wheels[2], wheels[3]}) {
    const btTransform& t = b->getWorldTransform();
    for (int a = 0; a < 3; ++a) {
      hash.add(double(t.getOrigin()[a]));
      if (!std::isfinite(t.getOrigin()[a])) ++out.nan_count;
    }
    if (t.getOrigin().z() < -1.0) ++out.fallthrough_count;  // below any bedrock of this scene
  }
  out.fallthrough_count += sand.stats().rescues + mud.stats().rescues;
  out.stats.state_hash = hash.value();
  out.stats.rescues = sand.stats().rescues + mud.stats().rescues;
  // Deepest sinkage left in either soil along the track.
  for (const auto& soil : out.soils)
    for (double x = out.sand_x0; x < out.mud_x1; x += c.cell)
      for (double y : {-0.65, 0.65})
        for (double dy = -kWheelWidth / 2; dy <= kWheelWidth / 2; dy += c.cell) {
          const auto i = soil->column_i(x), j = soil->column_j(y + dy);
          out.max_sinkage = std::max(out.max_sinkage, soil->sinkage(i, j));
        }
  for (auto& h : hinges) world.world().removeConstraint(h.get());
  return out;
}

}  // namespace shore::cases
