#pragma once
// Stability of the explicit (semi-implicit Euler) spring lattice, and how a step is split.
//
// Semi-implicit Euler (v += a dt, x += v dt) on a mode of angular frequency w with the
// damping force -gamma v (beta = gamma dt / m) is stable iff w^2 dt^2 < 2 (2 - beta) and
// beta < 2; undamped this is the familiar w dt < 2. A mode then oscillates at
// Omega = arccos(1 - w^2 dt^2 / 2) / dt.
//
// Highest frequency of the 3-D lattice (c stiffness, t = 1 - rest_ratio, m mass):
//  * at rest, in-plane modes are the stiffest: w_max^2 = (8 c + 4 c t) / m (wave vector
//    (pi, 0) on the lattice); vertical modes reach only 12 c t / m.
//  * in any configuration: each spring's Hessian is c n n^T + c (1 - L0 / l)(I - n n^T) <= c I,
//    and the 8-neighbour graph Laplacian has largest eigenvalue 12, so w_max^2 <= 12 c / m.
//  * deformation-aware bound used by the guard: with n the spring direction, e its rest
//    direction, sin(theta) = |n x e| and T = max(0, 1 - L0 / l),
//      Hessian <= c e e^T + c (T + sin(theta)) I,
//    and the rest-direction part has largest eigenvalue 8 c, hence
//      w_max^2 <= min(12 c, 8 c + 12 c (max T + max sin(theta))) / m.
//    At rest this is (8 c + 12 c t) / m, 5 % above the exact value for t = 0.1.
//  Constraints (fixed, vertical-only nodes) only remove degrees of freedom: the bounds hold.
// Vertical-only mode (linear): w_max^2 = 12 k_t / m exactly, k_t = c t.

#include "shore/water/parameters.h"

namespace shore::water {

/// Exact top frequency of the 3-D lattice at rest (rad/s): sqrt((8 c + 4 c t) / m).
double omega_max_at_rest(const LatticeParameters& p);
/// Top frequency of the vertical-only lattice (rad/s): sqrt(12 c t / m).
double omega_max_vertical(const LatticeParameters& p);
/// The guard's bound (rad/s) from the deformation measures max_tension = max over springs of
/// max(0, 1 - L0 / l) and max_sin = max over springs of sin(angle to the rest direction).
double omega_bound_3d(const LatticeParameters& p, double max_tension, double max_sin);

/// Oscillation frequency of a lattice mode of frequency w under semi-implicit Euler with
/// step dt (undamped): arccos(1 - w^2 dt^2 / 2) / dt. Requires w dt < 2.
double discrete_frequency(double omega, double dt);

/// How a step of length dt is split so that omega * dt_sub <= 2 * safety * sqrt(1 - beta / 2)
/// and beta = gamma dt_sub / m <= 0.5, with at most max_substeps substeps.
struct SubstepPlan {
  int substeps = 1;
  double substep = 0.0;       ///< s, length of each substep
  double simulated = 0.0;     ///< s, substeps * substep (< dt only when the cap was hit)
  bool time_clamped = false;  ///< the cap was hit: the step simulates less than dt
};
SubstepPlan plan_substeps(double omega, double dt, double mass, double damping, double safety, int max_substeps);

}  // namespace shore::water
