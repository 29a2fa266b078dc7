#include "shore/render/camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

namespace shore::render {
namespace {
double radians(double deg) { return deg * std::numbers::pi / 180.0; }

/// The view's forward, side (right) and up directions looking from eye to target (Z up;
/// straight down, the side is +x).
struct Axes {
  Eigen::Vector3d forward, side, up;
};
Axes axes(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d f = (target - eye).normalized();
  Eigen::Vector3d s = f.cross(Eigen::Vector3d::UnitZ());
  if (s.norm() < 1e-9) s = Eigen::Vector3d::UnitX();
  s.normalize();
  return {f, s, s.cross(f)};
}
}  // namespace

Eigen::Matrix4f look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Axes a = axes(eye, target);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = a.side.transpose();
  m.block<1, 3>(1, 0) = a.up.transpose();
  m.block<1, 3>(2, 0) = -a.forward.transpose();
  m(0, 3) = -a.side.dot(eye);
  m(1, 3) = -a.up.dot(eye);
  m(2, 3) = a.forward.dot(eye);
  return m.cast<float>();
}

Eigen::Vector3d OrbitCamera::eye() const {
  const double yaw = radians(yaw_deg), pitch = radians(pitch_deg);
  return target +
         distance * Eigen::Vector3d(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch));
}

Eigen::Matrix4f OrbitCamera::view() const { return look_at(eye(), target); }

Eigen::Matrix4f OrbitCamera::projection(double aspect) const {
  const double n = std::max(distance * 0.01, 1e-3), f = distance * 50.0 + 50.0;
  const double t = 1.0 / std::tan(radians(fov_deg) / 2.0);
  Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
  p(0, 0) = t / aspect;
  p(1, 1) = t;
  p(2, 2) = (f + n) / (n - f);
  p(2, 3) = 2.0 * f * n / (n - f);
  p(3, 2) = -1.0;
  return p.cast<float>();
}

Eigen::Vector3d OrbitCamera::ray(double ndc_x, double ndc_y, double aspect) const {
  const Axes a = axes(eye(), target);
  const double t = std::tan(radians(fov_deg) / 2.0);
  return (a.forward + a.side * (ndc_x * t * aspect) + a.up * (ndc_y * t)).normalized();
}

void OrbitCamera::orbit(double dx, double dy) {
  yaw_deg -= 0.3 * dx;
  pitch_deg = std::clamp(pitch_deg + 0.3 * dy, -89.0, 89.0);
}

void OrbitCamera::pan(double dx, double dy, double height) {
  const Axes a = axes(eye(), target);
  const double metres_per_pixel = 2.0 * distance * std::tan(radians(fov_deg) / 2.0) / std::max(height, 1.0);
  target += (-dx * a.side + dy * a.up) * metres_per_pixel;
}

void OrbitCamera::zoom(double steps) { distance = std::clamp(distance * std::pow(0.9, steps), 0.05, 1e4); }

OrbitCamera OrbitCamera::framing(const scenes::Bounds& b, double z, double aspect) {
  OrbitCamera c;
  c.frame(b, z, aspect);
  return c;
}

void OrbitCamera::frame(const scenes::Bounds& b, double z, double aspect) {
  OrbitCamera& c = *this;
  c.target = {0.5 * (b.x0 + b.x1), 0.5 * (b.y0 + b.y1), z};
  // The nearest eye (bisection on the distance) from which the four corners of the bounds
  // lie inside the view with a small margin.
  auto fits = [&](double d) {
    c.distance = d;
    const Eigen::Matrix4f m = c.projection(aspect) * c.view();
    for (const double x : {b.x0, b.x1})
      for (const double y : {b.y0, b.y1}) {
        const Eigen::Vector4f p = m * Eigen::Vector4f(float(x), float(y), float(z), 1.0f);
        if (p.w() <= 0 || std::abs(p.x() / p.w()) > 0.94 || std::abs(p.y() / p.w()) > 0.9) return false;
      }
    return true;
  };
  double lo = 0.05, hi = 1e4;
  for (int k = 0; k < 60; ++k) {
    const double mid = std::sqrt(lo * hi);
    (fits(mid) ? hi : lo) = mid;
  }
  c.distance = hi;
}

}  // namespace shore::render
