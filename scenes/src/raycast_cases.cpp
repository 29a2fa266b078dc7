#include "shore/scenes/raycast_cases.h"

#include <array>
#include <chrono>
#include <memory>

#include <BulletCollision/CollisionShapes/btStaticPlaneShape.h>

#include "shore/bullet/soil_vehicle.h"
#include "shore/bullet/terrain_coupling.h"
#include "shore/scenes/world.h"
#include "shore/terrain/terrain.h"

namespace shore::scenes {

namespace {

terrain::TerrainSettings flat_soil(const terrain::Material& m, double cell) {
  terrain::TerrainSettings s;
  s.cell = cell;
  s.material = m;
  s.threads = 1;
  return s;
}

/// The chassis' centre with its wheels touching z = 0 at rest length.
btVector3 resting(const RaycastCarSettings& s, double x) {
  return btVector3(btScalar(x), 0, btScalar(s.suspension_rest + s.wheel_radius - s.connection_height));
}

std::array<double, 4> widths(const RaycastCarSettings& s) {
  return {s.wheel_width, s.wheel_width, s.wheel_width, s.wheel_width};
}

void hold_speed(btRigidBody& chassis, double speed) {
  btVector3 v = chassis.getLinearVelocity();
  v.setX(btScalar(speed));
  chassis.setLinearVelocity(v);
}

}  // namespace

RaycastTowResult run_raycast_tow(const RaycastTowCase& c) {
  World world;
  terrain::Terrain soil(flat_soil(c.material, c.cell));
  bullet::TerrainCoupling coupling(world.world(), soil);
  RaycastCar car(world, c.car, resting(c.car, -3.0) + btVector3(0, 0, btScalar(c.drop)),
                 c.soil_raycaster ? &coupling : nullptr);
  coupling.add_vehicle(&car.vehicle(), widths(c.car), car.soil_raycaster());
  auto* soil_vehicle = dynamic_cast<bullet::SoilVehicle*>(&car.vehicle());
  const auto settle = static_cast<int>(std::lround(1.0 / c.substep));
  for (int k = 0; k < settle; ++k) world.step(c.substep);
  if (c.slip >= 0.0 && soil_vehicle != nullptr)
    for (int w = 0; w < 4; ++w) soil_vehicle->hold_wheel_spin(w, c.speed / ((1.0 - c.slip) * c.car.wheel_radius));
  RaycastTowResult out;
  int samples = 0;
  const auto steps = static_cast<int>(std::lround(c.seconds / c.substep));
  const auto from = static_cast<int>(std::lround(c.average_from * steps));
  for (int k = 0; k < steps; ++k) {
    hold_speed(*car.chassis(), c.speed);
    world.step(c.substep);
    if (k < from) continue;
    for (int w = 0; w < 2; ++w) {  // the front wheels
      const btWheelInfo& info = car.vehicle().getWheelInfo(w);
      out.load += double(info.m_wheelsSuspensionForce);
      out.resistance += coupling.wheel_push(&car.vehicle(), w);
      out.sinkage -= double(info.m_raycastInfo.m_contactPointWS.z());
      if (soil_vehicle != nullptr) {
        const bullet::WheelTraction& t = soil_vehicle->wheel_traction(w);
        out.thrust += t.forward, out.torque += t.torque, out.slip += t.slip;
      }
      ++samples;
    }
  }
  const double n = std::max(samples, 1);
  out.load /= n, out.resistance /= n, out.sinkage /= n, out.thrust /= n, out.torque /= n, out.slip /= n;
  out.pull = out.thrust + out.resistance;
  // Between the axles only the front wheel has passed (the rear one runs in its rut, a
  // second pass that Bekker's single-pass sinkage does not describe).
  const double middle = car.chassis()->getCenterOfMassPosition().x();
  int columns = 0;
  for (double x = middle - 0.6; x <= middle + 0.6; x += c.cell, ++columns)
    out.rut -= soil.height(soil.column_i(x), soil.column_j(c.car.track_half));
  out.rut /= std::max(columns, 1);
  return out;
}

RaycastCostResult run_raycast_cost(const RaycastCostCase& c) {
  World world;
  RaycastCarSettings s;
  s.soil_traction = true;
  s.four_wheel_drive = true;
  std::unique_ptr<terrain::Terrain> soil;
  std::unique_ptr<bullet::TerrainCoupling> coupling;
  if (c.on_plane)
    world.add_body(std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), btScalar(0)), 0.0, btVector3(0, 0, 0));
  else {
    soil = std::make_unique<terrain::Terrain>(flat_soil(c.material, c.cell));
    coupling = std::make_unique<bullet::TerrainCoupling>(world.world(), *soil);
  }
  RaycastCar car(world, s, resting(s, 0.0));
  if (coupling) coupling->add_vehicle(&car.vehicle(), widths(s));
  const auto settle = static_cast<int>(std::lround(0.5 / c.substep));
  for (int k = 0; k < settle; ++k) world.step(c.substep);
  car.drive(c.engine_force, 0.0, 0.0);
  const double x0 = car.chassis()->getCenterOfMassPosition().x();
  RaycastCostResult out;
  out.substeps = std::lround(c.seconds / c.substep);
  const auto t0 = std::chrono::steady_clock::now();
  for (std::int64_t k = 0; k < out.substeps; ++k) world.step(c.substep);
  out.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.distance = car.chassis()->getCenterOfMassPosition().x() - x0;
  return out;
}

}  // namespace shore::scenes
