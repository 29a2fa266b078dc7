#include "shore/water/reference_surface.h"

#include <cmath>

#if defined(__x86_64__) || defined(__i386__)
#include <xmmintrin.h>
#endif

#include "shore/core/error.h"
#include "shore/water/stability.h"
#include "surface_state.h"

namespace shore::water {

ReferenceSurface::ReferenceSurface(const SurfaceSettings& settings) : settings_(settings) {
  settings_.validate();
  nodes_.resize(static_cast<std::size_t>(settings_.nx) * static_cast<std::size_t>(settings_.ny));
  // The same edge constraints as Surface (the reference has no open boundary's layer).
  for (int j = 0; j < settings_.ny; ++j)
    for (int i = 0; i < settings_.nx; ++i)
      set_constraint(i, j, default_constraint(settings_.boundary, i, j, settings_.nx, settings_.ny));
}

void ReferenceSurface::set_constraint(int i, int j, NodeConstraint c) {
  const Check check{"water.ReferenceSurface.set_constraint"};
  check.in_closed("i", i, 0, settings_.nx - 1);
  check.in_closed("j", j, 0, settings_.ny - 1);
  Node& n = nodes_[static_cast<std::size_t>(j) * static_cast<std::size_t>(settings_.nx) + static_cast<std::size_t>(i)];
  n.constraint = c;
  if (c != NodeConstraint::free && settings_.mode == SurfaceMode::full_3d) n.v[0] = n.v[1] = 0.f;
  if (c == NodeConstraint::fixed) n.v[2] = 0.f;
}

void ReferenceSurface::disturb(const Disturbance& d) {
  d.validate();
  const LatticeParameters& p = settings_.lattice;
  const bool height = d.target == Disturbance::Target::height;
  const double omega = settings_.mode == SurfaceMode::full_3d ? omega_max_at_rest(p) : omega_max_vertical(p);
  const double cap = settings_.guard.max_disturbance_spacings * p.spacing * (height ? 1.0 : omega);
  if (!(std::abs(d.amplitude) <= cap))
    throw InvalidSetting("water.Disturbance.amplitude", detail::to_text(d.amplitude),
                         "must be within +-" + detail::to_text(cap));
  const DisturbanceAxis ax = tabulate_axis(d, d.x, d.half_x, settings_.origin_x, p.spacing, settings_.nx);
  const DisturbanceAxis ay = tabulate_axis(d, d.y, d.half_y, settings_.origin_y, p.spacing, settings_.ny);
  for (std::size_t b = 0; b < ay.weights.size(); ++b) {
    for (std::size_t a = 0; a < ax.weights.size(); ++a) {
      const int i = ax.first + static_cast<int>(a), j = ay.first + static_cast<int>(b);
      Node& n =
          nodes_[static_cast<std::size_t>(j) * static_cast<std::size_t>(settings_.nx) + static_cast<std::size_t>(i)];
      if (n.constraint == NodeConstraint::fixed) continue;
      float& target = height ? n.u[2] : n.v[2];
      target += static_cast<float>(d.amplitude * ay.weights[b] * ax.weights[a]);
    }
  }
}

void ReferenceSurface::step(double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw InvalidSetting("water.ReferenceSurface.step.dt", detail::to_text(dt), "must be finite and > 0");
#if defined(__x86_64__) || defined(__i386__)
  // Subnormals flushed to zero as in the fast kernel (a wave's leading edge underflows;
  // subnormal arithmetic is ~100x slower), so the two are compared on their algorithms.
  const unsigned saved = _mm_getcsr();
  _mm_setcsr(saved | 0x8040u);
#endif
  for (Node& n : nodes_) n.f[0] = n.f[1] = n.f[2] = 0.f;
  if (settings_.mode == SurfaceMode::full_3d) {
    accumulate_3d_springs();
  } else {
    accumulate_vertical_springs();
  }
  update(dt);
#if defined(__x86_64__) || defined(__i386__)
  _mm_setcsr(saved);
#endif
}

void ReferenceSurface::add_spring(Node& a, Node& b, double rest_dx, double rest_dy, double rest_length) {
  // f = c (x_b - x_a) (1 - L0 / l) on a, the opposite on b (the paper's formula (1)').
  const auto c = static_cast<float>(settings_.lattice.stiffness);
  float d[3];
  d[0] = static_cast<float>(rest_dx) + (b.u[0] - a.u[0]);
  d[1] = static_cast<float>(rest_dy) + (b.u[1] - a.u[1]);
  d[2] = b.u[2] - a.u[2];
  const float l = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (!(l > 0.f)) return;
  const float s = c * (1.f - static_cast<float>(rest_length) / l);
  for (int k = 0; k < 3; ++k) {
    a.f[k] += s * d[k];
    b.f[k] -= s * d[k];
  }
}

void ReferenceSurface::accumulate_3d_springs() {
  const int nx = settings_.nx, ny = settings_.ny;
  const double h = settings_.lattice.spacing;
  const double rest = settings_.lattice.rest_ratio * h, rest_diag = std::sqrt(2.0) * rest;
  const auto at = [&](int i, int j) -> Node& {
    return nodes_[static_cast<std::size_t>(j) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(i)];
  };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      if (i + 1 < nx) add_spring(at(i, j), at(i + 1, j), h, 0.0, rest);
      if (j + 1 < ny) add_spring(at(i, j), at(i, j + 1), 0.0, h, rest);
      if (i + 1 < nx && j + 1 < ny) {
        add_spring(at(i, j), at(i + 1, j + 1), h, h, rest_diag);
        add_spring(at(i + 1, j), at(i, j + 1), -h, h, rest_diag);
      }
    }
  }
}

void ReferenceSurface::accumulate_vertical_springs() {
  // Linearised vertical force of each pre-tensioned spring: k_t (w_b - w_a).
  const int nx = settings_.nx, ny = settings_.ny;
  const auto kt = static_cast<float>(settings_.lattice.transverse_stiffness());
  const auto at = [&](int i, int j) -> Node& {
    return nodes_[static_cast<std::size_t>(j) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(i)];
  };
  const auto spring = [kt](Node& a, Node& b) {
    const float f = kt * (b.u[2] - a.u[2]);
    a.f[2] += f;
    b.f[2] -= f;
  };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      if (i + 1 < nx) spring(at(i, j), at(i + 1, j));
      if (j + 1 < ny) spring(at(i, j), at(i, j + 1));
      if (i + 1 < nx && j + 1 < ny) {
        spring(at(i, j), at(i + 1, j + 1));
        spring(at(i + 1, j), at(i, j + 1));
      }
    }
  }
}

void ReferenceSurface::update(double dt) {
  // a = (f - gamma v) / m;  v += a dt;  x += v dt  (the paper's scheme).
  const LatticeParameters& p = settings_.lattice;
  const auto m = static_cast<float>(p.mass), gamma = static_cast<float>(p.damping), h = static_cast<float>(dt);
  const bool full = settings_.mode == SurfaceMode::full_3d;
  for (Node& n : nodes_) {
    if (n.constraint == NodeConstraint::fixed) continue;
    const int first = (full && n.constraint == NodeConstraint::free) ? 0 : 2;
    for (int k = first; k < 3; ++k) {
      const float a = (n.f[k] - gamma * n.v[k]) / m;
      n.v[k] += a * h;
      n.u[k] += n.v[k] * h;
    }
  }
}

}  // namespace shore::water
