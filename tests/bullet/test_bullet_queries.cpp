// Bullet's own queries on Shore's ground: the ray casts of a stock btRaycastVehicle and the
// convex sweeps of a btKinematicCharacterController find the heightfield tiles, rigid and
// soft, wherever the object goes, without the object being added to the coupling.

#include <gtest/gtest.h>

#include <BulletCollision/CollisionDispatch/btGhostObject.h>
#include <BulletDynamics/Character/btKinematicCharacterController.h>

#include <cmath>
#include <memory>
#include <numbers>

#include "shore/bullet/terrain_coupling.h"
#include "shore/bullet/terrain_tiles.h"
#include "shore/scenes/character_cases.h"
#include "shore/scenes/raycast_car.h"
#include "shore/scenes/rigid_ground.h"
#include "shore/scenes/world.h"
#include "shore/terrain/height_source.h"
#include "shore/terrain/terrain.h"

namespace {

using shore::scenes::RaycastCar;
using shore::scenes::World;

constexpr double kCell = 0.1;
constexpr double kHalfSpan = 12.0;  // m: the ground spans [-12, 12] in x and y

shore::terrain::TerrainSettings hilly_ground(const shore::terrain::Material& material) {
  shore::terrain::LatticeNoiseSettings relief;
  relief.spacing = 3.0;
  relief.amplitude = 0.15;
  relief.octaves = 2;
  shore::terrain::TerrainSettings s;
  s.cell = kCell;
  s.origin_x = -kHalfSpan;
  s.origin_y = -kHalfSpan;
  s.tile_columns = 32;
  s.material = material;
  s.base = std::make_shared<shore::terrain::LatticeNoise>(relief);
  s.threads = 1;
  return s;
}

/// Sand in columns of `cell` m (flat at 0 until a base is given), stepped on one thread.
shore::terrain::TerrainSettings one_thread_sand(double cell) {
  shore::terrain::TerrainSettings s;
  s.cell = cell;
  s.threads = 1;
  return s;
}

struct Track {
  std::vector<btVector3> positions;
  int steps_with_all_wheels_down = 0;
};

/// Drives the car 5 s at 1/120 s along +x with a steady engine force and a little steering.
Track drive(World& world, RaycastCar& car) {
  Track t;
  constexpr double h = 1.0 / 120;
  for (int k = 0; k < 600; ++k) {
    car.drive(k < 60 ? 0.0 : 400.0, 0.0, k < 300 ? 0.0 : 0.05);
    world.step(h);
    t.positions.push_back(car.chassis()->getCenterOfMassPosition());
    t.steps_with_all_wheels_down += car.wheels_on_ground() == 4;
  }
  return t;
}

TEST(BulletQueries, StockRaycastVehicleDrivesOnRigidShoreGroundAsOnABulletHeightfield) {
  shore::terrain::Terrain ground(hilly_ground(shore::terrain::Material::rigid_ground()));
  const btVector3 start(-7.0f, 0.0f, btScalar(ground.height(ground.column_i(-7.0), ground.column_j(0.0)) + 1.0));

  // Shore's ground; the car is not added to the coupling (its wheels never touch the tiles,
  // only their rays do).
  World on_shore;
  shore::bullet::TerrainCoupling coupling(on_shore.world(), ground);
  RaycastCar shore_car(on_shore, {}, start);
  const Track a = drive(on_shore, shore_car);

  // The same heights as one plain static btHeightfieldTerrainShape body.
  World on_bullet;
  shore::bullet::HeightfieldTileSettings tile;
  tile.columns = static_cast<int>(std::lround(2 * kHalfSpan / kCell)) + 1;
  tile.cell = kCell;
  tile.origin_x = tile.origin_y = -kHalfSpan;
  tile.min_height = -1.0;
  tile.max_height = 1.0;
  const shore::scenes::RigidGround reference(
      on_bullet, tile, [&](double x, double y) { return ground.height(ground.column_i(x), ground.column_j(y)); });
  RaycastCar bullet_car(on_bullet, {}, start);
  const Track b = drive(on_bullet, bullet_car);

  EXPECT_GT(b.steps_with_all_wheels_down, 550) << "the reference car must stand on its wheels";
  EXPECT_EQ(a.steps_with_all_wheels_down, b.steps_with_all_wheels_down);
  EXPECT_GT(b.positions.back().x() - start.x(), 5.0) << "the reference car must drive";
  double worst = 0.0;
  for (std::size_t k = 0; k < a.positions.size(); ++k)
    worst = std::max(worst, double((a.positions[k] - b.positions[k]).length()));
  EXPECT_LT(worst, 1e-3) << "m, largest distance between the chassis on Shore's ground and on Bullet's";
}

/// A stock character controller, set up as Bullet's CharacterDemo sets one up (its capsule
/// on a btPairCachingGhostObject, filtered to collide with static and default objects),
/// walking along the ground's +x at 1.2 m/s for 5 s at 1/60 s, its up the ground's (the
/// world's ground frame: World::ground()). Returns its capsule centre every step, in the
/// ground's coordinates.
std::vector<btVector3> walk(World& world) {
  const shore::bullet::GroundFrame& frame = world.ground();
  btGhostPairCallback ghost_pairs;
  world.world().getBroadphase()->getOverlappingPairCache()->setInternalGhostPairCallback(&ghost_pairs);
  constexpr double radius = 0.3, cylinder = 1.0, speed = 1.2, h = 1.0 / 60;
  btCapsuleShapeZ capsule{btScalar(radius), btScalar(cylinder)};
  btPairCachingGhostObject ghost;
  ghost.setCollisionShape(&capsule);
  ghost.setCollisionFlags(btCollisionObject::CF_CHARACTER_OBJECT);
  const double stand = radius + 0.5 * cylinder;  // centre above the ground when standing
  // Placed after the controller is made: given an up other than its initial z, it turns the
  // ghost by the turn from z to that up, and the pose below is already the world's.
  btKinematicCharacterController character(&ghost, &capsule, btScalar(0.2), frame.up());
  ghost.setWorldTransform(
      world.to_world(btTransform(btQuaternion::getIdentity(), btVector3(-3.0f, 0.0f, btScalar(stand + 0.05)))));
  world.world().addCollisionObject(&ghost, btBroadphaseProxy::CharacterFilter,
                                   btBroadphaseProxy::StaticFilter | btBroadphaseProxy::DefaultFilter);
  world.world().addAction(&character);
  std::vector<btVector3> track;
  for (int k = 0; k < 300; ++k) {
    character.setWalkDirection(frame.direction_to_world(btVector3(btScalar(speed * h), 0, 0)));
    world.step(h);
    track.push_back(frame.to_ground()(ghost.getWorldTransform().getOrigin()));
  }
  world.world().removeAction(&character);
  world.world().removeCollisionObject(&ghost);
  world.world().getBroadphase()->getOverlappingPairCache()->setInternalGhostPairCallback(nullptr);
  return track;
}

TEST(BulletQueries, KinematicCharacterControllerWalksOnSoftShoreGroundAsOnBulletGround) {
  shore::terrain::TerrainSettings s = one_thread_sand(0.05);
  shore::terrain::Terrain sand(s);  // flat at 0
  World on_shore;
  shore::bullet::TerrainCoupling coupling(on_shore.world(), sand);
  const std::vector<btVector3> a = walk(on_shore);

  World on_bullet;
  shore::bullet::HeightfieldTileSettings tile;
  tile.columns = 201;
  tile.cell = s.cell;
  tile.origin_x = tile.origin_y = -5.0;
  const shore::scenes::RigidGround reference(on_bullet, tile, [](double, double) { return 0.0; });
  const std::vector<btVector3> b = walk(on_bullet);

  EXPECT_NEAR(double(b.back().x()) + 3.0, 6.0, 0.1) << "m the reference character walked";
  EXPECT_NEAR(double(b.back().z()), 0.8, 0.1) << "m, the reference character's height";
  double worst = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) worst = std::max(worst, double((a[k] - b[k]).length()));
  EXPECT_LT(worst, 1e-3) << "m, largest distance between the character on Shore's sand and on Bullet's ground";
}

