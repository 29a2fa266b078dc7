// Misuse and lifetimes of the couplings: each case has the behaviour documented
// in shore/bullet/terrain_coupling.h and water_coupling.h, and never a crash (the
// sanitizer run reads these cases under ASan, so a read of a deleted body fails there).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <sstream>
#include <string>

#include <BulletCollision/CollisionShapes/btMultiSphereShape.h>
#include <btBulletDynamicsCommon.h>

#include "shore/bullet/terrain_coupling.h"
#include "shore/bullet/water_coupling.h"
#include "shore/core/error.h"
#include "shore/scenes/world.h"
#include "shore/terrain/terrain.h"
#include "shore/water/surface.h"

using namespace shore;
using shore::scenes::World;

namespace {
constexpr double kH = 1.0 / 240;

terrain::TerrainSettings sand() {
  terrain::TerrainSettings s;
  s.cell = 0.02;
  s.material = terrain::Material::sand();
  s.threads = 1;
  return s;
}

bool finite(const btVector3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

void steps(World& world, int n) {
  for (int s = 0; s < n; ++s) world.step(kH);
}

/// The lowest point of a body, against the soil's bedrock under its centre.
double clearance_above_bedrock(const btRigidBody& b, const terrain::Terrain& soil) {
  btVector3 lo, hi;
  b.getCollisionShape()->getAabb(b.getWorldTransform(), lo, hi);
  const btVector3 c = b.getCenterOfMassPosition();
  return lo.z() - soil.bedrock(soil.column_i(c.x()), soil.column_j(c.y()));
}

bool soil_bit_cleared(const btRigidBody& b, const bullet::TerrainCoupling& ground) {
  return (b.getBroadphaseHandle()->m_collisionFilterMask & ground.settings().terrain_filter_bit) == 0;
}

/// A 40 kg box that never sleeps, added at height z and left half a second to press the soil.
btRigidBody* add_pressing_box(World& world, bullet::TerrainCoupling& ground, double z) {
  btRigidBody* box =
      world.add_body(std::make_unique<btBoxShape>(btVector3(0.15f, 0.15f, 0.1f)), 40.0, btVector3(0, 0, btScalar(z)));
  box->setActivationState(DISABLE_DEACTIVATION);
  ground.add_body(box);
  steps(world, 120);
  return box;
}

/// A body the test owns (not the World), so that it can delete it.
struct OwnBody {
  btSphereShape shape{0.1f};
  btDefaultMotionState motion;
  std::unique_ptr<btRigidBody> body;
  explicit OwnBody(const btVector3& at) : motion(btTransform(btQuaternion::getIdentity(), at)) {
    btVector3 inertia;
    shape.calculateLocalInertia(2.0, inertia);
    body = std::make_unique<btRigidBody>(btRigidBody::btRigidBodyConstructionInfo(2.0, &motion, &shape, inertia));
  }
};
}  // namespace

TEST(CouplingMisuse, RemovingABodyNeverAddedOrTwiceDoesNothing) {
  terrain::Terrain soil(sand());
  World world;
  bullet::TerrainCoupling ground(world.world(), soil);
  btRigidBody* ball = world.add_body(std::make_unique<btSphereShape>(0.1f), 2.0, btVector3(0, 0, 0.3f));
  btRigidBody* other = world.add_body(std::make_unique<btSphereShape>(0.1f), 2.0, btVector3(1, 0, 0.3f));
  ground.add_body(ball);
  ground.remove_body(other);  // never added
  ground.remove_body(nullptr);
  EXPECT_EQ(ground.bodies().size(), 1u);
  ground.remove_body(ball);
  ground.remove_body(ball);  // twice
  EXPECT_TRUE(ground.bodies().empty());
  EXPECT_FALSE(soil_bit_cleared(*ball, ground)) << "a removed body collides with the tiles through Bullet again";
  steps(world, 240);  // stepping after remove: the ball lands on the tiles as on rigid ground
  EXPECT_NEAR(ball->getCenterOfMassPosition().z(), 0.1, 0.01);
}

TEST(CouplingMisuse, AddingABodyTwiceKeepsOneEntryWithTheLatestSettings) {
  terrain::Terrain soil(sand());
  World world;
  bullet::TerrainCoupling ground(world.world(), soil);
  btRigidBody* ball = world.add_body(std::make_unique<btSphereShape>(0.1f), 20.0, btVector3(0, 0, 0.3f));
  ground.add_body(ball, {.deform = false});
  ground.add_body(ball);  // now it deforms
  ASSERT_EQ(ground.bodies().size(), 1u);
  steps(world, 240);
  EXPECT_GT(soil.sinkage(0, 0), 1e-3) << "the second add_body's settings (deform) hold";
}

TEST(CouplingMisuse, RemovingABodyInContactHandsItToBulletsTileContact) {
  terrain::Terrain soil(sand());
  World world;
  bullet::TerrainCoupling ground(world.world(), soil);
  btRigidBody* box = add_pressing_box(world, ground, 0.11);
  ASSERT_GT(ground.terrain_force(box).contact_columns, 0) << "in contact when removed";
  ground.remove_body(box);
  EXPECT_EQ(ground.terrain_force(box).contact_columns, 0);
  steps(world, 240);
  EXPECT_TRUE(finite(box->getCenterOfMassPosition()));
  EXPECT_GT(clearance_above_bedrock(*box, soil), 0.0);
  EXPECT_LT(box->getLinearVelocity().length(), 0.05) << "held by the tiles";
}

// A body taken out of the world and deleted without remove_body: both couplings drop it at
// the next substep without reading it (ASan would report the read) and count it.
TEST(CouplingMisuse, ABodyDeletedWithoutRemoveBodyIsDroppedUnread) {
  terrain::Terrain soil(sand());
  water::PhysicalParameters phys;
  phys.cell = 0.05;
  water::SurfaceSettings ws = water::SurfaceSettings::physical(phys, 16, 16);
  ws.origin_x = ws.origin_y = -0.4;
  water::Surface pond(ws);
  World world;
  bullet::TerrainCoupling ground(world.world(), soil);
  bullet::WaterCoupling water(world.world(), pond);
  auto own = std::make_unique<OwnBody>(btVector3(0, 0, 0.3f));
  world.world().addRigidBody(own->body.get());
  btRigidBody* kept = world.add_body(std::make_unique<btSphereShape>(0.1f), 2.0, btVector3(0.5f, 0, 0.3f));
  ground.add_body(own->body.get());
  water.add_body(own->body.get());
  ground.add_body(kept);
  steps(world, 60);
  world.world().removeRigidBody(own->body.get());
  own.reset();  // deleted, never removed from the couplings
  EXPECT_NO_THROW(steps(world, 60));
  EXPECT_EQ(ground.stats().lost_bodies, 1);
  EXPECT_EQ(water.stats().lost_bodies, 1);
  ASSERT_EQ(ground.bodies().size(), 1u);
  EXPECT_EQ(ground.bodies()[0], kept);
  EXPECT_TRUE(water.bodies().empty());
}

// A kinematic body never in the world (allowed: it presses geometrically) is not "lost".
TEST(CouplingMisuse, AKinematicBodyOutsideTheWorldIsKept) {
  terrain::Terrain soil(sand());
  World world;
  bullet::TerrainCoupling ground(world.world(), soil);
  OwnBody press(btVector3(0, 0, 0.05f));
  press.body->setCollisionFlags(press.body->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
  press.body->setMassProps(0, btVector3(0, 0, 0));
  ground.add_body(press.body.get());
  steps(world, 10);
  EXPECT_EQ(ground.stats().lost_bodies, 0);
  EXPECT_EQ(ground.bodies().size(), 1u);
  EXPECT_GT(soil.sinkage(0, 0), 0.01) << "it pressed the soil";
}

TEST(CouplingMisuse, DestroyingTheCouplingFirstLeavesAPlainWorld) {
  terrain::Terrain soil(sand());
  World world;
  const int objects_before = world.world().getNumCollisionObjects();
  auto ground = std::make_unique<bullet::TerrainCoupling>(world.world(), soil);
  btRigidBody* ball = world.add_body(std::make_unique<btSphereShape>(0.1f), 2.0, btVector3(0, 0, 0.3f));
  ground->add_body(ball);
  steps(world, 60);
  ASSERT_GT(world.world().getNumCollisionObjects(), objects_before + 1) << "tiles were made";
  ground.reset();
  EXPECT_EQ(world.world().getNumCollisionObjects(), objects_before + 1) << "only the ball is left";
  steps(world, 60);  // the coupling's action is gone with it (ASan would catch a call)
  EXPECT_TRUE(finite(ball->getCenterOfMassPosition()));
}

// The world destroyed before the coupling: detach() first, then the destructor touches
// nothing (ASan checks it); a detached coupling refuses new bodies.
TEST(CouplingMisuse, DetachLetsTheWorldGoFirst) {
  terrain::Terrain soil(sand());
  auto world = std::make_unique<World>();
  bullet::TerrainCoupling ground(world->world(), soil);
  btRigidBody* ball = world->add_body(std::make_unique<btSphereShape>(0.1f), 2.0, btVector3(0, 0, 0.3f));
  ground.add_body(ball);
  steps(*world, 60);
  ground.detach();
  EXPECT_FALSE(soil_bit_cleared(*ball, ground)) << "a let-go body collides with tiles through Bullet again";
  EXPECT_TRUE(ground.bodies().empty());
  EXPECT_EQ(world->world().getNumCollisionObjects(), 1) << "the tiles are gone";
  const std::int64_t substeps = ground.stats().substeps;
  steps(*world, 5);
  EXPECT_EQ(ground.stats().substeps, substeps) << "no longer an action of the world";
  world.reset();
  EXPECT_THROW(ground.add_body(ball), shore::InvalidSetting);
  ground.detach();  // twice: nothing
}

TEST(CouplingMisuse, AChangedShapeOrScaleIsCheckedAgainAndAnUnusableOneSkipped) {
  terrain::Terrain soil(sand());
  World world;
  bullet::TerrainCoupling ground(world.world(), soil);
  btRigidBody* body = world.add_body(std::make_unique<btSphereShape>(0.1f), 20.0, btVector3(0, 0, 0.12f));
  body->setActivationState(DISABLE_DEACTIVATION);
  ground.add_body(body);
  steps(world, 120);
  // A bigger box instead of the ball: it is imprinted as the box.
  btCollisionShape* box = world.keep(std::make_unique<btBoxShape>(btVector3(0.3f, 0.3f, 0.1f)));
  body->setCollisionShape(box);
  steps(world, 240);
  EXPECT_GT(soil.sinkage(soil.column_i(0.25), soil.column_j(0.25)), 1e-4) << "the box's corner pressed the soil";
  // Scaled up by half: imprinted as the bigger box.
  box->setLocalScaling(btVector3(1.5f, 1.5f, 1));
  steps(world, 240);
  EXPECT_GT(soil.sinkage(soil.column_i(0.4), soil.column_j(0.4)), 1e-4) << "the scaled box's corner pressed the soil";
  // A shape the soil cannot take (multi-sphere): skipped each substep, never a crash.
  const std::int64_t skipped = ground.stats().skipped_bodies;
  btVector3 centres[1] = {btVector3(0, 0, 0)};
  btScalar radii[1] = {btScalar(0.2)};
  btCollisionShape* unusable = world.keep(std::make_unique<btMultiSphereShape>(centres, radii, 1));
  body->setCollisionShape(unusable);
  EXPECT_NO_THROW(steps(world, 10));
  EXPECT_EQ(ground.stats().skipped_bodies, skipped + 10);
  body->setCollisionShape(box);  // usable again
  steps(world, 120);
  EXPECT_EQ(ground.stats().skipped_bodies, skipped + 10);
  EXPECT_TRUE(finite(body->getCenterOfMassPosition()));
  EXPECT_GT(clearance_above_bedrock(*body, soil), 0.0);
}

// Switched to kinematic and back (Bullet wants the body out of the world for it, which
// resets its collision mask): each substep treats it as what it is now.
TEST(CouplingMisuse, SwitchingBetweenKinematicAndDynamic) {
  terrain::Terrain soil(sand());
  World world;
  bullet::TerrainCoupling ground(world.world(), soil);
  btRigidBody* box = add_pressing_box(world, ground, 0.2);
  auto switch_to = [&](bool kinematic) {
    world.world().removeRigidBody(box);
    if (kinematic) {
      box->setCollisionFlags(box->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
      box->setMassProps(0, btVector3(0, 0, 0));
    } else {
      box->setCollisionFlags(box->getCollisionFlags() & ~btCollisionObject::CF_KINEMATIC_OBJECT);
      btVector3 inertia;
      box->getCollisionShape()->calculateLocalInertia(40.0, inertia);
      box->setMassProps(40.0, inertia);
    }
    world.world().addRigidBody(box);
  };
  switch_to(true);
  steps(world, 60);
  EXPECT_EQ(ground.bodies().size(), 1u) << "back in the world before the substep: not lost";
  switch_to(false);
  EXPECT_FALSE(soil_bit_cleared(*box, ground)) << "Bullet's re-add reset the mask";
  steps(world, 1);
  EXPECT_TRUE(soil_bit_cleared(*box, ground)) << "the soil owns the dynamic body's contact again";
  steps(world, 240);
  EXPECT_TRUE(finite(box->getCenterOfMassPosition()));
  EXPECT_GT(clearance_above_bedrock(*box, soil), 0.0);
  EXPECT_EQ(ground.stats().lost_bodies, 0);
}

// A ball asleep on the sand; a heavy box lands beside it and its rim heaves the soil under
// the ball, which wakes.
TEST(CouplingMisuse, ASleepingBodyWakesWhenAnotherBodyChangesTheSoilUnderIt) {
  terrain::Terrain soil(sand());
  World world;
  bullet::TerrainCoupling ground(world.world(), soil);
  btRigidBody* ball = world.add_body(std::make_unique<btSphereShape>(0.1f), 1.0, btVector3(0.32f, 0, 0.1f));
  ground.add_body(ball, {.deform = false});
  for (int s = 0; s < 1200 && ball->isActive(); ++s) world.step(kH);
  ASSERT_FALSE(ball->isActive()) << "the ball never fell asleep";
  btRigidBody* box =
      world.add_body(std::make_unique<btBoxShape>(btVector3(0.2f, 0.2f, 0.1f)), 400.0, btVector3(0, 0, 0.15f));
  ground.add_body(box);
  bool woke = false;
  for (int s = 0; s < 120 && !woke; ++s) {
    world.step(kH);
    woke = ball->isActive();
  }
  EXPECT_TRUE(woke);
  steps(world, 240);
  EXPECT_GT(clearance_above_bedrock(*ball, soil), 0.0);
}

TEST(CouplingMisuse, MaterialChangesMidRunAreCheckedAndOutOfRangeIndicesRefusedOrAnswered) {
  terrain::Terrain soil(sand());
  World world;
  bullet::TerrainCoupling ground(world.world(), soil);
  btRigidBody* ball = world.add_body(std::make_unique<btSphereShape>(0.1f), 5.0, btVector3(0, 0, 0.3f));
  ground.add_body(ball);
  steps(world, 60);
  terrain::Material deeper = soil.settings().material;
  deeper.soil_depth *= 2;
  EXPECT_THROW(soil.set_material(deeper), shore::InvalidSetting) << "bedrock cannot move mid-run";
  terrain::Material softer = soil.settings().material;
  softer.bekker_kphi *= 0.5;
  EXPECT_NO_THROW(soil.set_material(softer));
  softer.bekker_n = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(soil.set_material(softer), shore::InvalidSetting);
  steps(world, 120);
  EXPECT_TRUE(finite(ball->getCenterOfMassPosition()));
  // The soil is unbounded: any column index answers (untouched ground), even the extremes.
  for (std::int64_t i :
       {std::numeric_limits<std::int64_t>::min(), std::int64_t{-1} << 40, std::numeric_limits<std::int64_t>::max()}) {
    try {
      EXPECT_TRUE(std::isfinite(soil.height(i, i))) << i;
    } catch (const shore::InvalidSetting&) {
      // refused with a clear error: also fine
    }
  }
  water::PhysicalParameters phys;
  water::Surface pond(water::SurfaceSettings::physical(phys, 16, 16));
  EXPECT_THROW((void)pond.height(-1, 0), shore::InvalidSetting);
  EXPECT_THROW((void)pond.height(0, 16), shore::InvalidSetting);
  EXPECT_THROW(pond.set_constraint(16, 16, water::NodeConstraint::fixed), shore::InvalidSetting);
}

namespace {
/// The InvalidSetting add_body threw, or an empty message if it threw none.
template <class Coupling>
std::string refusal_of(Coupling& coupling, btRigidBody* body) {
  try {
    coupling.add_body(body);
  } catch (const shore::InvalidSetting& e) {
    return e.what();
  }
  return {};
}

bool mentions(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::string address_of(const void* p) {
  std::ostringstream s;
  s << p;
  return s.str();
}
}  // namespace

// Two soils whose regions overlap would both push a body in both couplings: the second
// add_body refuses it, naming the body and both regions, and changes nothing.
TEST(CouplingMisuse, ABodyInTwoTerrainCouplingsOverOverlappingRegionsIsRefused) {
  terrain::Terrain sand_soil(sand()), mud_soil(sand());
  World world;
  bullet::TerrainCouplingSettings west, east;
  west.region = {-1.5, -1.5, 0.5, 1.5};
  east.region = {0.0, -1.5, 1.5, 1.5};  // overlaps west over [0, 0.5)
  bullet::TerrainCoupling a(world.world(), sand_soil, west);
  bullet::TerrainCoupling b(world.world(), mud_soil, east);
  btRigidBody* ball = world.add_body(std::make_unique<btSphereShape>(0.1f), 5.0, btVector3(0.3f, 0, 0.3f));
  a.add_body(ball);
  const int mask = ball->getBroadphaseHandle()->m_collisionFilterMask;
  const std::string why = refusal_of(b, ball);
  ASSERT_FALSE(why.empty()) << "the second add_body over an overlapping region was accepted";
  EXPECT_TRUE(mentions(why, "bullet.TerrainCoupling.add_body(body)")) << why;
  EXPECT_TRUE(mentions(why, address_of(ball))) << why;
  EXPECT_TRUE(mentions(why, "SPHERE")) << why;
  EXPECT_TRUE(mentions(why, "[-1.5, 0.5) x [-1.5, 1.5) m")) << why;
  EXPECT_TRUE(mentions(why, "[0, 1.5) x [-1.5, 1.5) m")) << why;
  EXPECT_TRUE(b.bodies().empty()) << "the refused add_body changed nothing";
  ASSERT_EQ(a.bodies().size(), 1u);
  EXPECT_EQ(ball->getBroadphaseHandle()->m_collisionFilterMask, mask);
  EXPECT_TRUE(refusal_of(a, ball).empty()) << "adding it again to the same coupling still replaces its settings";
  steps(world, 120);
  EXPECT_GT(sand_soil.sinkage(sand_soil.column_i(0.3), 0), 1e-4) << "the first coupling still presses the soil";
  EXPECT_EQ(mud_soil.sinkage(mud_soil.column_i(0.3), 0), 0.0) << "the refused one never did";
  // Taken out of the first coupling, it may go to the second.
  a.remove_body(ball);
  EXPECT_TRUE(refusal_of(b, ball).empty());
  EXPECT_FALSE(refusal_of(a, ball).empty()) << "now the first refuses it";
}

TEST(CouplingMisuse, TwoTerrainCouplingsOverTheWholePlaneRefuseASharedBody) {
  terrain::Terrain one(sand()), two(sand());
  World world;
  bullet::TerrainCoupling a(world.world(), one);
  bullet::TerrainCoupling b(world.world(), two);
  btRigidBody* ball = world.add_body(std::make_unique<btSphereShape>(0.1f), 5.0, btVector3(0, 0, 0.3f));
  b.add_body(ball);
  const std::string why = refusal_of(a, ball);
  EXPECT_TRUE(mentions(why, "everywhere (the default Region) overlaps this one's everywhere")) << why;
}

// Regions side by side (sharing an edge) are disjoint: a body in both couplings is how a
// vehicle crosses from one soil to the next. Detached or destroyed couplings, and
// couplings of another world, are not looked at.
TEST(CouplingMisuse, ABodyMayBeInCouplingsOfDisjointRegionsOrOtherWorlds) {
  terrain::Terrain one(sand()), two(sand()), three(sand());
  World world, other_world;
  bullet::TerrainCouplingSettings west, east;
  west.region = {-1.28, -1.28, 0.0, 1.28};
  east.region = {0.0, -1.28, 1.28, 1.28};
  bullet::TerrainCoupling a(world.world(), one, west);
  bullet::TerrainCoupling b(world.world(), two, east);
  btRigidBody* ball = world.add_body(std::make_unique<btSphereShape>(0.1f), 5.0, btVector3(0, 0, 0.3f));
  a.add_body(ball);
  EXPECT_TRUE(refusal_of(b, ball).empty()) << "regions sharing an edge do not overlap";
  steps(world, 60);
  EXPECT_TRUE(finite(ball->getCenterOfMassPosition()));
  EXPECT_GT(clearance_above_bedrock(*ball, one), 0.0);
  {
    auto everywhere = std::make_unique<bullet::TerrainCoupling>(world.world(), three);
    EXPECT_FALSE(refusal_of(*everywhere, ball).empty());
    everywhere->detach();
    a.remove_body(ball);
    b.remove_body(ball);
    everywhere = std::make_unique<bullet::TerrainCoupling>(world.world(), three);
    everywhere->add_body(ball);
    everywhere.reset();  // destroyed while holding the ball: it leaves the world's list
  }
  EXPECT_TRUE(refusal_of(a, ball).empty()) << "a destroyed coupling is not looked at";
  // A kinematic press outside every world (allowed) in couplings of two worlds.
  OwnBody press(btVector3(3, 0, 0.05f));
  press.body->setCollisionFlags(press.body->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
  press.body->setMassProps(0, btVector3(0, 0, 0));
  bullet::TerrainCoupling here(world.world(), three);
  bullet::TerrainCoupling there(other_world.world(), one);
  here.add_body(press.body.get());
  EXPECT_TRUE(refusal_of(there, press.body.get()).empty()) << "couplings of another world are not looked at";
}

// One body in a terrain and a water coupling (a beach) is fine, and in two water couplings
// whose surfaces lie apart; where they overlap it would float twice, so the second refuses it.
TEST(CouplingMisuse, ABodyInTwoWaterCouplingsOverOverlappingWaterIsRefused) {
  water::PhysicalParameters phys;
  phys.cell = 0.05;
  water::SurfaceSettings near = water::SurfaceSettings::physical(phys, 16, 16);
  near.origin_x = near.origin_y = -0.4;  // nodes -0.4 .. 0.35: cells [-0.425, 0.375)
  water::SurfaceSettings far = near;
  far.origin_x = 0.3;  // cells [0.275, 1.075): overlaps near
  water::SurfaceSettings beside = near;
  beside.origin_x = 0.5;  // cells [0.475, 1.275): apart from near
  water::Surface pond(near), lake(far), sea(beside);
  terrain::Terrain soil(sand());
  World world;
  bullet::TerrainCoupling ground(world.world(), soil);
  bullet::WaterCoupling in_pond(world.world(), pond);
  bullet::WaterCoupling in_lake(world.world(), lake);
  bullet::WaterCoupling in_sea(world.world(), sea);
  btRigidBody* ball = world.add_body(std::make_unique<btSphereShape>(0.1f), 0.5, btVector3(0.3f, 0, 0.3f));
  ground.add_body(ball);
  EXPECT_TRUE(refusal_of(in_pond, ball).empty()) << "a terrain and a water coupling may share a body";
  const std::string why = refusal_of(in_lake, ball);
  EXPECT_TRUE(mentions(why, "bullet.WaterCoupling.add_body(body)")) << why;
  EXPECT_TRUE(mentions(why, address_of(ball))) << why;
  EXPECT_TRUE(mentions(why, "water [-0.42")) << why;      // the pond's cells (rounded in the last digits)
  EXPECT_TRUE(mentions(why, "this one's [0.27")) << why;  // the lake's
  EXPECT_TRUE(in_lake.bodies().empty());
  EXPECT_TRUE(refusal_of(in_sea, ball).empty()) << "surfaces apart do not overlap";
  steps(world, 60);
  EXPECT_TRUE(finite(ball->getCenterOfMassPosition()));
}
