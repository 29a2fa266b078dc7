// Identical continuation: a scene run to a save point, checkpointed, and run on
// must end in the same state hash as a fresh scene (a new Bullet world, new soils and water)
// restored from the checkpoint and run for the same substeps. Equal hashes mean every
// soil column, water node and body is bit-identical; the uninterrupted run is the reference,
// not the code's own prediction.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <BulletCollision/CollisionShapes/btBoxShape.h>

#include "shore/bullet/body_state.h"
#include "shore/bullet/terrain_coupling.h"
#include "shore/core/checkpoint_file.h"
#include "shore/core/error.h"
#include "shore/core/hash.h"
#include "shore/scenes/checkpoint.h"
#include "shore/scenes/contents.h"
#include "shore/scenes/runner.h"
#include "shore/scenes/world.h"

using namespace shore::scenes;

namespace {

SceneOptions smoke_options(const std::string& name) { return pinning_options(*find_scene(name)); }

struct Continuation {
  std::uint64_t uninterrupted = 0, restored = 0;
  int contact_points_at_save = 0;  // Bullet contact points the reference run had at the save point
};

/// Runs `name` for save_at substeps, checkpoints it (through a file), runs it on to the
/// end of its smoke run; restores a fresh scene from the file and runs it to the same end.
/// clear_contacts: both runs continue from no Bullet contact points (body_state.h).
/// nudge: substeps added to the save point.
Continuation continue_from(const std::string& name, double save_share, bool clear_contacts, int nudge = 0) {
  const SceneOptions opt = smoke_options(name);
  const SceneType& type = *find_scene(name);
  const int total = opt.substeps(), save_at = static_cast<int>(save_share * total) + nudge;
  // Named by the test too: ctest runs each test in its own process, and two tests that
  // continue the same scene at once must not write one file.
  const testing::TestInfo& test = *testing::UnitTest::GetInstance()->current_test_info();
  const std::string tag = std::string(test.test_suite_name()) + "." + test.name();
  std::string file_name = "shore_scene_checkpoint_" + tag + "_" + name + "_" + std::to_string(nudge) + ".ckp";
  std::replace(file_name.begin(), file_name.end(), '/', '_');
  const std::filesystem::path file = std::filesystem::path(testing::TempDir()) / file_name;
  Continuation out;

  const std::unique_ptr<Scene> reference = type.create(opt);
  for (int k = 0; k < save_at; ++k) reference->step();
  btDiscreteDynamicsWorld& ref_world = reference->contents().world->world();
  for (int m = 0; m < ref_world.getDispatcher()->getNumManifolds(); ++m)
    out.contact_points_at_save += ref_world.getDispatcher()->getManifoldByIndexInternal(m)->getNumContacts();
  save_checkpoint(*reference).save(file);
  if (clear_contacts) shore::bullet::clear_contact_points(ref_world);
  for (int k = save_at; k < total; ++k) reference->step();
  out.uninterrupted = state_hash(reference->state());

  const std::unique_ptr<Scene> fresh = type.create(opt);
  restore_checkpoint(*fresh, shore::CheckpointReader::open(file, shore::bullet::scalar_bytes()));
  if (clear_contacts) shore::bullet::clear_contact_points(fresh->contents().world->world());
  for (int k = save_at; k < total; ++k) fresh->step();
  out.restored = state_hash(fresh->state());
  std::filesystem::remove(file);
  return out;
}

/// The state hash of a fresh scene run from the save point's substep count without a
/// restore: the control that shows a restore is what makes the hashes equal.
std::uint64_t unrestored_hash(const std::string& name, double save_share, int nudge = 0) {
  const SceneOptions opt = smoke_options(name);
  const int total = opt.substeps(), save_at = static_cast<int>(save_share * total) + nudge;
  const std::unique_ptr<Scene> fresh = find_scene(name)->create(opt);
  for (int k = save_at; k < total; ++k) fresh->step();
  return state_hash(fresh->state());
}

class SceneCheckpoint : public testing::TestWithParam<std::string> {};

// Bodies on soil and in water touch only through Shore's couplings: nothing of Bullet's
// contact cache is in play, and the restored run continues bit-identically as it is.
TEST_P(SceneCheckpoint, RestoredMidRunInAFreshWorldContinuesBitIdentically) {
  const Continuation c = continue_from(GetParam(), 0.4, false);
  EXPECT_EQ(c.contact_points_at_save, 0) << "this scene's bodies touch through Bullet at the save point";
  EXPECT_EQ(shore::to_hex(c.uninterrupted), shore::to_hex(c.restored));
  EXPECT_NE(c.uninterrupted, unrestored_hash(GetParam(), 0.4)) << "the continuation does not depend on the restore";
}

// The soil steps every second substep at these scenes' 1/240 s (step_interval), and a moving
// body's contact follows it in between (follow_drift): saved just after a soil step and just
// before the next, the restored run keeps the soil's clock, which envelopes are still to be
// pressed and the followed contacts, and continues bit-identically either way. impact:
// bodies dropping and settling; tracks: a bicycle rolling.
TEST(SceneCheckpointSoilClock, RestoredOnEitherSideOfASoilStepContinuesBitIdentically) {
  for (const char* name : {"impact", "tracks"}) {
    const SceneOptions opt = smoke_options(name);
    ASSERT_EQ(std::lround(shore::bullet::TerrainCouplingSettings{}.step_interval / opt.substep), 2) << name;
    for (const int nudge : {0, 1}) {
      const Continuation c = continue_from(name, 0.4, false, nudge);
      EXPECT_EQ(shore::to_hex(c.uninterrupted), shore::to_hex(c.restored))
          << name << " saved " << nudge << " substeps later";
      EXPECT_NE(c.uninterrupted, unrestored_hash(name, 0.4, nudge)) << name;
    }
  }
}

/// The first substep from `from` on (at most 240 more) after which one of the scene's soils
/// holds a spray body between two clinging steps of its cadence (its state file is then
/// format 9, the one that keeps each body's last clinging step), or -1.
int between_clinging_steps(const std::string& name, int from) {
  const std::unique_ptr<Scene> scene = find_scene(name)->create(smoke_options(name));
  for (int k = 0; k < from + 240; ++k) {
    scene->step();
    if (k + 1 < from) continue;
    for (const SoilContents& soil : scene->contents().soils)
      if (soil.soil->save_bytes()[8] == 9) return k + 1;
  }
  return -1;
}

// The rally's wheels step their clinging soil every second soil step while their rims stay
// on the soil (Imprint::cling_every): saved while one waits between two such steps, the
// restored wheel still covers the time since its last one, and the run continues
// bit-identically.
TEST(SceneCheckpointCadence, RallySavedWhileAWheelWaitsBetweenClingingStepsContinuesBitIdentically) {
  // Its wheels switch cadence as the car sets off (one waits after substeps 4 to 52); from
  // substep 20 on they hold soil off the ground, whose shedding depends on the time since
  // their last clinging step (measured: a restore that lost it continues differently).
  const int at = between_clinging_steps("rally", 20);
  ASSERT_GE(at, 0) << "no wheel of the rally waits between two clinging steps: this tests nothing";
  const Continuation c = continue_from("rally", 0.0, false, at);
  EXPECT_EQ(shore::to_hex(c.uninterrupted), shore::to_hex(c.restored)) << "saved after substep " << at;
  EXPECT_NE(c.uninterrupted, unrestored_hash("rally", 0.0, at)) << "the continuation does not depend on the restore";
}

// impact: bodies dropped into soil, spray in flight at the save point; pond: a floating body
// in waves; beach: a ball rolling down sand into water, a box afloat; footprints: kinematic
// feet on three soils; tracks: a bicycle in a rut; rover: a btMultiBody on sand and water
// (its joint positions restored with the links' cached rotations, which the colliders'
// poses are built from: written past them, the restored wheels stood at the fresh scene's
// angles until the next step and the run went on otherwise); rally: a raycast car (its
// wheels' rotations and spins restored beside its chassis: bullet::save_vehicle) whose
// wheels are in the soil and the water.
INSTANTIATE_TEST_SUITE_P(Scenes, SceneCheckpoint,
                         testing::Values("impact", "pond", "beach", "footprints", "tracks", "rover", "rally"),
                         [](const auto& p) { return p.param; });

// Bodies that touch through Bullet (the vehicle's wheels on rigid ground, a box resting on a
// rigid heightfield): Bullet's manifolds hold contact points whose impulses warm-start the
// next solve, and a fresh world has none, so the restored run differs (measured: it does).
// The remedy (body_state.h): both runs continue from no contact points.
class BulletContactCheckpoint : public testing::TestWithParam<std::string> {};

TEST_P(BulletContactCheckpoint, ContinuesBitIdenticallyWhenBothRunsClearContactPoints) {
  const Continuation cleared = continue_from(GetParam(), 0.4, true);
  ASSERT_GT(cleared.contact_points_at_save, 0) << "no Bullet contact at the save point: this tests nothing";
  EXPECT_EQ(shore::to_hex(cleared.uninterrupted), shore::to_hex(cleared.restored));
  const Continuation kept = continue_from(GetParam(), 0.4, false);
  EXPECT_NE(kept.uninterrupted, kept.restored)
      << "Bullet's contact points no longer change the continuation: docs/checkpoints.md's remedy may go";
}

INSTANTIATE_TEST_SUITE_P(Scenes, BulletContactCheckpoint, testing::Values("vehicle", "rigid_drop"),
                         [](const auto& p) { return p.param; });

TEST(SceneCheckpointErrors, ACheckpointOfAnotherSceneIsRefusedNamingTheSection) {
  const std::unique_ptr<Scene> beach = find_scene("beach")->create(smoke_options("beach"));
  const std::vector<unsigned char> bytes = save_checkpoint(*beach).bytes();
  const std::unique_ptr<Scene> pond = find_scene("pond")->create(smoke_options("pond"));
  try {
    restore_checkpoint(*pond, shore::CheckpointReader(bytes, "beach.ckp"));
    FAIL() << "a beach checkpoint restored into the pond";
  } catch (const shore::FileError& e) {
    EXPECT_NE(std::string(e.what()).find("beach.ckp, section WATER"), std::string::npos) << e.what();
  }
}

TEST(SceneCheckpointErrors, TruncatedCouplingStatesAreRefusedAndLeaveTheCouplingsUntouched) {
  const std::unique_ptr<Scene> beach = find_scene("beach")->create(smoke_options("beach"));
  for (int k = 0; k < 60; ++k) beach->step();
  const SceneContents c = beach->contents();
  const std::vector<unsigned char> soil = c.soils[0].coupling->save_state(), water = c.waters[0].coupling->save_state();
  const std::vector<unsigned char> bodies = shore::bullet::save_bodies(c.world->world());
  for (std::size_t cut : {std::size_t{0}, std::size_t{7}, std::size_t{40}, soil.size() / 2, soil.size() - 1}) {
    EXPECT_THROW(c.soils[0].coupling->restore_state(std::span(soil).first(cut), "soil"), shore::FileError) << cut;
    EXPECT_THROW(c.waters[0].coupling->restore_state(std::span(water).first(std::min(cut, water.size() - 1)), "water"),
                 shore::FileError)
        << cut;
    EXPECT_THROW(shore::bullet::restore_bodies(c.world->world(),
                                               std::span(bodies).first(std::min(cut, bodies.size() - 1)), "bodies"),
                 shore::FileError)
        << cut;
  }
  EXPECT_EQ(c.soils[0].coupling->save_state(), soil);
  EXPECT_EQ(c.waters[0].coupling->save_state(), water);
  EXPECT_EQ(shore::bullet::save_bodies(c.world->world()), bodies);
  // The other precision and another body count are named.
  std::vector<unsigned char> other = bodies;
  other[12] = sizeof(btScalar) == 4 ? 8 : 4;
  try {
    shore::bullet::restore_bodies(c.world->world(), other, "bodies");
    FAIL();
  } catch (const shore::FileError& e) {
    EXPECT_NE(std::string(e.what()).find("-bit Bullet scalars"), std::string::npos) << e.what();
  }
  const std::unique_ptr<Scene> pond = find_scene("pond")->create(smoke_options("pond"));
  try {
    shore::bullet::restore_bodies(pond->contents().world->world(), bodies, "bodies");
    FAIL();
  } catch (const shore::FileError& e) {
    EXPECT_NE(std::string(e.what()).find("rigid bodies, the world has"), std::string::npos) << e.what();
  }
}

TEST(SceneCheckpointErrors, BodiesKeepTheirStatesWhenTheWorldsObjectOrderChanges) {
  // Bullet removes a collision object by moving the last one into its slot, as Shore's
  // couplings do with their soil tiles: two identical boxes then swap places in the world's
  // order. Saved in the order the application added them, each gets its own state back.
  auto build = [](World& w, bool with_tile) {
    btCollisionObject* tile = nullptr;
    if (with_tile) {
      tile = new btCollisionObject();
      tile->setCollisionShape(new btBoxShape(btVector3(1, 1, 1)));
      w.world().addCollisionObject(tile);
    }
    w.add_body(std::make_unique<btBoxShape>(btVector3(0.1f, 0.1f, 0.1f)), 1.0, btVector3(0, 0, 1));
    w.add_body(std::make_unique<btBoxShape>(btVector3(0.1f, 0.1f, 0.1f)), 1.0, btVector3(0, 0, 2));
    return tile;
  };
  World saved(9.81);
  btCollisionObject* tile = build(saved, true);
  saved.world().removeCollisionObject(tile);  // [tile, A, B] becomes [B, A]
  delete tile->getCollisionShape();
  delete tile;
  saved.bodies()[0]->setLinearVelocity(btVector3(1, 0, 0));
  saved.bodies()[1]->setLinearVelocity(btVector3(-1, 0, 0));
  ASSERT_EQ(btRigidBody::upcast(saved.world().getCollisionObjectArray()[0]), saved.bodies()[1]);

  World fresh(9.81);
  (void)build(fresh, false);
  shore::bullet::restore_bodies(fresh.world(), fresh.bodies(),
                                shore::bullet::save_bodies(saved.world(), saved.bodies()), "bodies");
  EXPECT_EQ(fresh.bodies()[0]->getLinearVelocity().x(), 1);
  EXPECT_EQ(fresh.bodies()[0]->getCenterOfMassPosition().z(), 1);
  EXPECT_EQ(fresh.bodies()[1]->getLinearVelocity().x(), -1);
  // In the world's order the boxes trade states.
  World swapped(9.81);
  (void)build(swapped, false);
  shore::bullet::restore_bodies(swapped.world(), shore::bullet::save_bodies(saved.world()), "bodies");
  EXPECT_EQ(swapped.bodies()[0]->getLinearVelocity().x(), -1);
}

}  // namespace

