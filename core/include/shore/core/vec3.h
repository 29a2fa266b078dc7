#pragma once
// The one 3-vector of Shore's own code (Bullet's btVector3 stays at the Bullet boundary):
// double precision, world frame unless a name says otherwise.

#include <cmath>

namespace shore {

struct Vec3 {
  double x = 0.0, y = 0.0, z = 0.0;

  [[nodiscard]] constexpr double operator[](int k) const noexcept { return k == 0 ? x : (k == 1 ? y : z); }
  [[nodiscard]] constexpr double& operator[](int k) noexcept { return k == 0 ? x : (k == 1 ? y : z); }
  friend constexpr bool operator==(const Vec3&, const Vec3&) = default;
};

constexpr Vec3 operator+(Vec3 a, Vec3 b) noexcept { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
constexpr Vec3 operator-(Vec3 a, Vec3 b) noexcept { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
constexpr Vec3 operator-(Vec3 a) noexcept { return {-a.x, -a.y, -a.z}; }
constexpr Vec3 operator*(Vec3 a, double s) noexcept { return {a.x * s, a.y * s, a.z * s}; }
constexpr double dot(Vec3 a, Vec3 b) noexcept { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(Vec3 a, Vec3 b) noexcept {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm(Vec3 a) noexcept { return std::sqrt(dot(a, a)); }
inline bool finite(Vec3 a) noexcept { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }

/// A rotation as a unit quaternion w + x i + y j + z k.
struct Quat {
  double w = 1.0, x = 0.0, y = 0.0, z = 0.0;
  friend constexpr bool operator==(const Quat&, const Quat&) = default;
};

}  // namespace shore
