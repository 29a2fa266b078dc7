#include "shore/water/stability.h"

#include <algorithm>
#include <cmath>

namespace shore::water {

double omega_max_at_rest(const LatticeParameters& p) {
  const double t = 1.0 - p.rest_ratio;
  return std::sqrt((8.0 + 4.0 * t) * p.stiffness / p.mass);
}

double omega_max_vertical(const LatticeParameters& p) { return std::sqrt(12.0 * p.transverse_stiffness() / p.mass); }

double omega_bound_3d(const LatticeParameters& p, double max_tension, double max_sin) {
  const double deformation = std::max(0.0, max_tension) + std::max(0.0, max_sin);
  const double scaled = std::min(12.0, 8.0 + 12.0 * deformation);
  return std::sqrt(scaled * p.stiffness / p.mass);
}

double discrete_frequency(double omega, double dt) { return std::acos(1.0 - 0.5 * omega * omega * dt * dt) / dt; }

namespace {
bool substep_is_stable(double omega, double dt_sub, double mass, double damping, double safety) {
  const double beta = damping * dt_sub / mass;
  if (beta > 0.5) return false;
  return omega * dt_sub <= 2.0 * safety * std::sqrt(1.0 - 0.5 * beta);
}
}  // namespace

SubstepPlan plan_substeps(double omega, double dt, double mass, double damping, double safety, int max_substeps) {
  // First guess from the undamped limit, then grow while damping still breaks the test.
  const double limit = 2.0 * safety;
  double guess = std::ceil(omega * dt / limit);
  guess = std::max(guess, std::ceil(damping * dt / (0.5 * mass)));
  guess = std::max(guess, 1.0);
  SubstepPlan plan;
  if (!(guess <= static_cast<double>(max_substeps))) {
    guess = static_cast<double>(max_substeps);
  }
  auto n = static_cast<int>(guess);
  while (n < max_substeps && !substep_is_stable(omega, dt / n, mass, damping, safety)) ++n;
  plan.substeps = n;
  plan.substep = dt / n;
  if (!substep_is_stable(omega, plan.substep, mass, damping, safety)) {
    // Pathological dt: advance only max_substeps substeps of the largest stable length.
    double stable = limit / std::max(omega, 1e-300);
    stable = std::min(stable, 0.5 * mass / std::max(damping, 1e-300));
    while (!substep_is_stable(omega, stable, mass, damping, safety)) stable *= 0.99;
    plan.substep = std::min(plan.substep, stable);
    plan.time_clamped = true;
  }
  plan.simulated = plan.substeps * plan.substep;
  return plan;
}

}  // namespace shore::water
