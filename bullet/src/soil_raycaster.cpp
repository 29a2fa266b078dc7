#include "shore/bullet/soil_raycaster.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <BulletCollision/CollisionDispatch/btCollisionObject.h>

#include "shore/bullet/terrain_coupling.h"
#include "shore/bullet/terrain_tiles.h"
#include "shore/core/error.h"
#include "shore/terrain/terrain.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

void SoilRaycasterSettings::validate(const char* field) const { Check{field}.positive("span", span); }

SoilRaycaster::SoilRaycaster(TerrainCoupling& coupling, SoilRaycasterSettings settings)
    : inner_(&coupling.world()), coupling_(coupling), settings_(settings) {
  settings_.validate("bullet.SoilRaycasterSettings");
}

void* SoilRaycaster::castRay(const btVector3& from, const btVector3& to, btVehicleRaycasterResult& result) {
  void* hit = inner_.castRay(from, to, result);
  const auto* object = static_cast<const btCollisionObject*>(hit);
  if (object == nullptr || !is_terrain_tile(object)) return hit;
  const terrain::Terrain& terrain = coupling_.terrain();
  const GroundFrame& frame = coupling_.settings().frame;
  const btVector3 at = frame.to_ground() * result.m_hitPointInWorld;
  const double x = double(at.x()), y = double(at.y());
  if (!coupling_.settings().region.contains(x, y)) return hit;  // another coupling's tile
  // Rigid ground's triangles are its own (a rigid material, or a painted road or rock).
  const std::int64_t i = terrain.column_i(x), j = terrain.column_j(y);
  if (terrain.exposed_material(i, j).rigid) return hit;
  // The base's slope by central differences between the columns at +- span (at least a
  // cell), over the distance of their centres (exact on a plane whatever the span).
  const double cell = terrain.settings().cell, s = std::max(settings_.span, cell);
  const std::int64_t i0 = terrain.column_i(x - s), i1 = terrain.column_i(x + s);
  const std::int64_t j0 = terrain.column_j(y - s), j1 = terrain.column_j(y + s);
  const double dx = (terrain.base_height(i1, j) - terrain.base_height(i0, j)) / (static_cast<double>(i1 - i0) * cell);
  const double dy = (terrain.base_height(i, j1) - terrain.base_height(i, j0)) / (static_cast<double>(j1 - j0) * cell);
  const btVector3 normal = btVector3(btScalar(-dx), btScalar(-dy), btScalar(1)).normalized();
  result.m_hitNormalInWorld = frame.identity() ? normal : frame.direction_to_world(normal);
  return hit;
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