// Saved body states Bullet cannot step (an orientation that is no rotation turns the inertia
// into NaN in one step; the fuzzer found it) or that no coupling can index are refused,
// naming what is wrong, and leave the bodies as they were.
TEST(SceneCheckpointErrors, BodyStatesBulletCannotStepAreRefused) {
  const std::unique_ptr<Scene> beach = find_scene("beach")->create(smoke_options("beach"));
  const SceneContents c = beach->contents();
  btRigidBody* body = nullptr;
  for (int k = 0; k < c.world->world().getNumCollisionObjects() && !body; ++k)
    if (btRigidBody* b = btRigidBody::upcast(c.world->world().getCollisionObjectArray()[k]); b && b->getInvMass() > 0)
      body = b;
  ASSERT_NE(body, nullptr);
  const std::vector<unsigned char> good = shore::bullet::save_bodies(c.world->world());
  const btTransform pose = body->getWorldTransform();
  const btVector3 v = body->getLinearVelocity();
  auto refused_with = [&](const char* what) {
    const std::vector<unsigned char> bad = shore::bullet::save_bodies(c.world->world());
    body->setWorldTransform(pose), body->setLinearVelocity(v);
    try {
      shore::bullet::restore_bodies(c.world->world(), bad, "bodies");
      ADD_FAILURE() << "accepted: " << what;
    } catch (const shore::FileError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
    EXPECT_EQ(shore::bullet::save_bodies(c.world->world()), good) << what;
  };
  btTransform sheared = pose;
  sheared.getBasis()[1][1] = btScalar(-4.95e27);
  body->setWorldTransform(sheared);
  refused_with("not a rotation");
  btTransform far = pose;
  far.setOrigin(btVector3(btScalar(1e30), 0, 0));
  body->setWorldTransform(far);
  refused_with("farther than 1e9 m");
  body->setLinearVelocity(btVector3(0, btScalar(2e6), 0));
  refused_with("faster than 1e6 m/s");
}

// A multibody scene (rover: a six-wheeled btMultiBody on sand): a fresh scene restored from
// a checkpoint taken mid-run holds the saved state exactly (soil, water, the multibody's
// base and joints: equal state hashes), and a fresh scene not restored does not.
TEST(SceneCheckpointMultibody, RestoresTheMultibodysPoseVelocitiesAndJoints) {
  const SceneOptions opt = smoke_options("rover");
  const SceneType& type = *find_scene("rover");
  const std::unique_ptr<Scene> run = type.create(opt);
  for (int k = 0; k < opt.substeps() / 2; ++k) run->step();
  const std::vector<unsigned char> bytes = save_checkpoint(*run).bytes();
  const std::unique_ptr<Scene> fresh = type.create(opt);
  const std::uint64_t before = state_hash(fresh->state());
  restore_checkpoint(*fresh, shore::CheckpointReader(bytes, "rover checkpoint", shore::bullet::scalar_bytes()));
  EXPECT_EQ(shore::to_hex(state_hash(fresh->state())), shore::to_hex(state_hash(run->state())));
  EXPECT_NE(before, state_hash(run->state())) << "the run moved the rover";
  fresh->step();  // and it steps on, finite
  EXPECT_EQ(non_finite_count(fresh->state()), 0);
}
