// Hard cases of the soil coupling: nothing falls through, rigid ground is plain Bullet,
// sleeping bodies wake, thread count does not change results, bad bodies are skipped.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <random>
#include <string>

#include "bad_bodies.h"
#include "shore/bullet/heightfield_tile.h"
#include "shore/bullet/terrain_coupling.h"
#include "shore/core/error.h"
#include "shore/scenes/soak.h"
#include "shore/scenes/soil_cases.h"
#include "shore/scenes/stack_cases.h"
#include "shore/scenes/world.h"
#include "shore/terrain/bekker.h"
#include "shore/terrain/terrain.h"

using namespace shore;
using shore::scenes::World;

namespace {
terrain::TerrainSettings soil_of(const char* material, double cell = 0.02) {
  terrain::TerrainSettings s;
  s.cell = cell;
  s.material = terrain::Material::preset(material);
  s.threads = 1;
  return s;
}

}  // namespace

// 1,000 seeded drops of every shape type at up to 50 m/s onto sand, mud and snow: every
// body ends above bedrock. (At 50 m/s a body travels 0.2 m per substep, more than some
// soil depths: such bodies are lifted back onto bedrock by the coupling, by design.)
TEST(SoilRobustness, NothingFallsThrough) {
  std::mt19937 rng(20261122);
  int drops = 0;
  for (const char* material : {"sand", "mud", "snow"})
    for (int batch = 0; batch < 14 && drops < 1000; ++batch) {
      terrain::Terrain soil(soil_of(material, 0.04));           // 4 cm columns: bodies are 10-50 cm
      std::vector<std::unique_ptr<btCollisionShape>> children;  // of compounds: outlive the world
      World world;
      bullet::TerrainCoupling ground(world.world(), soil);
      std::vector<btRigidBody*> bodies;
      std::uniform_real_distribution<double> speed(0.0, 50.0), angle(-3.14, 3.14), lateral(-2.0, 2.0);
      for (int k = 0; k < 24 && drops < 1000; ++k, ++drops) {
        const btVector3 at(btScalar(1.0 * (k % 6)), btScalar(1.0 * (k / 6)), btScalar(0.5 + 0.1 * (k % 3)));
        // One draw per statement, so every compiler makes the same bodies (the order of a
        // call's arguments is unspecified).
        const double az = angle(rng), ay = angle(rng), ax = angle(rng);
        const double mass = 1.0 + 20.0 * double(rng() % 100) / 100.0;
        auto shape = scenes::random_body_shape(rng, children);
        btRigidBody* b =
            world.add_body(std::move(shape), mass, at, btQuaternion(btScalar(ax), btScalar(ay), btScalar(az)));
        const double vz = -speed(rng), vy = lateral(rng), vx = lateral(rng);
        b->setLinearVelocity(btVector3(btScalar(vx), btScalar(vy), btScalar(vz)));
        ground.add_body(b);
        bodies.push_back(b);
      }
      for (int s = 0; s < 120; ++s) world.step(1.0 / 240);  // every body has landed by then
      for (btRigidBody* b : bodies) {
        btVector3 lo, hi;
        b->getCollisionShape()->getAabb(b->getWorldTransform(), lo, hi);
        const btVector3 c = b->getCenterOfMassPosition();
        ASSERT_TRUE(std::isfinite(c.z()));
        EXPECT_GT(lo.z(), soil.bedrock(soil.column_i(c.x()), soil.column_j(c.y())) - 0.02) << material;
      }
    }
  EXPECT_EQ(drops, 1000);
}

