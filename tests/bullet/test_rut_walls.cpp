// A raycast wheel that drifts into the wall of a rut is pushed back into it: each loaded
// column under the wheel pushes along its surface's normal, which on a rut's wall leans
// towards the rut's middle. On even ground the push is nothing beyond Bullet's own.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>

#include "shore/bullet/terrain_coupling.h"
#include "shore/scenes/raycast_car.h"
#include "shore/terrain/terrain.h"
#include "soil_rig.h"

namespace {

using shore::scenes::RaycastCar;
using shore::scenes::RaycastCarSettings;

constexpr double kSubstep = 1.0 / 240, kRutDepth = 0.05, kRutHalfWidth = 0.17;  // a 0.3 m wheel's rut, 2 cm to spare

RaycastCarSettings car_settings(bool soil_traction) {
  RaycastCarSettings s;  // 800 kg, wheels D 0.8 m, b 0.3 m at y = +-0.75 m
  s.soil_traction = soil_traction;
  return s;
}

/// Two straight ruts along x under the car's wheel tracks (y = +-track_half), 5 cm deep.
void cut_ruts(shore::terrain::Terrain& soil, const RaycastCarSettings& s) {
  const double cell = soil.settings().cell;
  for (std::int64_t j = soil.column_j(-1.2); j <= soil.column_j(1.2); ++j)
    for (std::int64_t i = soil.column_i(-3.0); i <= soil.column_i(16.0); ++i) {
      const double y = soil.column_y(j);
      if (std::abs(std::abs(y) - s.track_half) <= kRutHalfWidth - 0.5 * cell) soil.set_height(i, j, -kRutDepth);
    }
}

/// The car's lateral place: the mean y of its four wheels' contact points.
double track_y(const RaycastCar& car) {
  double y = 0.0;
  for (int k = 0; k < 4; ++k) y += double(car.vehicle().getWheelInfo(k).m_raycastInfo.m_contactPointWS.y()) / 4;
  return y;
}

struct RutRun {
  double start_y = 0.0, end_y = 0.0;  ///< m, track_y after the first second and at the end
  double side_push_y = 0.0;           ///< N, the four wheels' rut-wall push along y, mean over the run
};

/// The four wheels' rut-wall push along y, N.
double side_push_y(const shore::bullet::TerrainCoupling& coupling, const RaycastCar& car) {
  double sum = 0.0;
  for (int k = 0; k < 4; ++k)
    sum += coupling.wheel_side_push(&car.vehicle(), k) *
           double(car.vehicle().getWheelInfo(k).m_raycastInfo.m_wheelAxleWS.y());
  return sum;
}

/// The car set down `offset` m to the side of the ruts (or on even soil), standing or rolling
/// along x at 2 m/s with `engine_force` on its rear wheels, for `seconds`.
RutRun drive_off_line(bool ruts, bool soil_traction, double offset, double engine_force, double seconds) {
  SoilRig rig(shore::terrain::Material::sand());
  const RaycastCarSettings s = car_settings(soil_traction);
  if (ruts) cut_ruts(rig.soil, s);
  RaycastCar car(rig.world, s,
                 btVector3(0, btScalar(offset), btScalar(s.suspension_rest + s.wheel_radius - s.connection_height)));
  const std::array<double, 4> widths{s.wheel_width, s.wheel_width, s.wheel_width, s.wheel_width};
  rig.coupling.add_vehicle(&car.vehicle(), widths);
  RutRun run;
  if (engine_force > 0.0) car.chassis()->setLinearVelocity(btVector3(2, 0, 0));
  car.drive(engine_force, 0.0, 0.0);
  const int steps = static_cast<int>(seconds * 240);
  for (int n = 0; n < steps; ++n) {
    rig.world.step(kSubstep);
    run.side_push_y += side_push_y(rig.coupling, car) / steps;
    if (n == 239) run.start_y = track_y(car);
  }
  run.end_y = track_y(car);
  return run;
}

// Standing with its wheels 6 cm up the ruts' +y walls, the walls push the car towards -y;
// on even soil, 8 cm to the side of nothing, the push is nothing beyond Bullet's own (its
// own sinkage's walls stand on both sides of each wheel and cancel).
TEST(RutWalls, PushAStandingWheelBackIntoItsRut) {
  const RutRun rut = drive_off_line(true, false, 0.08, 0.0, 1.0), even = drive_off_line(false, false, 0.08, 0.0, 1.0);
  const double weight = car_settings(false).mass * 9.81;
  std::printf("[ rut walls ] standing 8 cm off the ruts' line: %.0f N along y; on even soil %.1f N (weight %.0f N)\n",
              rut.side_push_y, even.side_push_y, weight);
  EXPECT_LT(rut.side_push_y, -0.05 * weight) << "N: the +y walls must push the car towards -y";
  EXPECT_GT(rut.side_push_y, -weight) << "N: at most the weight";
  EXPECT_LT(std::abs(even.side_push_y), 0.002 * weight) << "N: even soil pushes nothing sideways";
}

// Rolling along the ruts 8 cm off their line, a SoilVehicle (its side force the soil's shear,
// mobilised by sideways slip) is pushed back towards their line all the way; on even soil the
// pushes cancel. The car does not centre in the ruts: pushed by a few % of its weight it
// crabs, yawed out of them, and the soil's sideways shear holds it (docs/terrain.md,
// "Raycast wheels").
TEST(RutWalls, PushARollingSoilVehicleTowardsTheRutsLine) {
  const RutRun rut = drive_off_line(true, true, 0.08, 900.0, 3.0), even = drive_off_line(false, true, 0.08, 900.0, 3.0);
  const double weight = car_settings(true).mass * 9.81;
  std::printf(
      "[ rut walls ] rolling 8 cm off the ruts: %.0f N along y, y %.4f -> %.4f m; on even soil %.1f N, "
      "y %.4f -> %.4f m\n",
      rut.side_push_y, rut.start_y, rut.end_y, even.side_push_y, even.start_y, even.end_y);
  EXPECT_LT(rut.side_push_y, -0.01 * weight) << "N: the ruts' +y walls push the car towards -y";
  EXPECT_LT(std::abs(even.side_push_y), 0.2 * std::abs(rut.side_push_y)) << "N: even soil's pushes cancel";
  EXPECT_LT(rut.end_y, 0.07) << "m: no further out of the ruts than it was set down";
}

}  // namespace