/// Gentle ripples a few centimetres below the characters' start.
class Ripples final : public shore::terrain::HeightSource {
 public:
  [[nodiscard]] double height(double x, double y) const override {
    return 0.03 * std::sin(2.0 * std::numbers::pi * x / 0.7) * std::cos(2.0 * std::numbers::pi * y / 0.9) - 0.05;
  }
};

// With a contact stride of 4 the character's capsule meets the soil's surface sampled every
// fourth column, and walks exactly as on Bullet's own heightfield of 4 x the cell through the
// same heights; with every column it walks on the ripples' finer triangles, a visibly
// different path. Shore's ripples are the soil's columns (5 cm), untouched: the capsule is
// not added, and presses nothing.
TEST(BulletQueries, KinematicCharacterControllerWithAContactStrideWalksOnTheSampledSurface) {
  shore::terrain::TerrainSettings s = one_thread_sand(0.05);
  s.tile_columns = 32;
  s.base = std::make_shared<Ripples>();
  constexpr int kStride = 4;
  shore::terrain::Terrain sand(s), fine_sand(s);
  World on_shore, on_fine_shore;
  shore::bullet::TerrainCouplingSettings cs;
  cs.tiles.contact_stride = kStride;
  shore::bullet::TerrainCoupling coupling(on_shore.world(), sand, cs);
  shore::bullet::TerrainCoupling fine_coupling(on_fine_shore.world(), fine_sand);
  const std::vector<btVector3> a = walk(on_shore), fine = walk(on_fine_shore);

  World on_bullet;
  shore::bullet::HeightfieldTileSettings tile;
  tile.columns = 51;
  tile.cell = kStride * s.cell;
  tile.origin_x = tile.origin_y = -5.0;
  tile.min_height = -1.0;
  // The coarse vertices are the soil's columns whose indices are multiples of the stride.
  const shore::scenes::RigidGround reference(
      on_bullet, tile, [&](double x, double y) { return sand.height(sand.column_i(x), sand.column_j(y)); });
  const std::vector<btVector3> b = walk(on_bullet);

  EXPECT_NEAR(double(b.back().x()) + 3.0, 6.0, 0.1) << "m the reference character walked";
  double worst = 0.0, worst_fine = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    worst = std::max(worst, double((a[k] - b[k]).length()));
    worst_fine = std::max(worst_fine, double((fine[k] - b[k]).length()));
  }
  EXPECT_LT(worst, 1e-3) << "m, largest distance between the character on strided sand and on Bullet's coarse ground";
  EXPECT_GT(worst_fine, 3e-3) << "m: on every column the character should walk another path";
}

