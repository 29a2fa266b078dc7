#pragma once
// Helpers shared by the water tests: mode shapes, projections and frequency estimates.

#include <cmath>
#include <numbers>
#include <vector>

#include "shore/water/surface.h"

namespace shore::water::testing {

/// sin(m pi i / (N-1)) sin(n pi j / (N-1)): a mode of a fixed-edge square of N x N nodes.
inline double mode_shape(int N, int m, int n, int i, int j) {
  const double L = N - 1;
  return std::sin(m * std::numbers::pi * i / L) * std::sin(n * std::numbers::pi * j / L);
}

/// A mode shape tabulated on the grid (index j * nx + i), for projections.
inline std::vector<double> tabulate_mode(int N, int m, int n) {
  std::vector<double> phi(static_cast<std::size_t>(N) * static_cast<std::size_t>(N));
  for (int j = 0; j < N; ++j)
    for (int i = 0; i < N; ++i) phi[static_cast<std::size_t>(j * N + i)] = mode_shape(N, m, n, i, j);
  return phi;
}

/// Least-squares projection of the heights onto a tabulated mode shape.
inline double project(const Surface& s, const std::vector<double>& phi) {
  const std::vector<double> uz = s.dense_state().uz;
  double num = 0.0, den = 0.0;
  for (std::size_t k = 0; k < phi.size(); ++k) {
    num += phi[k] * uz[k];
    den += phi[k] * phi[k];
  }
  return num / den;
}

/// Single-frequency fit of a sampled signal q_k (Prony): a sampled sinusoid satisfies
/// q_{k+1} + q_{k-1} = 2 cos(W dt) q_k; cos(W dt) by least squares over all samples.
/// Returns W (rad/s). residual receives max |q_{k+1} + q_{k-1} - 2 cos q_k| / max |q|.
inline double prony_frequency(const std::vector<double>& q, double dt, double* residual = nullptr) {
  double num = 0.0, den = 0.0, qmax = 0.0;
  for (std::size_t k = 1; k + 1 < q.size(); ++k) {
    num += q[k] * (q[k + 1] + q[k - 1]);
    den += 2.0 * q[k] * q[k];
  }
  const double cw = num / den;
  if (residual) {
    double r = 0.0;
    for (std::size_t k = 1; k + 1 < q.size(); ++k) r = std::max(r, std::abs(q[k + 1] + q[k - 1] - 2.0 * cw * q[k]));
    for (double v : q) qmax = std::max(qmax, std::abs(v));
    *residual = r / qmax;
  }
  return std::acos(cw) / dt;
}

/// Damped single-mode fit: q_{k+1} = a q_k + b q_{k-1} by least squares; a sampled damped
/// sinusoid A rho^k cos(theta k + phi) has b = -rho^2. Returns the amplitude decay rate
/// -ln(rho) / dt (1/s).
inline double prony_decay_rate(const std::vector<double>& q, double dt) {
  double s11 = 0, s12 = 0, s22 = 0, r1 = 0, r2 = 0;
  for (std::size_t k = 1; k + 1 < q.size(); ++k) {
    s11 += q[k] * q[k];
    s12 += q[k] * q[k - 1];
    s22 += q[k - 1] * q[k - 1];
    r1 += q[k + 1] * q[k];
    r2 += q[k + 1] * q[k - 1];
  }
  const double det = s11 * s22 - s12 * s12;
  const double b = (s11 * r2 - s12 * r1) / det;
  return -0.5 * std::log(-b) / dt;
}

}  // namespace shore::water::testing
