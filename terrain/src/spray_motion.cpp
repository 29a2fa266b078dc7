#include "spray_motion.h"

namespace shore::terrain {

BodyMotion::BodyMotion(const double centre[3], const double orientation[4]) { set_pose(centre, orientation); }

BodyMotion::BodyMotion(const Imprint& im) : v{im.vx, im.vy, im.vz}, w{im.wx, im.wy, im.wz} {
  const double centre[3] = {im.cx, im.cy, im.cz};
  const double orientation[4] = {im.qw, im.qx, im.qy, im.qz};
  set_pose(centre, orientation);
}

// The rotation matrix of the unit quaternion (validation keeps |q| within 1e-3 of 1; it is
// normalised here so the frame is exactly orthonormal to rounding).
void BodyMotion::set_pose(const double centre[3], const double orientation[4]) {
  c = {centre[0], centre[1], centre[2]};
  const double n = std::sqrt(orientation[0] * orientation[0] + orientation[1] * orientation[1] +
                             orientation[2] * orientation[2] + orientation[3] * orientation[3]);
  for (int k = 0; k < 4; ++k) q[k] = orientation[k] / n;
  const double w0 = q[0], x = q[1], y = q[2], z = q[3];
  r[0][0] = 1.0 - 2.0 * (y * y + z * z), r[0][1] = 2.0 * (x * y - w0 * z), r[0][2] = 2.0 * (x * z + w0 * y);
  r[1][0] = 2.0 * (x * y + w0 * z), r[1][1] = 1.0 - 2.0 * (x * x + z * z), r[1][2] = 2.0 * (y * z - w0 * x);
  r[2][0] = 2.0 * (x * z - w0 * y), r[2][1] = 2.0 * (y * z + w0 * x), r[2][2] = 1.0 - 2.0 * (x * x + y * y);
}

}  // namespace shore::terrain