// Over hilly sand with a line of 3 cm prints, the character on tiles of contact stride 2 walks
// the path it walks on every column to within 2 cm, and neither sinks into the soil deeper than
// Bullet's sweeps allow (the world's allowed CCD penetration) and a centimetre.
TEST(BulletQueries, CharacterOnAContactStrideOfTwoStaysOnTheSoilAndOnItsPath) {
  const double allowed = double(World().world().getDispatchInfo().m_allowedCcdPenetration);
  const shore::scenes::CharacterWalkResult every = shore::scenes::run_character_walk({.cell = 0.02});
  const shore::scenes::CharacterWalkResult sampled =
      shore::scenes::run_character_walk({.cell = 0.02, .contact_stride = 2});
  EXPECT_GT(double(every.track.back().x()) - double(every.track.front().x()), 4.5) << "m walked";
  for (const auto* r : {&every, &sampled}) EXPECT_GT(r->gap_min, -(allowed + 0.01)) << "m: into the soil";
  EXPECT_LT(shore::scenes::track_distance(sampled.track, every.track), 0.02) << "m from the path on every column";
}

// In a Y-up world (the ground's frame GroundFrame::y_up(), the controller's up the world's y)
// the character walks on Shore's sand as on Bullet's own ground in the same world (a static
// plane), and, seen in the ground's coordinates, as in the Z-up world once it has landed
// (Bullet's controller drops its first 5 cm differently when its up is not its initial z).
TEST(BulletQueries, KinematicCharacterControllerWalksOnShoreGroundInAYUpWorld) {
  shore::terrain::TerrainSettings s = one_thread_sand(0.05);
  shore::terrain::Terrain z_sand(s), y_sand(s);
  World z_up;
  shore::bullet::TerrainCoupling z_coupling(z_up.world(), z_sand);
  const std::vector<btVector3> a = walk(z_up);
  const shore::bullet::GroundFrame frame = shore::bullet::GroundFrame::y_up();
  World y_up(9.81, frame);
  shore::bullet::TerrainCouplingSettings cs;
  cs.frame = frame;
  shore::bullet::TerrainCoupling y_coupling(y_up.world(), y_sand, cs);
  const std::vector<btVector3> b = walk(y_up);
  World y_plane(9.81, frame);
  y_plane.add_body(std::make_unique<btStaticPlaneShape>(frame.up(), btScalar(0)), 0.0, btVector3(0, 0, 0));
  const std::vector<btVector3> c = walk(y_plane);
  EXPECT_NEAR(double(c.back().x()) + 3.0, 6.0, 0.1) << "m the reference character walked in the Y-up world";
  double worst_plane = 0.0, worst_z_up = 0.0;
  for (std::size_t k = 0; k < b.size(); ++k) {
    worst_plane = std::max(worst_plane, double((b[k] - c[k]).length()));
    if (k >= 10) worst_z_up = std::max(worst_z_up, double((b[k] - a[k]).length()));
  }
  EXPECT_LT(worst_plane, 1e-3) << "m, largest distance between the character on Shore's sand and on Bullet's plane";
  EXPECT_LT(worst_z_up, 1e-3) << "m, largest distance between the walks in the Y-up and the Z-up world";
}

