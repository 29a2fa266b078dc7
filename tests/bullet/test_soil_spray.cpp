// Spray through Bullet (shore/terrain/spray.h): volume exact at every substep of a fast
// drop and of a slipping wheel, nothing from bodies at rest, more from faster wheels, the
// same state whatever the threads or the order of add_body, and the switches.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>

#include "shore/bullet/terrain_coupling.h"
#include "shore/scenes/soil_cases.h"
#include "shore/scenes/state.h"
#include "shore/scenes/world.h"

using namespace shore;
using namespace shore::scenes;

namespace {

/// The worst |ground + compacted + airborne + lost - edited| over the volume moved (compacted,
/// net ground change, picked up by spray) at any substep, and the largest airborne volume.
struct VolumeWatch {
  double worst = 0.0, peak_airborne = 0.0, mean_airborne = 0.0;
  long samples = 0;
  void attach(SoilRun& run) {
    run.after_substep = [this](const terrain::Terrain& soil, const bullet::TerrainCoupling&) {
      const terrain::VolumeTotals v = soil.volume();
      const double moved = v.compacted + std::abs(v.ground) + soil.spray_counts().picked_volume;
      if (moved > 0.0) worst = std::max(worst, std::abs(v.total() - v.edited) / moved);
      peak_airborne = std::max(peak_airborne, v.airborne);
      mean_airborne += v.airborne;
      ++samples;
    };
  }
};

constexpr double kG = 9.81;

}  // namespace

// 8 m/s at impact: straight down (height v^2 / 2g), and at 30 degrees from the vertical
// with a horizontal 4 m/s (the ball ploughs, its back lifts out of the sand and sheds).
// How much an impact throws depends on how often the soil samples it: the pieces of the
// ball that touch the soil while still fast load with soil, and the ball is slowed within a
// few milliseconds. Oblique: 7 particles with the soil stepping at 120 Hz, 22 at 240 Hz, 38
// at 480 Hz (docs/terrain.md, "Spray": sampling), so the count is checked at both rates.
TEST(SoilSpray, VolumeIsExactAtEverySubstepOfAnEightMetrePerSecondDrop) {
  for (const double interval : {bullet::TerrainCouplingSettings{}.step_interval, 0.0})
    for (const double vx : {0.0, 4.0}) {
      SphereDropCase c;
      c.vx = vx;
      c.height = (64.0 - vx * vx) / (2.0 * kG);
      c.seconds = 1.2;
      c.run.coupling.step_interval = interval;
      VolumeWatch watch;
      watch.attach(c.run);
      const SphereDropResult r = run_sphere_drop(c);
      EXPECT_LT(watch.worst, 1e-12) << "vx " << vx << ", soil interval " << interval;
      EXPECT_EQ(r.stats.rescues, 0);
      EXPECT_EQ(r.stats.spray.lost, 0);
      if (vx > 0.0) {
        EXPECT_GT(r.stats.spray.created, interval > 0.0 ? 4 : 20)
            << "an oblique 8 m/s impact throws sand (soil interval " << interval << " s)";
        EXPECT_GT(watch.peak_airborne, 0.0);
      }
      EXPECT_EQ(r.stats.spray.particles, 0) << "all landed after " << c.seconds << " s";
    }
}

TEST(SoilSpray, VolumeIsExactAtEverySubstepOfAWheelSpinningAtHalfSlipFor2s) {
  DrivenWheelCase c;
  c.slip = 0.5;
  c.rim_speed = 2.0;
  c.distance = 2.0;  // 2 s at (1 - 0.5) 2 m/s
  VolumeWatch watch;
  watch.attach(c.run);
  const DrivenWheelResult r = run_driven_wheel(c);
  EXPECT_LT(watch.worst, 1e-12);
  EXPECT_GT(r.stats.spray.created, 200) << "a slipping wheel throws a rooster tail";
  EXPECT_GT(r.stats.spray.landed, 100);
  EXPECT_EQ(r.stats.spray.lost, 0);
  EXPECT_GT(watch.peak_airborne, 0.0);
}

