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

Forces forces(const WongReeceWheel& w, double slip, double th1) {
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
  auto tau = [&](double th) {
    const double j = r * ((th1 - th) - (1.0 - slip) * (std::sin(th1) - std::sin(th)));
    return (m.cohesion + sigma(th) * tan_phi) * (1.0 - std::exp(-std::max(j, 0.0) / m.shear_modulus));
  };
  Forces f;
  f.vertical = r * b * simpson([&](double t) { return sigma(t) * std::cos(t) + tau(t) * std::sin(t); }, 0.0, th1);
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
    (forces(w, slip, mid).vertical < w.load ? lo : hi) = mid;
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

}  // namespace shore::scenes
