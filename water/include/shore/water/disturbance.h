#pragma once
// Additive disturbances of the water surface (the seed paper's way of making waves): a
// Gaussian bump of height or of vertical velocity, centred at a world point, or a rectangle
// with Gaussian-smoothed edges. Weights are tabulated per call along x and along y
// (the shapes are separable), so a disturbance costs (wx + wy) exponentials or erfs plus
// wx * wy multiply-adds, wx and wy being the covered node counts.

#include <vector>

namespace shore::water {

struct Disturbance {
  enum class Shape {
    point,  ///< A exp(-r^2 / (2 sigma^2)), r the horizontal distance to (x, y)
    area,   ///< A * box(x) * box(y): a rectangle of half sizes (half_x, half_y) centred at
            ///< (x, y) convolved with a unit Gaussian of std. dev. sigma; ~A well inside
  };
  enum class Target {
    height,             ///< adds to node heights (m)
    vertical_velocity,  ///< adds to node vertical velocities (m/s)
  };

  Shape shape = Shape::point;
  Target target = Target::height;
  double x = 0.0;          ///< m, world x of the centre, finite
  double y = 0.0;          ///< m, world y of the centre, finite
  double radius = 1.0;     ///< m, Gaussian std. dev. sigma, finite and > 0
  double amplitude = 0.0;  ///< m or m/s, finite, |A| <= the surface's cap (GuardSettings)
  double half_x = 0.0;     ///< m, area only: rectangle half size along x, finite and > 0
  double half_y = 0.0;     ///< m, area only: rectangle half size along y, finite and > 0

  /// Weights beyond this many sigmas from the shape are dropped (exp(-8) = 3.4e-4).
  static constexpr double kCutoffSigmas = 4.0;

  /// Throws shore::InvalidSetting (field named "water.Disturbance.<field>") on bad values.
  /// The amplitude cap is checked by the surface, which knows its scale.
  void validate() const;

  static Disturbance point_height(double x, double y, double radius, double amplitude);
  static Disturbance point_velocity(double x, double y, double radius, double amplitude);
  static Disturbance area_height(double x, double y, double half_x, double half_y, double radius, double amplitude);
  static Disturbance area_velocity(double x, double y, double half_x, double half_y, double radius, double amplitude);
};

/// One axis of a disturbance's weight table: nodes [first, first + weights.size()).
struct DisturbanceAxis {
  int first = 0;
  std::vector<double> weights;
};

/// The tabulated weights of a validated disturbance along one axis for a grid with nodes at
/// origin + k * spacing, k in [0, count). The node weight is axis_x[i] * axis_y[j].
DisturbanceAxis tabulate_axis(const Disturbance& d, double centre, double half, double origin, double spacing,
                              int count);

}  // namespace shore::water