TEST(SoilSpray, BodiesAtRestMakeNothing) {
  PlateCase plate;  // released at rest, settles for 1 s
  const PlateResult p = run_plate(plate);
  EXPECT_EQ(p.stats.spray.created, 0);
  EXPECT_EQ(p.stats.spray.picked_volume, 0.0);
  EXPECT_EQ(p.stats.spray.clinging_cells, 0);
  WheelCase wheel;  // pressed statically
  const WheelResult w = run_wheel(wheel);
  EXPECT_EQ(w.stats.spray.created, 0);
  EXPECT_EQ(w.stats.spray.picked_volume, 0.0);
}

TEST(SoilSpray, FasterWheelsThrowMore) {
  double last = 0.0;
  for (const double rim : {1.0, 2.0, 4.0}) {
    DrivenWheelCase c;
    c.slip = 0.5;
    c.rim_speed = rim;
    c.distance = 0.25 * rim;  // 0.5 s of driving
    c.ramp_seconds = 0.5;
    VolumeWatch watch;
    watch.attach(c.run);
    (void)run_driven_wheel(c);
    const double mean = watch.mean_airborne / double(std::max(watch.samples, 1L));
    EXPECT_GT(mean, last) << "mean airborne volume at rim speed " << rim << " m/s";
    last = mean;
  }
}

TEST(SoilSpray, SwitchedOffPerTerrainOrPerBodyNothingSprays) {
  DrivenWheelCase c;
  c.slip = 0.5;
  c.rim_speed = 3.0;
  c.distance = 0.75;
  c.ramp_seconds = 0.5;
  DrivenWheelCase off_terrain = c, off_body = c;
  off_terrain.run.terrain.spray.enabled = false;
  off_body.run.body_spray = false;
  EXPECT_GT(run_driven_wheel(c).stats.spray.created, 0);
  for (const DrivenWheelCase* q : {&off_terrain, &off_body}) {
    const DrivenWheelResult r = run_driven_wheel(*q);
    EXPECT_EQ(r.stats.spray.created, 0);
    EXPECT_EQ(r.stats.spray.picked_volume, 0.0);
  }
}

namespace {

/// A ball thrown in obliquely with backspin and a ball dropped beside it, added to the
/// coupling in either order: the soil's and the bodies' state hash.
std::uint64_t two_balls(int threads, bool reversed) {
  terrain::TerrainSettings s;
  s.threads = threads;
  s.parallel_min_columns = 0;
  s.max_erosion_passes = 4;
  terrain::Terrain soil(s);
  World world(kG);
  bullet::TerrainCoupling ground(world.world(), soil);
  btRigidBody* a = world.add_body(std::make_unique<btSphereShape>(btScalar(0.1)), 10.0, btVector3(0, 0, 0.3));
  btRigidBody* b = world.add_body(std::make_unique<btSphereShape>(btScalar(0.08)), 5.0, btVector3(0.4, 0.5, 0.5));
  a->setLinearVelocity(btVector3(4, 0, -6));
  a->setAngularVelocity(btVector3(0, -20, 0));
  b->setLinearVelocity(btVector3(0, 0, -5));
  for (btRigidBody* body : {a, b}) body->setActivationState(DISABLE_DEACTIVATION);
  ground.add_body(reversed ? b : a);
  ground.add_body(reversed ? a : b);
  for (int k = 0; k < 120; ++k) world.step(1.0 / 240);
  EXPECT_GT(soil.spray_counts().created, 0);
  return state_hash({.soils = {&soil}, .bodies = {a, b}});
}

}  // namespace

TEST(SoilSpray, SameStateForOneTwoFourThreadsAndEitherOrderOfAddBody) {
  const std::uint64_t one = two_balls(1, false);
  EXPECT_EQ(two_balls(2, false), one);
  EXPECT_EQ(two_balls(4, false), one);
  EXPECT_EQ(two_balls(1, true), one);
  EXPECT_EQ(two_balls(4, true), one);
}
