#pragma once
// An orbit camera (Z up): it looks at a target from `distance` metres, at an azimuth (yaw)
// and an elevation (pitch); the mouse orbits, pans and zooms it.

#include <Eigen/Core>

#include "shore/scenes/contents.h"

namespace shore::render {

/// The view matrix of an eye looking at a target (Z up; straight down, +x is to the right).
Eigen::Matrix4f look_at(const Eigen::Vector3d& eye, const Eigen::Vector3d& target);

struct OrbitCamera {
  Eigen::Vector3d target{0.0, 0.0, 0.0};  ///< m, the point looked at
  double yaw_deg = -70.0;                 ///< azimuth of the eye about the target, degrees from +x (counter-clockwise)
  double pitch_deg = 35.0;                ///< elevation of the eye above the target's horizon, degrees, in [-89, 89]
  double distance = 5.0;                  ///< m from the target, > 0
  double fov_deg = 40.0;                  ///< vertical field of view, degrees

  [[nodiscard]] Eigen::Vector3d eye() const;
  [[nodiscard]] Eigen::Matrix4f view() const;
  [[nodiscard]] Eigen::Matrix4f projection(double aspect) const;
  /// Ray from the eye through normalised device coordinates (x, y) in [-1, 1] (y up).
  [[nodiscard]] Eigen::Vector3d ray(double ndc_x, double ndc_y, double aspect) const;

  /// Mouse drags in pixels of a viewport `height` pixels high.
  void orbit(double dx_pixels, double dy_pixels);
  void pan(double dx_pixels, double dy_pixels, double height_pixels);
  /// Scroll steps: each brings the eye 10 % closer (negative: farther).
  void zoom(double steps);

  /// The camera at the default yaw and pitch nearest to the bounds (at height z) that
  /// shows all of them in a view of this aspect (width / height).
  static OrbitCamera framing(const scenes::Bounds& bounds, double z = 0.0, double aspect = 16.0 / 9.0);
  /// Keeps yaw, pitch and field of view; looks at the bounds' centre (at height z) from
  /// the nearest distance that shows all of them in a view of this aspect.
  void frame(const scenes::Bounds& bounds, double z, double aspect);
};

}  // namespace shore::render
