#include "spray_motion.h"

namespace shore::terrain {

BodyMotion::BodyMotion(const Vec3& centre, const Quat& orientation) { set_pose(centre, orientation); }

BodyMotion::BodyMotion(const Imprint& im) : v(im.velocity), w(im.angular_velocity) {
  set_pose(im.centre, im.orientation);
}

// The rotation matrix of the unit quaternion (validation keeps |q| within 1e-3 of 1; it is
// normalised here so the frame is exactly orthonormal to rounding).
void BodyMotion::set_pose(const Vec3& centre, const Quat& orientation) {
  c = centre;
  const Quat& o = orientation;
  const double n = std::sqrt(o.w * o.w + o.x * o.x + o.y * o.y + o.z * o.z);
  q = {o.w / n, o.x / n, o.y / n, o.z / n};
  const double w0 = q.w, x = q.x, y = q.y, z = q.z;
  r[0][0] = 1.0 - 2.0 * (y * y + z * z), r[0][1] = 2.0 * (x * y - w0 * z), r[0][2] = 2.0 * (x * z + w0 * y);
  r[1][0] = 2.0 * (x * y + w0 * z), r[1][1] = 1.0 - 2.0 * (x * x + z * z), r[1][2] = 2.0 * (y * z - w0 * x);
  r[2][0] = 2.0 * (x * z - w0 * y), r[2][1] = 2.0 * (y * z + w0 * x), r[2][2] = 1.0 - 2.0 * (x * x + y * y);
}

}  // namespace shore::terrain
