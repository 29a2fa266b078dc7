// A SoilVehicle on Shore's soft ground grips as the soil does: its wheels' pull, torque and
// sinkage against Wong and Reece's driven wheel, its side force against the soil's
// strength, and bad input refused.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <memory>

#include "shore/bullet/soil_vehicle.h"
#include "shore/bullet/terrain_coupling.h"
#include "shore/core/error.h"
#include "shore/scenes/raycast_car.h"
#include "shore/scenes/raycast_cases.h"
#include "shore/scenes/soil_cases.h"
#include "shore/scenes/wong_reece.h"
#include "shore/scenes/world.h"
#include "shore/terrain/bekker.h"
#include "shore/terrain/terrain.h"
#include "soil_rig.h"

namespace {

using shore::bullet::SoilVehicle;
using shore::scenes::RaycastCar;
using shore::scenes::RaycastCarSettings;
using shore::scenes::World;

constexpr double kGravity = 9.81, kSubstep = 1.0 / 240;

/// Wong and Reece's wheel (D 0.6 m, b 0.15 m) under each corner of a car carrying 1 kN each.
RaycastCarSettings wong_reece_car() {
  const shore::scenes::WongReeceWheel w;
  RaycastCarSettings s;
  s.mass = 4 * w.load / kGravity;
  s.wheel_radius = w.radius;
  s.wheel_width = w.width;
  s.soil_traction = true;
  return s;
}

using Rig = SoilRig;

SoilVehicle& soil_vehicle(RaycastCar& car) { return dynamic_cast<SoilVehicle&>(car.vehicle()); }

std::array<double, 4> widths(const RaycastCarSettings& s) {
  return {s.wheel_width, s.wheel_width, s.wheel_width, s.wheel_width};
}

/// A car standing on the rig's flat soil (its wheels touching z = 0 at rest length), its
/// vehicle added to the coupling with every wheel's width.
std::unique_ptr<RaycastCar> car_on(Rig& rig, const RaycastCarSettings& s) {
  auto car = std::make_unique<RaycastCar>(
      rig.world, s, btVector3(0, 0, btScalar(s.suspension_rest + s.wheel_radius - s.connection_height)));
  rig.coupling.add_vehicle(&car->vehicle(), widths(s));
  return car;
}

/// The car towed at 0.5 m/s with every wheel held at the spin of `slip`, measured on its
/// front wheels (they meet fresh soil, as Wong and Reece's wheel does) over the second half.
shore::scenes::RaycastTowResult run_driven(double slip) {
  shore::scenes::RaycastTowCase c;
  c.car = wong_reece_car();
  c.speed = 0.5;
  c.seconds = 4.0;
  c.average_from = 0.5;
  c.slip = slip;
  return shore::scenes::run_raycast_tow(c);
}

// Wong and Reece's driven wheel (D 0.6 m, b 0.15 m, dry sand) at fixed slips: torque within
// 15 %, sinkage within 20 % and growing with slip, drawbar pull within the target's 0.08 W
// of Wong-Reece's (0.057 to 0.077 W above it: the column model's stresses sit closer to the
// bottom of the rim than Wong and Reece's at any slip, so it resists less: docs/terrain.md,
// "Raycast wheels").
TEST(SoilVehicle, DrivenWheelsPullAsWongAndReecePredict) {
  double last_sinkage = 0.0;
  for (const double slip : {0.1, 0.2, 0.3, 0.5}) {
    const shore::scenes::RaycastTowResult run = run_driven(slip);
    shore::scenes::WongReeceWheel ref;
    ref.load = run.load;
    const shore::scenes::WongReeceResult want = shore::scenes::wong_reece(ref, slip);
    std::printf(
        "[ soil vehicle ] slip %.1f (measured %.3f): load %.0f N, pull %.1f N (Wong-Reece %.1f), thrust %.1f N "
        "(%.1f), resistance / load %.3f (%.3f), torque %.1f N m (%.1f), sinkage %.4f m (%.4f)\n",
        slip, run.slip, run.load, run.pull, want.drawbar_pull, run.thrust, want.thrust, -run.resistance / run.load,
        want.resistance / run.load, run.torque, want.torque, run.sinkage, want.sinkage);
    EXPECT_NEAR(run.slip, slip, 0.01) << "the held spin is the slip asked for";
    EXPECT_LT(std::abs(run.pull - want.drawbar_pull) / run.load, 0.08) << "slip " << slip;
    EXPECT_LT(std::abs(run.torque - want.torque) / want.torque, 0.15) << "slip " << slip;
    EXPECT_LT(std::abs(run.sinkage - want.sinkage) / want.sinkage, 0.20) << "slip " << slip;
    EXPECT_GT(run.sinkage, last_sinkage) << "slip " << slip << ": sinkage grows with slip";
    last_sinkage = run.sinkage;
  }
}

// A slipping wheel's soil bears less where the rim has sheared it, most at the bottom, so
// its normal stress peaks ahead of the bottom by more the more it slips, and its compaction
// resistance grows with slip as Wong and Reece's (their peak at (0.43 + 0.32 i) theta_1):
// R / W from slip 0.1 to 0.5 grows by at least theirs (0.034 here) and at most 1.5 times it.
// Loosened by the rim's mean shear alone, the same stress kept its peak at the bottom and
// grew by 0.027.
TEST(SoilVehicle, DrivenWheelsResistMoreTheMoreTheySlipAsWongAndReece) {
  std::array<double, 2> model{}, reference{};
  const std::array<double, 2> slips{0.1, 0.5};
  for (std::size_t k = 0; k < slips.size(); ++k) {
    const shore::scenes::RaycastTowResult run = run_driven(slips[k]);
    shore::scenes::WongReeceWheel ref;
    ref.load = run.load;
    model[k] = -run.resistance / run.load;
    reference[k] = shore::scenes::wong_reece(ref, slips[k]).resistance / run.load;
  }
  const double grows = model[1] - model[0], theirs = reference[1] - reference[0];
  std::printf("[ soil vehicle ] resistance / load at slips 0.1, 0.5: %.3f, %.3f (Wong-Reece %.3f, %.3f)\n", model[0],
              model[1], reference[0], reference[1]);
  EXPECT_GE(grows, theirs) << "R / W grows with slip by " << grows << ", Wong-Reece's by " << theirs;
  EXPECT_LE(grows, 1.5 * theirs) << "R / W grows with slip by " << grows << ", Wong-Reece's by " << theirs;
}

/// A car at rest on sand, pushed sideways at its centre of mass by `share` of what the soil
/// under its wheels can hold, c A + W tan(phi) (A the wheels' contact areas, taken here as
/// Bekker's static contact length times the width). Returns how far its wheels' contacts
/// moved sideways in 2 s (the chassis also rolls on its springs).
double sideways_strength() {
  const shore::terrain::Material m = shore::terrain::Material::sand();
  const RaycastCarSettings s = wong_reece_car();
  const double weight = s.mass * kGravity, sinkage = 0.045;  // m, about Bekker's static sinkage
  const double contact = 2.0 * std::sqrt(2.0 * s.wheel_radius * sinkage);
  return m.cohesion * 4 * contact * s.wheel_width + weight * std::tan(m.friction_angle);
}

double pushed_sideways(double share) {
  Rig rig(shore::terrain::Material::sand());
  const RaycastCarSettings s = wong_reece_car();
  const std::unique_ptr<RaycastCar> owned = car_on(rig, s);
  RaycastCar& car = *owned;
  for (int k = 0; k < 480; ++k) rig.world.step(kSubstep);  // settles into its imprints
  const double hold = sideways_strength();
  auto contacts_y = [&car] {
    double y = 0.0;
    for (int w = 0; w < 4; ++w) y += double(car.vehicle().getWheelInfo(w).m_raycastInfo.m_contactPointWS.y()) / 4;
    return y;
  };
  const double y0 = contacts_y();
  for (int k = 0; k < 480; ++k) {
    car.chassis()->applyCentralForce(btVector3(0, btScalar(share * hold), 0));
    rig.world.step(kSubstep);
  }
  return contacts_y() - y0;
}

// Sideways the soil holds the wheels below its strength and lets them slide beyond it,
// against its shear and the walls of the imprints the wheels stand in, which they bulldoze
// (Bekker's bulldozing resistance, the imprint's depth high and the wheels' contact long).
// Held is not quite still: a standing wheel's shear is mobilised by its sliding speed (it
// keeps no memory of how far it has slid), so at 0.6 of the strength the car creeps while
// the chassis rolls and its uphill wheels carry less (docs/terrain.md).
TEST(SoilVehicle, TheSoilHoldsTheWheelsSidewaysUpToItsStrength) {
  const double held = pushed_sideways(0.6), slid = pushed_sideways(1.5);
  std::printf("[ soil vehicle ] sideways in 2 s: %.4f m at 0.6 of the soil's strength, %.3f m at 1.5\n", held, slid);
  EXPECT_LT(std::abs(held), 0.06) << "m: held by the soil's shear, creeping";
  EXPECT_GT(slid, 20 * std::abs(held)) << "m: beyond the soil's strength it slides";
  // Past the strength it slides at (F - strength - bulldozing) / m, and at most that with
  // 0.78 of the strength once the slid soil has lost its strength (remould_shear_ratio 0.22).
  const RaycastCarSettings s = wong_reece_car();
  const double mass = s.mass, strength = sideways_strength(), t = 2.0, sinkage = 0.045;
  const double contact = 2.0 * std::sqrt(2.0 * s.wheel_radius * sinkage);
  // Bekker's blade is as deep as the wall all along; a wheel's side meets the imprint's wall as
  // a circular segment, z(x) = z (1 - (2x / l)^2) along its chord l, so the cohesive term
  // (linear in z) takes 2/3 of the blade's and the weight term (z^2) 8/15.
  const shore::terrain::Material sand = shore::terrain::Material::sand();
  const double cohesive = shore::scenes::bulldozing_resistance(sand, sinkage, contact, 0.0);
  const double weighty = shore::scenes::bulldozing_resistance(sand, sinkage, contact) - cohesive;
  const double bulldozing = 4 * (2.0 / 3.0 * cohesive + 8.0 / 15.0 * weighty);
  const double least = 0.5 * ((1.5 - 1.0) * strength - bulldozing) / mass * t * t;
  const double most = 0.5 * ((1.5 - 0.78) * strength - bulldozing) / mass * t * t;
  std::printf("[ soil vehicle ] Coulomb on the soil's strength %.0f N and Bekker's bulldozing %.0f N: %.2f to %.2f m\n",
              strength, bulldozing, least, most);
  EXPECT_GT(slid, 0.8 * least) << "m";
  EXPECT_LT(slid, 1.2 * most) << "m";
}

// A four-wheel-drive car at rest in its own prints starts when driven, whatever the column
// size: the engine's thrust against Bekker's rolling compaction resistance moves it at least
// half as far as that balance says in 2 s, and less far than on a bare plane. The wheels'
// thrust is a drive, not a brake: were it limited to stopping the chassis whenever it
// opposes the chassis' motion, a car that rolled back by a rounding's worth while settling
// would get only the push that stops it, substep after substep (on 7 mm sand it stood still
// for the whole 2 s, on 7.5 mm for about a second).
TEST(SoilVehicle, ACarAtRestInItsPrintsStartsWhenDriven) {
  const RaycastCarSettings car;  // the cost case's car: 800 kg, D 0.8 m, b 0.3 m
  const shore::terrain::Material sand = shore::terrain::Material::sand();
  const double load = car.mass * kGravity / 4, force = 500.0, t = 2.0;
  const double rolling =
      shore::terrain::bekker::wheel_sinkage_rolling(sand, load, 2 * car.wheel_radius, car.wheel_width);
  const double resistance = shore::terrain::bekker::wheel_compaction_resistance(sand, rolling, car.wheel_width);
  const double bekker = 0.5 * 4 * (force - resistance) / car.mass * t * t, bare = 0.5 * 4 * force / car.mass * t * t;
  for (const double cell : {0.007, 0.0075, 0.01}) {
    shore::scenes::RaycastCostCase c;
    c.cell = cell;
    c.seconds = t;
    c.engine_force = force;
    const double driven = shore::scenes::run_raycast_cost(c).distance;
    std::printf(
        "[ soil vehicle ] %.4f m cells: %.3f m in %.0f s (Bekker's rolling resistance %.0f N a wheel: %.3f m)\n", cell,
        driven, t, resistance, bekker);
    EXPECT_GT(driven, 0.5 * bekker) << "m, on " << cell << " m columns";
    EXPECT_LT(driven, bare) << "m, on " << cell << " m columns";
  }
}

// A car braked hard at speed on sand and on mud: its wheels lock and skid, and the soil
// stops it as Coulomb on its strength says, each wheel held back by the shear of its
// contact, c A + W tan(phi) (remoulded by the skid to 1 - remould_shear_ratio of it at
// most), plus Bekker's compaction resistance. Stopped, the chassis rocks back on its springs
// and the car creeps back a little, as Bullet's own vehicle does (on a rigid heightfield the
// same car rolls back 8 cm after stopping): at most 5 cm here, and then it stays.
TEST(SoilVehicle, ABrakedCarSkidsToAStopAsCoulombOnTheSoilsStrength) {
  for (const char* name : {"sand", "mud"}) {
    const shore::terrain::Material soil = shore::terrain::Material::preset(name);
    Rig rig(soil);
    RaycastCarSettings s;  // 800 kg, D 0.8 m, b 0.3 m
    s.soil_traction = true;
    const std::unique_ptr<RaycastCar> owned = car_on(rig, s);
    RaycastCar& car = *owned;
    for (int k = 0; k < 240; ++k) rig.world.step(kSubstep);  // settles into its imprints
    const double speed = 3.0, load = s.mass * kGravity / 4;
    car.chassis()->setLinearVelocity(btVector3(btScalar(speed), 0, 0));
    car.drive(0.0, 4 * load * kSubstep, 0.0);  // Bullet's brake, N s a substep: four times the load
    const double x0 = car.chassis()->getCenterOfMassPosition().x();
    double slowest = speed, stopped_at = -1.0;  // m/s, m
    for (int k = 0; k < 480; ++k) {
      rig.world.step(kSubstep);
      const double v = car.chassis()->getLinearVelocity().x();
      slowest = std::min(slowest, v);
      if (stopped_at < 0.0 && v < 1e-3) stopped_at = car.chassis()->getCenterOfMassPosition().x() - x0;
    }
    const double travelled = car.chassis()->getCenterOfMassPosition().x() - x0;
    // The contact: the chord of the wheel sunk to Bekker's rolling sinkage, the wheel's width wide.
    const double sinkage = shore::terrain::bekker::wheel_sinkage_rolling(soil, load, 2 * s.wheel_radius, s.wheel_width);
    const double area = 2.0 * std::sqrt(2.0 * s.wheel_radius * sinkage) * s.wheel_width;
    const double strength = soil.cohesion * area + load * std::tan(soil.friction_angle);
    const double resistance = shore::terrain::bekker::wheel_compaction_resistance(soil, sinkage, s.wheel_width);
    const double longest = speed * speed / (2 * 4 * ((1 - soil.remould_shear_ratio) * strength + resistance) / s.mass);
    const double shortest = speed * speed / (2 * 4 * (strength + resistance) / s.mass);
    std::printf(
        "[ soil vehicle ] %s: braked from %.1f m/s: stopped after %.3f m (Coulomb and Bekker: %.3f to %.3f m), "
        "%.3f m at the end, slowest %.4f m/s\n",
        name, speed, stopped_at, shortest, longest, travelled, slowest);
    EXPECT_GT(stopped_at, 0.9 * shortest) << "m, " << name;
    EXPECT_LT(stopped_at, 1.1 * longest) << "m, " << name;
    EXPECT_GT(travelled, stopped_at - 0.05) << "m: it creeps back at most 5 cm, " << name;
    EXPECT_LT(std::abs(car.chassis()->getLinearVelocity().x()), 1e-3f) << "m/s: and stays, " << name;
  }
}

// On ground that is not soft (a rigid terrain here) a SoilVehicle is Bullet's own vehicle:
// the same trajectory, bit for bit, as a stock btRaycastVehicle driven the same way.
TEST(SoilVehicle, OffSoftGroundItIsBulletsVehicleBitForBit) {
  auto run = [](bool soil) {
    shore::terrain::Material rock = shore::terrain::Material::sand();
    rock.rigid = true;
    Rig rig(rock);
    RaycastCarSettings s = wong_reece_car();
    s.soil_traction = soil;
    RaycastCar car(rig.world, s, btVector3(0, 0, 1.0f));
    rig.coupling.add_vehicle(&car.vehicle(), widths(s));
    car.drive(300.0, 0.0, 0.1);
    for (int k = 0; k < 2 * 240; ++k) rig.world.step(kSubstep);
    return car.chassis()->getCenterOfMassPosition();
  };
  const btVector3 stock = run(false), soil = run(true);
  EXPECT_GT(stock.x(), 0.5f) << "the stock car drove";
  EXPECT_EQ(stock.x(), soil.x());
  EXPECT_EQ(stock.y(), soil.y());
  EXPECT_EQ(stock.z(), soil.z());
}

TEST(SoilVehicle, BadWheelsAndSpinsAreRefusedNamingTheField) {
  Rig rig(shore::terrain::Material::sand());
  RaycastCar car(rig.world, wong_reece_car(), btVector3(0, 0, 1.0f));
  SoilVehicle& v = soil_vehicle(car);
  try {
    v.hold_wheel_spin(4, 1.0);
    FAIL() << "wheel 4 of 4 was taken";
  } catch (const shore::InvalidSetting& e) {
    EXPECT_NE(std::string(e.what()).find("hold_wheel_spin(wheel)"), std::string::npos) << e.what();
  }
  EXPECT_THROW(v.hold_wheel_spin(0, std::nan("")), shore::InvalidSetting);
  EXPECT_THROW(v.release_wheel_spin(-1), shore::InvalidSetting);
  EXPECT_FALSE(v.wheel_traction(7).on_soil) << "a bad index reads as no soil";
}

}  // namespace
