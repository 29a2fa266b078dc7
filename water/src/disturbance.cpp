#include "shore/water/disturbance.h"

#include <algorithm>
#include <cmath>

#include "shore/core/det_math.h"
#include "shore/core/error.h"

namespace shore::water {

void Disturbance::validate() const {
  const Check c{"water.Disturbance"};
  c.finite("x", x);
  c.finite("y", y);
  c.positive("radius", radius);
  c.finite("amplitude", amplitude);
  if (shape == Shape::area) {
    c.positive("half_x", half_x);
    c.positive("half_y", half_y);
  }
}

Disturbance Disturbance::point_height(double x, double y, double radius, double amplitude) {
  Disturbance d;
  d.x = x;
  d.y = y;
  d.radius = radius;
  d.amplitude = amplitude;
  return d;
}

Disturbance Disturbance::point_velocity(double x, double y, double radius, double amplitude) {
  Disturbance d = point_height(x, y, radius, amplitude);
  d.target = Target::vertical_velocity;
  return d;
}

Disturbance Disturbance::area_height(double x, double y, double half_x, double half_y, double radius,
                                     double amplitude) {
  Disturbance d = point_height(x, y, radius, amplitude);
  d.shape = Shape::area;
  d.half_x = half_x;
  d.half_y = half_y;
  return d;
}

Disturbance Disturbance::area_velocity(double x, double y, double half_x, double half_y, double radius,
                                       double amplitude) {
  Disturbance d = area_height(x, y, half_x, half_y, radius, amplitude);
  d.target = Target::vertical_velocity;
  return d;
}

namespace {
/// exp(-s^2/2) for a point; the unit box [-half, half] convolved with a unit Gaussian.
double axis_weight(const Disturbance& d, double offset, double half) {
  const double sigma = d.radius;
  if (d.shape == Disturbance::Shape::point) {
    const double s = offset / sigma;
    return det::exp(-0.5 * s * s);
  }
  const double k = 1.0 / (std::sqrt(2.0) * sigma);
  return 0.5 * (det::erf((offset + half) * k) - det::erf((offset - half) * k));
}
}  // namespace

DisturbanceAxis tabulate_axis(const Disturbance& d, double centre, double half, double origin, double spacing,
                              int count) {
  const double reach = (d.shape == Disturbance::Shape::area ? half : 0.0) + Disturbance::kCutoffSigmas * d.radius;
  const double lo = std::ceil((centre - reach - origin) / spacing);
  const double hi = std::floor((centre + reach - origin) / spacing);
  DisturbanceAxis axis;
  const double first = std::max(lo, 0.0);
  const double last = std::min(hi, static_cast<double>(count - 1));
  if (!(first <= last)) return axis;
  axis.first = static_cast<int>(first);
  const int n = static_cast<int>(last) - axis.first + 1;
  axis.weights.resize(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    // Offsets in index space first, so nodes mirrored about a centre on a node get
    // bit-identical weights.
    const double offset = ((axis.first + k) - (centre - origin) / spacing) * spacing;
    axis.weights[static_cast<std::size_t>(k)] = axis_weight(d, offset, half);
  }
  return axis;
}

}  // namespace shore::water
