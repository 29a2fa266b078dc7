#include "shore/scenes/character_cases.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>

#include <BulletCollision/CollisionDispatch/btGhostObject.h>
#include <BulletDynamics/Character/btKinematicCharacterController.h>

#include "shore/bullet/terrain_coupling.h"
#include "shore/scenes/world.h"
#include "shore/terrain/height_source.h"
#include "shore/terrain/terrain.h"

namespace shore::scenes {
namespace {

constexpr double kRadius = 0.25, kCylinder = 1.2;            // m, the capsule (1.7 m tall)
constexpr double kStand = kRadius + 0.5 * kCylinder;         // m, its centre above its lowest point
constexpr double kStartX = -2.6;                             // m
constexpr double kPrintLength = 0.26, kPrintWidth = 0.10;    // m
constexpr double kPrintSpacing = 0.65, kPrintOffset = 0.09;  // m along the walk, m either side of it

terrain::TerrainSettings hilly_sand(double cell) {
  terrain::LatticeNoiseSettings relief;
  relief.seed = 5;
  relief.spacing = 2.0;
  relief.amplitude = 0.12;
  relief.octaves = 2;
  terrain::TerrainSettings s;
  s.cell = cell;
  s.threads = 1;
  s.base = std::make_shared<terrain::LatticeNoise>(relief);
  return s;
}

/// Earlier walkers' prints along the walk: boxes of soil lowered by depth (an outside edit).
void press_prints(terrain::Terrain& soil, double depth, double x1) {
  if (depth <= 0.0) return;
  const int prints = static_cast<int>(std::ceil((x1 - kStartX - 0.4) / kPrintSpacing));
  for (int k = 0; k < prints; ++k) {
    const double x = kStartX + 0.4 + k * kPrintSpacing, y = (k % 2 == 0 ? 1 : -1) * kPrintOffset;
    const std::int64_t i0 = soil.column_i(x - 0.5 * kPrintLength), i1 = soil.column_i(x + 0.5 * kPrintLength);
    const std::int64_t j0 = soil.column_j(y - 0.5 * kPrintWidth), j1 = soil.column_j(y + 0.5 * kPrintWidth);
    for (std::int64_t j = j0; j <= j1; ++j)
      for (std::int64_t i = i0; i <= i1; ++i) soil.set_height(i, j, soil.height(i, j) - depth);
  }
  static_cast<void>(soil.take_changed());  // the tiles are made after this, from these heights
}

}  // namespace

CharacterWalkResult run_character_walk(const CharacterWalkCase& c) {
  terrain::Terrain soil(hilly_sand(c.cell));
  const double end_x = kStartX + c.speed * c.seconds + 1.0;
  press_prints(soil, c.print_depth, end_x);
  World world;
  bullet::TerrainCouplingSettings cs;
  cs.tiles.contact_stride = c.contact_stride;
  bullet::TerrainCoupling coupling(world.world(), soil, cs);

  btGhostPairCallback ghost_pairs;
  world.world().getBroadphase()->getOverlappingPairCache()->setInternalGhostPairCallback(&ghost_pairs);
  btCapsuleShapeZ capsule{btScalar(kRadius), btScalar(kCylinder)};
  btPairCachingGhostObject ghost;
  ghost.setCollisionShape(&capsule);
  ghost.setCollisionFlags(btCollisionObject::CF_CHARACTER_OBJECT);
  const double ground = soil.height(soil.column_i(kStartX), soil.column_j(0.0));
  ghost.setWorldTransform(
      btTransform(btQuaternion::getIdentity(), btVector3(btScalar(kStartX), 0, btScalar(ground + kStand + 0.05))));
  btKinematicCharacterController character(&ghost, &capsule, btScalar(0.3), btVector3(0, 0, 1));
  world.world().addCollisionObject(&ghost, btBroadphaseProxy::CharacterFilter,
                                   btBroadphaseProxy::StaticFilter | btBroadphaseProxy::DefaultFilter);
  world.world().addAction(&character);

  CharacterWalkResult r;
  const int steps = std::max(1, static_cast<int>(std::lround(c.seconds / c.step)));
  const int settle = static_cast<int>(std::lround(1.0 / c.step));
  double wall = 0.0, gap_sum = 0.0;
  int gaps = 0;
  r.gap_min = std::numeric_limits<double>::infinity();
  for (int k = 0; k < steps; ++k) {
    character.setWalkDirection(btVector3(btScalar(c.speed * c.step), 0, 0));
    const auto t0 = std::chrono::steady_clock::now();
    world.step(c.step);
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const btVector3 p = ghost.getWorldTransform().getOrigin();
    r.track.push_back(p);
    if (k < settle) continue;
    const double gap = double(p.z()) - kStand - soil.height(soil.column_i(p.x()), soil.column_j(p.y()));
    r.gap_min = std::min(r.gap_min, gap);
    gap_sum += gap;
    ++gaps;
  }
  r.wall_ms_per_step = 1e3 * wall / steps;
  r.gap_mean = gaps > 0 ? gap_sum / gaps : 0.0;
  if (gaps == 0) r.gap_min = 0.0;
  world.world().removeAction(&character);
  world.world().removeCollisionObject(&ghost);
  world.world().getBroadphase()->getOverlappingPairCache()->setInternalGhostPairCallback(nullptr);
  return r;
}

double track_distance(const std::vector<btVector3>& a, const std::vector<btVector3>& b) {
  double worst = 0.0;
  for (std::size_t k = 0; k < std::min(a.size(), b.size()); ++k)
    worst = std::max(worst, double((a[k] - b[k]).length()));
  return worst;
}

}  // namespace shore::scenes