// The soak's test version (the 100,000-substep run is shore-bench's reliability
// sweep): 50 bodies of every shape type, 40 dropped onto sand and 10 into a walled pool
// beside it (onto the sand under the water), 2,000 substeps at 1/240 s. Nothing becomes
// non-finite, nothing ends below bedrock, no body needs a rescue once settled (after 2 s),
// the soil's volume is conserved against what compression removed (ground + compacted
// equals the edited volume, 0, to 1e-9 of the moved volume), the pool's volume changes by
// exactly what the bodies displaced (no fixed node, no open edge: to 1e-12 m^3), and the
// soil's and water's memory stop growing once the bodies rest (the last 75 % within 5 %).
TEST(SoilRobustness, SoakOfFiftyBodiesStaysFiniteConservedAndFlat) {
  scenes::SoakCase c;
  c.floating_bodies = 10;
  c.substeps = 2000;
  c.warm_up_substeps = 500;
  const scenes::SoakResult r = scenes::run_soak(c);
  EXPECT_EQ(r.nan_count, 0);
  EXPECT_EQ(r.fall_throughs, 0);
  EXPECT_EQ(r.lost_bodies, 0);
  EXPECT_EQ(r.rescues_after_settling, 0) << "rescues after settling";
  EXPECT_GT(r.soil_moved_volume, 0.0) << "the bodies pressed the sand";
  EXPECT_LE(r.soil_volume_drift, 1e-9 * r.soil_moved_volume) << "moved " << r.soil_moved_volume << " m^3";
  EXPECT_NE(r.water_displaced_volume, 0.0) << "the floating bodies displaced water";
  EXPECT_LE(r.water_volume_drift, 1e-12) << "displaced " << r.water_displaced_volume << " m^3";
  EXPECT_LE(scenes::SoakResult::growth(r.soil_memory_warm, r.soil_memory_max), 0.05)
      << "soil memory grew from " << r.soil_memory_warm << " to " << r.soil_memory_max << " bytes after warm-up";
  EXPECT_LE(scenes::SoakResult::growth(r.water_memory_warm, r.water_memory_max), 0.05)
      << "water memory grew from " << r.water_memory_warm << " to " << r.water_memory_max << " bytes after warm-up";
}

// Bodies on bodies: a stack's weight reaches the soil through Bullet's contacts between the
// boxes, and the bottom box sinks as a rigid-plastic plate released under the whole weight
// (Bekker's, (n+1)^(1/n) past the quasi-static sinkage), on three soils, at the README's
// 1/240 s substeps. (At 1/60 s substeps it sinks 2 to 25 times deeper: shore-bench's
// plugin.stack_sinkage_ratio_60hz and docs/terrain.md, "Bodies on bodies".)
TEST(SoilRobustness, AStackOfBoxesSinksAsOnePlateOfItsWeight) {
  for (const char* soil : {"sand", "mud", "snow"}) {
    scenes::StackCase c;
    c.run.terrain.material = terrain::Material::preset(soil);
    const scenes::StackResult r = scenes::run_stack(c);
    ASSERT_TRUE(r.finite) << soil;
    EXPECT_NEAR(r.sinkage / r.reference, 1.0, 0.1) << soil << ": " << r.sinkage << " m, Bekker " << r.reference << " m";
    EXPECT_LT(r.overlap, 0.01) << soil << ": the boxes sank into each other";
    EXPECT_LT(r.late_speed, 0.05) << soil << ": still moving";
    EXPECT_EQ(r.rescues, 0) << soil;
    std::printf(
        "[ stack ] %s, 3 x 200 kg boxes 0.5 x 0.5 m: bottom box %.4f m, Bekker's released plate %.4f m (%+.1f %%), "
        "boxes overlap <= %.4f m\n",
        soil, r.sinkage, r.reference, 100.0 * (r.sinkage / r.reference - 1.0), r.overlap);
  }
}

