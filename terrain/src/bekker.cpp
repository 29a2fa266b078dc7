#include "shore/terrain/bekker.h"

#include <algorithm>
#include <cmath>

#include "shore/core/det_math.h"

namespace shore::terrain::bekker {

double pressure(const Material& m, double b, double z) {
  if (z <= 0.0) return 0.0;
  return (m.bekker_kc / b + m.bekker_kphi) * det::pow(z, m.bekker_n);
}

double plate_sinkage(const Material& m, double b, double p) {
  if (p <= 0.0) return 0.0;
  return det::pow(p / (m.bekker_kc / b + m.bekker_kphi), 1.0 / m.bekker_n);
}

double plate_sinkage_released(const Material& m, double b, double p) {
  return det::pow(m.bekker_n + 1.0, 1.0 / m.bekker_n) * plate_sinkage(m, b, p);
}

double wheel_sinkage_rolling(const Material& m, double W, double D, double b) {
  const double n = m.bekker_n;
  const double base = 3.0 * W / ((3.0 - n) * (m.bekker_kc + b * m.bekker_kphi) * std::sqrt(D));
  return det::pow(base, 2.0 / (2.0 * n + 1.0));
}

namespace {
// Load (N) carried by a wheel pressed to depth z0 with both halves of the contact bearing.
double static_wheel_load(const Material& m, double z0, double D, double b) {
  const double R = D / 2;
  const double x0 = std::sqrt(std::max(0.0, R * R - (R - z0) * (R - z0)));
  constexpr int kSteps = 4000;  // Simpson's rule; the integrand is smooth on [0, x0]
  const double h = x0 / kSteps;
  double sum = 0.0;
  for (int k = 0; k <= kSteps; ++k) {
    const double x = k * h;
    const double z = z0 - (R - std::sqrt(std::max(0.0, R * R - x * x)));
    const double f = pressure(m, b, z);
    sum += (k == 0 || k == kSteps ? 1.0 : (k % 2 ? 4.0 : 2.0)) * f;
  }
  return 2.0 * b * sum * h / 3.0;
}

// Depth (m) at which `halves` halves of the contact carry W (the load grows with depth).
double wheel_depth_carrying(const Material& m, double W, double D, double b, double halves) {
  double lo = 0.0, hi = D / 2;
  for (int it = 0; it < 200 && hi - lo > 1e-12; ++it) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * halves * static_wheel_load(m, mid, D, b) < W ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}
}  // namespace

double wheel_sinkage_static(const Material& m, double W, double D, double b) {
  return wheel_depth_carrying(m, W, D, b, 2.0);
}

double wheel_sinkage_rolling_integral(const Material& m, double W, double D, double b) {
  return wheel_depth_carrying(m, W, D, b, 1.0);
}

double wheel_compaction_resistance(const Material& m, double z0, double b) {
  const double n = m.bekker_n;
  return (m.bekker_kc + b * m.bekker_kphi) * det::pow(z0, n + 1.0) / (n + 1.0);
}

}  // namespace shore::terrain::bekker
