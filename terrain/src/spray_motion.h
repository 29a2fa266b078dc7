#pragma once
// Private: a body's rigid motion as spray reads it from its Imprint: a point p of it moves
// at v + w x (p - c); the body's frame (orientation q, about c) is where soil clings.

#include <cmath>

#include "shore/core/vec3.h"
#include "shore/terrain/terrain.h"

namespace shore::terrain {

[[nodiscard]] inline double length(const Vec3& a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

/// Whether |u| < min_speed, as length(u) < min_speed decides it (the same answer): sqrt is
/// correctly rounded and monotonic, so |u|^2 clear of min_speed^2 by a relative 2^-40
/// (thousands of ulps) decides it without the root; only in between is the root taken.
struct SpeedTest {
  explicit SpeedTest(double min_speed)
      : least(min_speed),
        below(min_speed * min_speed * (1.0 - 0x1.0p-40)),
        above(min_speed * min_speed * (1.0 + 0x1.0p-40)) {}
  [[nodiscard]] bool slower(const Vec3& u) const {
    const double s = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];  // as length() sums it
    if (s < below) return true;
    if (s > above) return false;
    return std::sqrt(s) < least;
  }
  double least, below, above;
};

struct BodyMotion {
  Vec3 v{}, w{}, c{};
  Quat q;                                              ///< normalised
  double r[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  ///< body to world

  /// A body that does not move, with this pose (a body seen last step, to set its soil down).
  BodyMotion(const Vec3& centre, const Quat& orientation);
  explicit BodyMotion(const Imprint& im);

  [[nodiscard]] Vec3 velocity_at(const Vec3& p) const {
    const Vec3 d = p - c;
    return {v.x + (w.y * d.z - w.z * d.y), v.y + (w.z * d.x - w.x * d.z), v.z + (w.x * d.y - w.y * d.x)};
  }
  /// World point -> body frame (relative to c).
  [[nodiscard]] Vec3 to_body(const Vec3& p) const {
    const Vec3 d = p - c;
    return {r[0][0] * d[0] + r[1][0] * d[1] + r[2][0] * d[2], r[0][1] * d[0] + r[1][1] * d[1] + r[2][1] * d[2],
            r[0][2] * d[0] + r[1][2] * d[1] + r[2][2] * d[2]};
  }
  [[nodiscard]] Vec3 to_world(const Vec3& b) const {
    return {c[0] + r[0][0] * b[0] + r[0][1] * b[1] + r[0][2] * b[2],
            c[1] + r[1][0] * b[0] + r[1][1] * b[1] + r[1][2] * b[2],
            c[2] + r[2][0] * b[0] + r[2][1] * b[1] + r[2][2] * b[2]};
  }

 private:
  void set_pose(const Vec3& centre, const Quat& orientation);
};

}  // namespace shore::terrain