namespace {
struct FarResult {
  double sinkage = 0.0;  ///< m, the box's bottom below the untouched surface
  double drift = 0.0;    ///< m, how far the box moved sideways
};
/// A 50 kg box set down on sand `far` m from the origin along x and y, for 4 s at 1/240 s.
FarResult far_from_origin(double far) {
  terrain::Terrain soil(soil_of("sand"));
  World world;
  bullet::TerrainCoupling ground(world.world(), soil);
  const btVector3 half(0.15f, 0.15f, 0.1f), at(btScalar(far + 0.003), btScalar(far - 0.007), half.z());
  btRigidBody* box = world.add_body(std::make_unique<btBoxShape>(half), 50.0, at);
  ground.add_body(box);
  for (int k = 0; k < 4 * 240; ++k) world.step(1.0 / 240);
  const btVector3 x = box->getCenterOfMassPosition();
  return {double(half.z() - x.z()), double(btVector3(x.x() - at.x(), x.y() - at.y(), 0).length())};
}
}  // namespace

// An open world: 10 km from the origin (a float's step there is 1 mm) a box sinks as at the
// origin, as Bekker's plate released at rest says, and stays where it was set down. (What
// moves there is Bullet's float integration's to keep: a ball rolling 8 mm a substep on it
// rolls 5 % farther than at the origin, in steps of 1 mm.)
TEST(SoilRobustness, FarFromTheOriginTheSoilBearsAsAtIt) {
  const FarResult here = far_from_origin(0.0), there = far_from_origin(10000.0);
  const double bekker = terrain::bekker::plate_sinkage_released(terrain::Material::sand(), 0.3, 50 * 9.81 / 0.09);
  EXPECT_NEAR(there.sinkage, here.sinkage, 0.02 * here.sinkage);
  EXPECT_NEAR(there.sinkage, bekker, 0.05 * bekker);
  EXPECT_LT(there.drift, 0.003);
  std::printf("[ far from the origin ] 10 km: box %.5f m (origin %.5f, Bekker's released plate %.5f), drift %.4f m\n",
              there.sinkage, here.sinkage, bekker, there.drift);
}

// On rigid material the coupling leaves Bullet's contact alone: same rest height as a
// plain Bullet heightfield.
TEST(SoilRobustness, RigidGroundBehavesLikeAPlainHeightfield) {
  auto rest_height = [](bool shore_ground) {
    World world;
    std::unique_ptr<terrain::Terrain> soil;
    std::unique_ptr<bullet::TerrainCoupling> ground;
    std::unique_ptr<bullet::HeightfieldTile> plain;
    if (shore_ground) {
      soil = std::make_unique<terrain::Terrain>(soil_of("rigid"));
      ground = std::make_unique<bullet::TerrainCoupling>(world.world(), *soil);
    } else {
      bullet::HeightfieldTileSettings hs;
      hs.columns = 129;
      hs.cell = 0.02;
      hs.origin_x = hs.origin_y = -1.28;
      plain = std::make_unique<bullet::HeightfieldTile>(hs);
      world.world().addCollisionObject(plain->object());
    }
    btRigidBody* box = world.add_body(std::make_unique<btBoxShape>(btVector3(0.2f, 0.15f, 0.1f)), 20.0,
                                      btVector3(0.653f, 0.647f, 0.3f));  // mid-tile: one heightfield, as the plain one
    if (ground) ground->add_body(box);
    for (int s = 0; s < 480; ++s) world.step(1.0 / 240);
    const double z = box->getCenterOfMassPosition().z();
    if (plain) world.world().removeCollisionObject(plain->object());
    return z;
  };
  EXPECT_NEAR(rest_height(true), rest_height(false), 1e-3);
}

