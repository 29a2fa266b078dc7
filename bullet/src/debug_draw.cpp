#include "shore/bullet/debug_draw.h"

#include <algorithm>
#include <cmath>

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace debug_draw {

void cross(btIDebugDraw& d, const btVector3& p, double half, const btVector3& colour) {
  const auto h = btScalar(half);
  d.drawLine(p - btVector3(h, 0, 0), p + btVector3(h, 0, 0), colour);
  d.drawLine(p - btVector3(0, h, 0), p + btVector3(0, h, 0), colour);
  d.drawLine(p - btVector3(0, 0, h), p + btVector3(0, 0, h), colour);
}

void arrow(btIDebugDraw& d, const btVector3& from, const btVector3& vector, const btVector3& colour) {
  const btVector3 to = from + vector;
  d.drawLine(from, to, colour);
  const btScalar length = vector.length();
  if (!(length > btScalar(1e-6))) return;
  // Head: two strokes back from the tip, in the plane of the arrow and a side axis.
  const btVector3 dir = vector / length;
  btVector3 side = dir.cross(std::abs(dir.z()) < btScalar(0.9) ? btVector3(0, 0, 1) : btVector3(1, 0, 0));
  side.normalize();
  const btScalar head = std::min(btScalar(0.2) * length, btScalar(0.1));
  d.drawLine(to, to - dir * head + side * (head * btScalar(0.5)), colour);
  d.drawLine(to, to - dir * head - side * (head * btScalar(0.5)), colour);
}

btVector3 force_arrow(const btVector3& force, double mass, double gravity) {
  const double per_newton = mass > 0.0 ? kArrowPerWeight / (mass * gravity) : 1e-3;
  btVector3 v = force * btScalar(per_newton);
  const btScalar length = v.length();
  if (length > btScalar(kMaxArrow)) v *= btScalar(kMaxArrow) / length;
  return v;
}

}  // namespace debug_draw
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
