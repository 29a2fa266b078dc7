// A btRaycastVehicle's wheels in a WaterCoupling: each wheel's cylinder floats as Archimedes
// says and its lift reaches the chassis, a car driving through the water makes waves and
// feels the water's drag on its wheels, and bad input and lifetimes are handled.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "shore/bullet/water_coupling.h"
#include "shore/core/error.h"
#include "shore/scenes/raycast_car.h"
#include "shore/scenes/world.h"
#include "shore/water/surface.h"

namespace {

using shore::scenes::RaycastCar;
using shore::scenes::RaycastCarSettings;
using shore::scenes::World;

constexpr double kSubstep = 1.0 / 240, kGravity = 9.81, kDensity = 1000.0, kFloor = -1.0;

/// Still water 0.05 m apart over 8 x 4.8 m around the origin, its rest level at z = 0,
/// 1 m deep (the car stands on a rigid floor at z = -1).
shore::water::SurfaceSettings pond() {
  shore::water::PhysicalParameters phys;
  phys.cell = 0.05;
  phys.depth = -kFloor;
  phys.density = kDensity;
  phys.damping_time = 2.0;
  shore::water::SurfaceSettings ws = shore::water::SurfaceSettings::physical(phys, 161, 97);
  ws.origin_x = -4.0;
  ws.origin_y = -2.4;
  ws.rest_height = 0.0;
  ws.threads = 1;
  return ws;
}

/// The world, its floor, the water and a car standing in it (wheels fully under water).
struct Ford {
  World world{kGravity};
  shore::water::Surface surface{pond()};
  shore::bullet::WaterCoupling water{world.world(), surface};
  RaycastCar car;
  explicit Ford(const RaycastCarSettings& s = {})
      : car((add_floor(world), world), s, btVector3(-1.5f, 0.0f, btScalar(kFloor + 1.1))) {}
  static void add_floor(World& w) {
    w.add_body(std::make_unique<btBoxShape>(btVector3(20, 20, 0.5)), 0.0, btVector3(0, 0, btScalar(kFloor - 0.5)));
  }
  [[nodiscard]] std::array<double, 4> widths() const {
    const double b = car.settings().wheel_width;
    return {b, b, b, b};
  }
  void run(double seconds) {
    for (int k = 0; k < static_cast<int>(std::lround(seconds / kSubstep)); ++k) world.step(kSubstep);
  }
};

// Standing in 1 m of water, each 0.4 x 0.3 m wheel is under water whole: the water lifts it
// by rho g pi r^2 b, and the suspensions carry the car's weight less the four lifts.
TEST(VehicleWater, WheelsFloatAsArchimedesSaysAndLiftTheCar) {
  Ford f;
  shore::bullet::WaterBodySettings still;
  still.disturb = false;
  f.water.add_vehicle(&f.car.vehicle(), f.widths(), still);
  f.run(2.0);
  const RaycastCarSettings& s = f.car.settings();
  const double volume = std::numbers::pi * s.wheel_radius * s.wheel_radius * s.wheel_width;
  double lift = 0.0, suspension = 0.0;
  for (int k = 0; k < 4; ++k) {
    const shore::bullet::BodyWater w = f.water.wheel_water(&f.car.vehicle(), k);
    EXPECT_NEAR(w.submerged_volume, volume, 0.02 * volume) << "wheel " << k;
    EXPECT_NEAR(double(w.buoyancy.z()), kDensity * kGravity * volume, 0.02 * kDensity * kGravity * volume);
    lift += double(w.force.z());
    suspension += double(f.car.vehicle().getWheelInfo(k).m_wheelsSuspensionForce);
  }
  const double weight = s.mass * kGravity;
  EXPECT_NEAR(suspension, weight - lift, 0.03 * weight) << "lift " << lift << " N";
  EXPECT_EQ(f.water.bodies().size(), 0u);  // wheels are not bodies of the game's
  std::printf("[ wheels in water ] volume %.4f m^3 (pi r^2 b %.4f), suspensions %.0f N = weight %.0f - lift %.0f\n",
              f.water.wheel_water(&f.car.vehicle(), 0).submerged_volume, volume, suspension, weight, lift);
}

// Driven through the water, the wheels push it into waves and the water drags them back.
TEST(VehicleWater, DrivingThroughMakesWavesAndDrag) {
  Ford f;
  f.water.add_vehicle(&f.car.vehicle(), f.widths());
  f.car.drive(1500.0, 0.0, 0.0);
  f.run(1.5);
  const double speed = double(f.car.chassis()->getLinearVelocity().x());
  ASSERT_GT(speed, 0.5);
  double drag = 0.0;
  for (int k = 0; k < 4; ++k) drag += double(f.water.wheel_water(&f.car.vehicle(), k).drag.x());
  EXPECT_LT(drag, 0.0) << "the water drags the wheels back";
  double wave = 0.0;
  for (int j = 0; j < f.surface.ny(); ++j)
    for (int i = 0; i < f.surface.nx(); ++i) wave = std::max(wave, std::abs(f.surface.height(i, j)));
  EXPECT_GT(wave, 0.005) << "the wheels make waves";
  std::printf("[ wheels in water ] at %.2f m/s: drag %.0f N on the wheels, highest wave %.1f mm\n", speed, drag,
              1000.0 * wave);
}

TEST(VehicleWater, BadVehiclesAreRefusedAndLostOnesDropped) {
  Ford f;
  const std::array<double, 4> widths = f.widths();
  const auto field_of = [](auto&& fn) {
    try {
      fn();
    } catch (const shore::InvalidSetting& e) {
      return e.field();
    }
    return std::string("no error");
  };
  EXPECT_EQ(field_of([&] { f.water.add_vehicle(nullptr, widths); }), "bullet.WaterCoupling.add_vehicle(vehicle)");
  const std::array<double, 3> three{0.3, 0.3, 0.3};
  EXPECT_EQ(field_of([&] { f.water.add_vehicle(&f.car.vehicle(), three); }),
            "bullet.WaterCoupling.add_vehicle(widths)");
  const std::array<double, 4> bad{0.3, 0.3, -0.3, 0.3};
  EXPECT_EQ(field_of([&] { f.water.add_vehicle(&f.car.vehicle(), bad); }),
            "bullet.WaterCoupling.add_vehicle(widths[2])");
  f.water.add_vehicle(&f.car.vehicle(), widths);
  EXPECT_EQ(field_of([&] { f.water.add_vehicle(&f.car.vehicle(), widths); }),
            "bullet.WaterCoupling.add_vehicle(vehicle)");
  shore::water::Surface other(pond());
  shore::bullet::WaterCoupling second(f.world.world(), other);
  EXPECT_EQ(field_of([&] { second.add_vehicle(&f.car.vehicle(), widths); }),
            "bullet.WaterCoupling.add_vehicle(vehicle)");
  second.detach();
  // Removed and added again; then its chassis leaves the world: its four wheels are dropped.
  f.water.remove_vehicle(&f.car.vehicle());
  EXPECT_EQ(f.water.wheel_water(&f.car.vehicle(), 0).submerged_volume, 0.0);
  f.water.add_vehicle(&f.car.vehicle(), widths);
  f.run(0.1);
  EXPECT_GT(f.water.wheel_water(&f.car.vehicle(), 0).submerged_volume, 0.0);
  EXPECT_EQ(f.water.wheel_water(&f.car.vehicle(), 4).submerged_volume, 0.0);  // a bad index
  f.world.world().removeRigidBody(f.car.chassis());
  f.run(0.1);
  EXPECT_EQ(f.water.stats().lost_bodies, 4);
  EXPECT_EQ(f.water.wheel_water(&f.car.vehicle(), 0).submerged_volume, 0.0);
  f.world.world().addRigidBody(f.car.chassis());  // the car's destructor takes it out again
}

}  // namespace