TEST(SoilRobustness, SleepingBodyWakesWhenTheGroundUnderItIsLowered) {
  terrain::Terrain soil(soil_of("sand"));
  World world;
  bullet::TerrainCoupling ground(world.world(), soil);
  // Resting on rigid-like ground: give the soil a bedrock right at the surface first.
  btRigidBody* ball = world.add_body(std::make_unique<btSphereShape>(0.1f), 1.0, btVector3(0.5f, 0.5f, 0.1f));
  ground.add_body(ball, {.deform = false});
  for (int s = 0; s < 1200 && ball->isActive(); ++s) world.step(1.0 / 240);
  ASSERT_FALSE(ball->isActive()) << "the ball never fell asleep";
  // Dig a pit under it (an editing tool would do this).
  for (std::int64_t j = soil.column_j(0.3); j <= soil.column_j(0.7); ++j)
    for (std::int64_t i = soil.column_i(0.3); i <= soil.column_i(0.7); ++i) soil.set_height(i, j, -0.2);
  world.step(1.0 / 240);
  EXPECT_TRUE(ball->isActive());
  for (int s = 0; s < 240; ++s) world.step(1.0 / 240);
  EXPECT_LT(ball->getCenterOfMassPosition().z(), 0.0) << "it should have fallen into the pit";
}

// A body at rest is still imprinted, holding without pressing: its print's rim, left
// eroding by a one-pass cap, slumps outward but never slides in under the body, also where
// the still-eroding region's edge (its halo) runs under the body.
TEST(SoilRobustness, ABodyAtRestKeepsErodingSoilOutOfItsPrint) {
  terrain::TerrainSettings s = soil_of("mud");
  s.max_erosion_passes = 1;
  terrain::Terrain soil(s);
  World world;
  bullet::TerrainCoupling ground(world.world(), soil);
  btRigidBody* box =
      world.add_body(std::make_unique<btBoxShape>(btVector3(0.2f, 0.2f, 0.1f)), 200.0, btVector3(0, 0, 0.2f));
  ground.add_body(box);
  int steps = 0;
  while (steps < 2400 && (box->isActive() || ground.stats().active_columns > 0)) {
    world.step(1.0 / 240);
    ++steps;
  }
  ASSERT_LT(steps, 2400) << "the box never came to rest, or the soil never settled";
  btVector3 lo, hi;
  box->getCollisionShape()->getAabb(box->getWorldTransform(), lo, hi);
  ASSERT_LT(lo.z(), -0.01) << "the box should have sunk into the mud";
  // Soil under the box, away from its edges, against the box's own underside there (it
  // may rest a little tilted).
  shore::EnvelopeRaster underside;
  bullet::EnvelopeOptions nominal;
  nominal.include_margin = false;
  bullet::rasterize_envelope(*box->getCollisionShape(), box->getWorldTransform(), {s.origin_x, s.origin_y, s.cell},
                             nominal, underside);
  double above = -1.0;  // the most the soil stands above the underside
  for (std::int64_t j = soil.column_j(-0.18); j <= soil.column_j(0.18); ++j)
    for (std::int64_t i = soil.column_i(-0.18); i <= soil.column_i(0.18); ++i)
      above = std::max(above, soil.height(i, j) - underside.lower[underside.index(i, j)]);
  EXPECT_LE(above, 0.25e-3);
}

TEST(SoilRobustness, SameResultWhateverTheThreadCount) {
  std::uint64_t first = 0;
  for (int threads : {1, 2, 4}) {
    scenes::SphereDropCase c;
    c.run.terrain.threads = threads;
    c.run.terrain.cell = 0.01;
    c.seconds = 1000.0 / 240;
    const auto r = scenes::run_sphere_drop(c);
    if (threads == 1) first = r.stats.state_hash;
    EXPECT_EQ(r.stats.state_hash, first) << threads << " threads";
  }
}

