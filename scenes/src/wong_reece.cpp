#include "shore/scenes/wong_reece.h"

#include <algorithm>
#include <cmath>

namespace shore::scenes {

namespace {

template <class F>
double simpson(F&& f, double a, double b, int n = 400) {
  if (b <= a) return 0.0;
  const double h = (b - a) / n;
  double s = f(a) + f(b);
  for (int k = 1; k < n; ++k) s += (k % 2 ? 4.0 : 2.0) * f(a + k * h);
  return s * h / 3.0;
}

struct Forces {
  double vertical, thrust, resistance, torque;
};

/// The forces at entry angle th1; vertical_only: the vertical force alone (the others 0),
/// all the search for th1 needs.
Forces forces(const WongReeceWheel& w, double slip, double th1, bool vertical_only = false) {
  const terrain::Material& m = w.soil;
  const double r = w.radius, b = w.width, k = m.bekker_kc / b + m.bekker_kphi, tan_phi = std::tan(m.friction_angle);
  const double thm = w.front_only ? 0.0 : (w.c1 + w.c2 * slip) * th1;
  auto sigma = [&](double th) {
    double z = 0.0;
    if (th >= thm && th <= th1)
      z = r * (std::cos(th) - std::cos(th1));
    else if (th >= 0.0 && th < thm)  // the rear arc, mapped onto the front one
      z = r * (std::cos(th1 - th / thm * (th1 - thm)) - std::cos(th1));
    return k * std::pow(std::max(z, 0.0), m.bekker_n);
  };
  // Janosi and Hanamoto's shear along the rim's slip on the soil: forward (driving) where
  // the rim has slipped back over the soil, j > 0 (every point of a wheel at slip >= 0),
  // backward where it has slid forward, j < 0 (ahead of the bottom of a skidding wheel).
  auto tau = [&](double th) {
    const double j = r * ((th1 - th) - (1.0 - slip) * (std::sin(th1) - std::sin(th)));
    const double strength = m.cohesion + sigma(th) * tan_phi;
    return j >= 0.0 ? strength * (1.0 - std::exp(-j / m.shear_modulus))
                    : -strength * (1.0 - std::exp(j / m.shear_modulus));
  };
  Forces f{};
  f.vertical = r * b * simpson([&](double t) { return sigma(t) * std::cos(t) + tau(t) * std::sin(t); }, 0.0, th1);
  if (vertical_only) return f;
  f.thrust = r * b * simpson([&](double t) { return tau(t) * std::cos(t); }, 0.0, th1);
  f.resistance = r * b * simpson([&](double t) { return sigma(t) * std::sin(t); }, 0.0, th1);
  f.torque = r * r * b * simpson(tau, 0.0, th1);
  return f;
}

}  // namespace

WongReeceResult wong_reece(const WongReeceWheel& w, double slip) {
  double lo = 1e-4, hi = 1.2;
  for (int it = 0; it < 80; ++it) {
    const double mid = 0.5 * (lo + hi);
    (forces(w, slip, mid, true).vertical < w.load ? lo : hi) = mid;
  }
  const double th1 = 0.5 * (lo + hi);
  const Forces f = forces(w, slip, th1);
  WongReeceResult out;
  out.sinkage = w.radius * (1.0 - std::cos(th1));
  out.thrust = f.thrust;
  out.resistance = f.resistance;
  out.drawbar_pull = f.thrust - f.resistance;
  out.torque = f.torque;
  out.entry_angle = th1;
  return out;
}

TowedWongReeceResult wong_reece_towed(const WongReeceWheel& wheel) {
  // The torque grows with the slip; it vanishes at a small skid, where the shear ahead of
  // the bottom (backward) balances the shear behind it (forward).
  double lo = -0.9, hi = 0.5;
  for (int it = 0; it < 30; ++it) {  // the skid to 1e-9
    const double mid = 0.5 * (lo + hi);
    (wong_reece(wheel, mid).torque < 0.0 ? lo : hi) = mid;
  }
  TowedWongReeceResult out;
  out.slip = 0.5 * (lo + hi);
  out.wheel = wong_reece(wheel, out.slip);
  return out;
}

}  // namespace shore::scenes
