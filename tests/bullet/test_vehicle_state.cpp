// A raycast vehicle's state in a checkpoint (shore/bullet/vehicle_state.h): bad bytes are
// refused naming the source and what is wrong, the vehicle unchanged. That a scene with a
// raycast car continues bit-identically from a checkpoint is tested with the scenes (rally
// in tests/scenes/test_scene_checkpoint.cpp).

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "shore/bullet/vehicle_state.h"
#include "shore/core/error.h"
#include "shore/scenes/raycast_car.h"
#include "shore/scenes/world.h"

namespace {

using shore::scenes::RaycastCar;
using shore::scenes::RaycastCarSettings;

RaycastCarSettings car_settings(bool soil) {
  RaycastCarSettings s;
  s.soil_traction = soil;
  return s;
}

std::string refusal(btRaycastVehicle& v, const std::vector<unsigned char>& bytes) {
  try {
    shore::bullet::restore_vehicle(v, bytes, "car.ckpt");
  } catch (const shore::FileError& e) {
    return e.what();
  }
  return "no error";
}

TEST(VehicleState, BadBytesAreRefusedAndTheVehicleKept) {
  shore::scenes::World world;
  RaycastCar stock(world, car_settings(false), btVector3(0, 0, 1));
  RaycastCar soil(world, car_settings(true), btVector3(0, 5, 1));
  stock.drive(900.0, 0.0, 0.2);
  for (int k = 0; k < 10; ++k) world.step(1.0 / 240);
  const std::vector<unsigned char> saved = shore::bullet::save_vehicle(stock.vehicle());
  const std::vector<unsigned char> before = shore::bullet::save_vehicle(soil.vehicle());
  EXPECT_NE(refusal(soil.vehicle(), saved).find("saved from a stock btRaycastVehicle"), std::string::npos);
  std::vector<unsigned char> cut(saved.begin(), saved.end() - 3);
  EXPECT_NE(refusal(stock.vehicle(), cut).find("car.ckpt"), std::string::npos);
  std::vector<unsigned char> longer = saved;
  longer.push_back(0);
  EXPECT_NE(refusal(stock.vehicle(), longer).find("bytes after the last wheel"), std::string::npos);
  EXPECT_EQ(shore::bullet::save_vehicle(soil.vehicle()), before);  // untouched by the refusals
  // The steering and engine force the game gave come back with the state.
  RaycastCar again(world, car_settings(false), btVector3(0, -5, 1));
  shore::bullet::restore_vehicle(again.vehicle(), saved, "car.ckpt");
  EXPECT_EQ(again.vehicle().getWheelInfo(0).m_steering, stock.vehicle().getWheelInfo(0).m_steering);
  EXPECT_EQ(again.vehicle().getWheelInfo(3).m_engineForce, btScalar(900.0));
  EXPECT_EQ(shore::bullet::save_vehicle(again.vehicle()), saved);
}

}  // namespace