TEST(SoilRobustness, BodyWithNaNPoseIsSkippedAndCounted) {
  terrain::Terrain soil(soil_of("sand"));
  World world;
  bullet::TerrainCoupling ground(world.world(), soil);
  btRigidBody* good = world.add_body(std::make_unique<btSphereShape>(0.1f), 5.0, btVector3(0, 0, 0.3f));
  btRigidBody* bad =
      world.add_body(std::make_unique<btBoxShape>(btVector3(0.1f, 0.1f, 0.1f)), 5.0, btVector3(2, 2, 0.3f));
  ground.add_body(good);
  ground.add_body(bad);
  bad->setLinearVelocity(btVector3(0, 0, std::numeric_limits<btScalar>::quiet_NaN()));
  for (int s = 0; s < 120; ++s) world.step(1.0 / 240);
  EXPECT_GT(ground.stats().skipped_bodies, 0);
  for (std::int64_t j = -20; j <= 20; ++j)
    for (std::int64_t i = -20; i <= 20; ++i) ASSERT_TRUE(std::isfinite(soil.height(i, j)));
  EXPECT_TRUE(std::isfinite(good->getCenterOfMassPosition().z()));
}

// A shape the soil cannot take is refused once, by add_body, with an error naming it; a
// body whose pose turns invalid later is skipped and counted, and stepSimulation goes on.
TEST(SoilRobustness, BadShapesAreRefusedAtAddBodyAndBadPosesSkippedPerSubstep) {
  terrain::Terrain soil(soil_of("sand"));
  World world;
  bullet::TerrainCoupling ground(world.world(), soil);
  expect_bad_bodies_refused_or_skipped(world, ground, btVector3(1, 1, 0.3f));
  // A body that only feels the ground needs no envelope.
  EXPECT_NO_THROW(ground.add_body(add_unsupported_body(world), {.deform = false}));
}

TEST(SoilRobustness, CouplingSettingsAreValidated) {
  terrain::Terrain soil(soil_of("sand"));
  World world;
  bullet::TerrainCouplingSettings s;
  s.rest_speed = 0.0;
  EXPECT_THROW(bullet::TerrainCoupling(world.world(), soil, s), shore::InvalidSetting);
  // The soil's interval and the contact's following: named, with the value and what is allowed.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Bad {
    void (*set)(bullet::TerrainCouplingSettings&, double);
    double value;
    const char *field, *allowed;
  };
  const auto interval = [](bullet::TerrainCouplingSettings& t, double v) { t.step_interval = v; };
  const auto drift = [](bullet::TerrainCouplingSettings& t, double v) { t.contact.follow_drift = v; };
  const auto speed = [](bullet::TerrainCouplingSettings& t, double v) { t.contact.follow_speed = v; };
  for (const Bad& bad : {Bad{interval, -1e-3, "bullet.TerrainCouplingSettings.step_interval", "[0, 0.125]"},
                         Bad{interval, 0.25, "bullet.TerrainCouplingSettings.step_interval", "[0, 0.125]"},
                         Bad{interval, nan, "bullet.TerrainCouplingSettings.step_interval", "[0, 0.125]"},
                         Bad{drift, 2.5, "bullet.TerrainContactSettings.follow_drift", "[0, 2]"},
                         Bad{drift, nan, "bullet.TerrainContactSettings.follow_drift", "[0, 2]"},
                         Bad{speed, -1.0, "bullet.TerrainContactSettings.follow_speed", ">= 0"},
                         Bad{speed, nan, "bullet.TerrainContactSettings.follow_speed", ">= 0"}}) {
    bullet::TerrainCouplingSettings t;
    bad.set(t, bad.value);
    try {
      bullet::TerrainCoupling refused(world.world(), soil, t);
      ADD_FAILURE() << bad.field << " = " << bad.value << " accepted";
    } catch (const shore::InvalidSetting& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(bad.field), std::string::npos) << what;
      EXPECT_NE(what.find(bad.allowed), std::string::npos) << what;
    }
  }
  bullet::TerrainCoupling ground(world.world(), soil);
  btRigidBody* ball = world.add_body(std::make_unique<btSphereShape>(0.1f), 1.0, btVector3(0, 0, 0.3f));
  EXPECT_THROW(ground.add_body(ball, {.ccd_motion_share = 0.0}), shore::InvalidSetting);
  EXPECT_THROW(ground.add_body(ball, {.ccd_sphere_share = 1.5}), shore::InvalidSetting);
}
