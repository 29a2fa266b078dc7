#include "shore/bullet/soil_raycaster.h"

#include <algorithm>
#include <cmath>

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
  if (terrain.exposed_material(terrain.column_i(x), terrain.column_j(y)).rigid) return hit;
  // The base's slope by central differences over +- span (at least a cell).
  const double s = std::max(settings_.span, terrain.settings().cell);
  const auto base = [&](double bx, double by) {
    return terrain.base_height(terrain.column_i(bx), terrain.column_j(by));
  };
  const double dx = (base(x + s, y) - base(x - s, y)) / (2.0 * s);
  const double dy = (base(x, y + s) - base(x, y - s)) / (2.0 * s);
  const btVector3 normal = btVector3(btScalar(-dx), btScalar(-dy), btScalar(1)).normalized();
  result.m_hitNormalInWorld = frame.identity() ? normal : frame.direction_to_world(normal);
  return hit;
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
