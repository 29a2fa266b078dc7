#pragma once
// Internal: Shore's vectors at the Bullet boundary. btVector3 carries btScalar (float or
// double by Bullet's build); Shore computes in double.

#include <LinearMath/btVector3.h>

#include "shore/bullet/config.h"
#include "shore/core/vec3.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

inline Vec3 to_vec3(const btVector3& v) noexcept {
  return {static_cast<double>(v.x()), static_cast<double>(v.y()), static_cast<double>(v.z())};
}
inline btVector3 to_bt(Vec3 v) noexcept { return {btScalar(v.x), btScalar(v.y), btScalar(v.z)}; }

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