// Ground is made ahead of an object a game moves itself (a ghost object has no velocity
// Bullet knows): by twice how far it moved in the last substep. A sphere moved 3 m a substep
// over 2 cm sand (tiles of 1.28 m) finds the soil under where it will be next, by a ray cast
// down there, every substep; with the cover margin alone (0.25 m) there was none, and a
// character controller moved that far walked off its ground.
TEST(BulletQueries, GroundIsMadeAheadOfAnObjectTheGameMovesItself) {
  shore::terrain::TerrainSettings s = one_thread_sand(0.02);
  shore::terrain::Terrain sand(s);  // flat at 0
  World world;
  shore::bullet::TerrainCoupling coupling(world.world(), sand);
  btSphereShape ball(0.3f);
  btGhostObject ghost;
  ghost.setCollisionShape(&ball);
  ghost.setCollisionFlags(btCollisionObject::CF_CHARACTER_OBJECT);  // not static: it moves
  world.world().addCollisionObject(&ghost, btBroadphaseProxy::CharacterFilter,
                                   btBroadphaseProxy::StaticFilter | btBroadphaseProxy::DefaultFilter);
  constexpr double stride = 3.0;  // m a substep
  int found = 0, asked = 0;
  for (int k = 0; k < 20; ++k) {
    const double x = k * stride;
    ghost.setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(btScalar(x), 0, 0.5f)));
    world.step(1.0 / 60);
    if (k == 0) continue;  // it has not moved yet
    const btVector3 from(btScalar(x + stride), 0, 1), to(btScalar(x + stride), 0, -1);
    btCollisionWorld::ClosestRayResultCallback ray(from, to);
    world.world().rayTest(from, to, ray);
    ++asked;
    if (ray.hasHit() && shore::bullet::is_terrain_tile(ray.m_collisionObject)) ++found;
  }
  EXPECT_EQ(found, asked) << "substeps whose next position had soil under it";
  world.world().removeCollisionObject(&ghost);
}

}  // namespace
