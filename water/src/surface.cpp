#include "shore/water/surface.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include <omp.h>
#include <Eigen/Geometry>

#include "kernel.h"
#include "shore/core/error.h"
#include "shore/core/hash.h"
#include "shore/water/stability.h"

namespace shore::water {

namespace {

constexpr double kSqrt2 = 1.4142135623730951;

/// The four spring families, each joining (i, j) to (i + di, j + dj); anti-diagonal springs
/// start at (i + 1, j). Rest offsets in units of h.
struct SpringFamily {
  int ai, aj, bi, bj;  ///< first and second end, relative to the cell corner (i, j)
  double rest_scale;   ///< rest length / (rest_ratio h): 1 or sqrt(2)
};
constexpr SpringFamily kFamilies[4] = {
    {0, 0, 1, 0, 1.0},     // horizontal
    {0, 0, 0, 1, 1.0},     // vertical
    {0, 0, 1, 1, kSqrt2},  // diagonal
    {1, 0, 0, 1, kSqrt2},  // anti-diagonal
};

/// Calls fn(a, b, family) for every spring of an nx x ny grid, a and b node indices.
template <class Fn>
void for_each_spring(int nx, int ny, Fn&& fn) {
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      for (const SpringFamily& f : kFamilies) {
        const int ai = i + f.ai, aj = j + f.aj, bi = i + f.bi, bj = j + f.bj;
        if (ai >= nx || bi >= nx || aj >= ny || bj >= ny) continue;
        const auto a = static_cast<std::size_t>(aj) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(ai);
        const auto b = static_cast<std::size_t>(bj) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(bi);
        fn(a, b, f);
      }
    }
  }
}

}  // namespace

Surface::Surface(const SurfaceSettings& settings) : settings_(settings) {
  settings_.validate();
  avx2_ = settings_.kernel == KernelChoice::avx2 ||
          (settings_.kernel == KernelChoice::automatic && kernel::avx2_available());
  const std::size_t n = node_count();
  const bool full = settings_.mode == SurfaceMode::full_3d;
  const std::size_t fields = full ? 6 : 2;
  const std::size_t stride = ((n + 15) & ~std::size_t{15}) + 48;  // + 192 bytes per field
  storage_.assign(fields * stride + 16, 0.f);
  float* base = storage_.data();
  float** targets[6] = {&uz_, &vz_, &ux_, &uy_, &vx_, &vy_};
  for (std::size_t f = 0; f < fields; ++f) *targets[f] = base + f * stride;
  constraints_.assign(n, NodeConstraint::free);
  apply_boundary(settings_.boundary);
  threads_ = settings_.threads;
}

std::size_t Surface::index(int i, int j) const {
  return static_cast<std::size_t>(j) * static_cast<std::size_t>(nx()) + static_cast<std::size_t>(i);
}

void Surface::check_index(const char* what, int i, int j) const {
  const Check c{std::string("water.Surface.") + what};
  c.in_closed("i", i, 0, nx() - 1);
  c.in_closed("j", j, 0, ny() - 1);
}

void Surface::set_threads(int threads) {
  Check{"water.Surface"}.at_least("threads", threads, 0);
  threads_ = threads;
}

const char* Surface::fast_kernel_isa() { return kernel::avx2_available() ? "avx2" : "generic"; }

bool Surface::kernel_available(KernelChoice choice) { return choice != KernelChoice::avx2 || kernel::avx2_available(); }

// ---- stepping ------------------------------------------------------------------------------

namespace {
/// The kernel's view of the state. The measure pass only reads through it.
kernel::Grid make_grid(int nx, int ny, const float* ux, const float* uy, const float* uz, const float* vx,
                       const float* vy, const float* vz, const std::vector<NodeConstraint>& constraints) {
  kernel::Grid g;
  g.nx = nx;
  g.ny = ny;
  g.ux = const_cast<float*>(ux);
  g.uy = const_cast<float*>(uy);
  g.uz = const_cast<float*>(uz);
  g.vx = const_cast<float*>(vx);
  g.vy = const_cast<float*>(vy);
  g.vz = const_cast<float*>(vz);
  g.flags = reinterpret_cast<const std::uint8_t*>(constraints.data());
  return g;
}

kernel::Coefficients make_coefficients(const SurfaceSettings& s, double dt) {
  const LatticeParameters& p = s.lattice;
  kernel::Coefficients k;
  k.h = static_cast<float>(p.spacing);
  k.c = static_cast<float>(s.mode == SurfaceMode::full_3d ? p.stiffness : p.transverse_stiffness());
  k.rest = static_cast<float>(p.rest_ratio * p.spacing);
  k.rest_diag = static_cast<float>(kSqrt2 * p.rest_ratio * p.spacing);
  k.damping = static_cast<float>(p.damping);
  k.impulse = static_cast<float>(dt / p.mass);
  k.dt = static_cast<float>(dt);
  return k;
}

/// Explicit thread counts are honoured; the default (0) takes OpenMP's count but at most one
/// thread per 16384 nodes, as fork/join costs more than it saves on small grids.
int resolve_threads(int threads, std::size_t nodes) {
  if (threads > 0) return threads;
  const auto by_size = static_cast<int>(std::min<std::size_t>(nodes / 16384u, 1024u));
  return std::max(1, std::min(omp_get_max_threads(), by_size));
}
}  // namespace

namespace {
float from_bits(std::uint32_t b) { return std::bit_cast<float>(b); }

/// Turns the kernel's raw measures into the guard's (max tension, max sin), for positions
/// that may have moved by up to `slack` along every spring since they were measured:
/// lengths and across-components grow or shrink by at most slack.
Deformation deformation_of(const kernel::Extremes& e, const kernel::Coefficients& k, double slack_axis,
                           double slack_diag) {
  const auto family = [](double rest, std::uint32_t longest2, std::uint32_t shortest2, std::uint32_t across2,
                         double slack, double& tension, double& sine) {
    const double longest = std::sqrt(static_cast<double>(from_bits(longest2))) + slack;
    const double shortest = std::sqrt(static_cast<double>(from_bits(shortest2))) - slack;
    const double across = std::sqrt(static_cast<double>(from_bits(across2))) + slack;
    tension = std::max(tension, longest > 0.0 ? 1.0 - rest / longest : 0.0);
    sine = std::max(sine, shortest > 0.0 ? std::min(1.0, across / shortest) : 1.0);
  };
  Deformation d;
  family(k.rest, e.long_axis, e.short_axis, e.across_axis, slack_axis, d.max_tension, d.max_sin);
  family(k.rest_diag, e.long_diag, e.short_diag, e.across_diag, slack_diag, d.max_tension, d.max_sin);
  return d;
}
}  // namespace

double Surface::omega_bound() const {
  const LatticeParameters& p = settings_.lattice;
  if (settings_.mode == SurfaceMode::vertical_only) return omega_max_vertical(p);
  if (!deformation_) {
    const kernel::Grid g = make_grid(nx(), ny(), ux_, uy_, uz_, vx_, vy_, vz_, constraints_);
    const kernel::Coefficients k = make_coefficients(settings_, 1.0);
    deformation_ =
        deformation_of(kernel::measure_3d(avx2_, g, k, resolve_threads(threads_, node_count())), k, 0.0, 0.0);
  }
  return omega_bound_3d(p, deformation_->max_tension, deformation_->max_sin);
}

StepStats Surface::step(double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw InvalidSetting("water.Surface.step.dt", detail::to_text(dt), "must be finite and > 0");
  const LatticeParameters& p = settings_.lattice;
  const GuardSettings& guard = settings_.guard;
  double omega = omega_bound();
  SubstepPlan plan = plan_substeps(omega, dt, p.mass, p.damping, guard.safety, guard.max_substeps);
  StepStats stats;
  stats.omega_bound = omega;
  stats.time_clamped = plan.time_clamped;
  int left = plan.substeps;
  double remaining = dt;
  while (left > 0 && stats.substeps < guard.max_substeps) {
    step_substep(plan.substep);
    --left;
    ++stats.substeps;
    stats.simulated += plan.substep;
    remaining -= plan.substep;
    last_substep_ = plan.substep;
    if (left == 0) break;
    // The lattice may have stiffened during the substep: re-plan what is left if needed.
    omega = omega_bound();
    stats.omega_bound = std::max(stats.omega_bound, omega);
    if (omega * plan.substep > 2.0 * guard.safety * std::sqrt(1.0 - 0.5 * p.damping * plan.substep / p.mass)) {
      const int budget = guard.max_substeps - stats.substeps;
      if (budget < 1) {
        stats.time_clamped = true;
        break;
      }
      plan = plan_substeps(omega, remaining, p.mass, p.damping, guard.safety, budget);
      stats.time_clamped = stats.time_clamped || plan.time_clamped;
      left = plan.substeps;
    }
  }
  stats.substep = stats.simulated / stats.substeps;
  last_stats_ = stats;
  time_ += stats.simulated;
  return stats;
}

void Surface::step_substep(double dt) {
  const int threads = resolve_threads(threads_, node_count());
  workspace_.resize(kernel::workspace_floats_per_thread(nx()) * static_cast<std::size_t>(threads));
  const kernel::Grid g = make_grid(nx(), ny(), ux_, uy_, uz_, vx_, vy_, vz_, constraints_);
  const kernel::Coefficients k = make_coefficients(settings_, dt);
  if (settings_.mode == SurfaceMode::full_3d) {
    const kernel::Extremes e = kernel::step_3d(avx2_, g, k, threads, workspace_.data());
    // Measured on the positions the substep started from; then every spring vector moved by
    // (v_b - v_a) dt with the new velocities: at most r dt for an axis spring, 2 r dt for a
    // diagonal (r the largest axis relative speed), plus a hair for rounding.
    const double slack =
        std::sqrt(static_cast<double>(from_bits(e.relative))) * dt * (1.0 + 1e-6) + 1e-7 * settings_.lattice.spacing;
    deformation_ = deformation_of(e, k, slack, 2.0 * slack);
  } else {
    kernel::step_vertical(avx2_, g, k, threads, workspace_.data());
  }
}

// ---- constraints ---------------------------------------------------------------------------

void Surface::set_constraint(int i, int j, NodeConstraint c) {
  check_index("set_constraint", i, j);
  const auto raw = static_cast<int>(c);
  Check{"water.Surface.set_constraint"}.in_closed("constraint", raw, 0, 2);
  const std::size_t k = index(i, j);
  constraints_[k] = c;
  if (c == NodeConstraint::fixed) vz_[k] = 0.f;
  if (c != NodeConstraint::free && settings_.mode == SurfaceMode::full_3d) {
    vx_[k] = 0.f;
    vy_[k] = 0.f;
  }
}

NodeConstraint Surface::constraint(int i, int j) const {
  check_index("constraint", i, j);
  return constraints_[index(i, j)];
}

void Surface::apply_boundary(Boundary b) {
  const NodeConstraint c = b == Boundary::fixed           ? NodeConstraint::fixed
                           : b == Boundary::vertical_only ? NodeConstraint::vertical_only
                                                          : NodeConstraint::free;
  for (int i = 0; i < nx(); ++i) {
    set_constraint(i, 0, c);
    set_constraint(i, ny() - 1, c);
  }
  for (int j = 0; j < ny(); ++j) {
    set_constraint(0, j, c);
    set_constraint(nx() - 1, j, c);
  }
}

// ---- disturbances --------------------------------------------------------------------------

double Surface::velocity_cap() const {
  const LatticeParameters& p = settings_.lattice;
  const double omega = settings_.mode == SurfaceMode::full_3d ? omega_max_at_rest(p) : omega_max_vertical(p);
  return settings_.guard.max_disturbance_spacings * p.spacing * omega;
}

void Surface::disturb(std::span<const Disturbance> ds) {
  const double height_cap = settings_.guard.max_disturbance_spacings * spacing();
  const double speed_cap = velocity_cap();
  for (const Disturbance& d : ds) {
    d.validate();
    const bool height = d.target == Disturbance::Target::height;
    const double cap = height ? height_cap : speed_cap;
    if (!(std::abs(d.amplitude) <= cap))
      throw InvalidSetting("water.Disturbance.amplitude", detail::to_text(d.amplitude),
                           "must be within +-" + detail::to_text(cap) + (height ? " m" : " m/s") +
                               " (GuardSettings::max_disturbance_spacings)");
  }
  deformation_.reset();
  for (const Disturbance& d : ds) {
    const DisturbanceAxis ax = tabulate_axis(d, d.x, d.half_x, settings_.origin_x, spacing(), nx());
    const DisturbanceAxis ay = tabulate_axis(d, d.y, d.half_y, settings_.origin_y, spacing(), ny());
    float* target = d.target == Disturbance::Target::height ? uz_ : vz_;
    for (std::size_t b = 0; b < ay.weights.size(); ++b) {
      const double wy = d.amplitude * ay.weights[b];
      const int j = ay.first + static_cast<int>(b);
      for (std::size_t a = 0; a < ax.weights.size(); ++a) {
        const std::size_t k = index(ax.first + static_cast<int>(a), j);
        if (constraints_[k] == NodeConstraint::fixed) continue;
        target[k] += static_cast<float>(wy * ax.weights[a]);
      }
    }
  }
}

// ---- node access ---------------------------------------------------------------------------

double Surface::height(int i, int j) const {
  check_index("height", i, j);
  return settings_.rest_height + static_cast<double>(uz_[index(i, j)]);
}

double Surface::vertical_velocity(int i, int j) const {
  check_index("vertical_velocity", i, j);
  return static_cast<double>(vz_[index(i, j)]);
}

bool Surface::add_height(int i, int j, double dz) {
  check_index("add_height", i, j);
  const double cap = settings_.guard.max_disturbance_spacings * spacing();
  if (!(std::abs(dz) <= cap))
    throw InvalidSetting("water.Surface.add_height.dz", detail::to_text(dz),
                         "must be finite and within +-" + detail::to_text(cap) + " m");
  const std::size_t k = index(i, j);
  if (constraints_[k] == NodeConstraint::fixed) return false;
  deformation_.reset();
  uz_[k] += static_cast<float>(dz);
  return true;
}

bool Surface::add_vertical_velocity(int i, int j, double dv) {
  check_index("add_vertical_velocity", i, j);
  const double cap = velocity_cap();
  if (!(std::abs(dv) <= cap))
    throw InvalidSetting("water.Surface.add_vertical_velocity.dv", detail::to_text(dv),
                         "must be finite and within +-" + detail::to_text(cap) + " m/s");
  const std::size_t k = index(i, j);
  if (constraints_[k] == NodeConstraint::fixed) return false;
  vz_[k] += static_cast<float>(dv);
  return true;
}

Eigen::Vector3d Surface::position(int i, int j) const {
  check_index("position", i, j);
  const std::size_t k = index(i, j);
  const bool full = settings_.mode == SurfaceMode::full_3d;
  return {node_x(i) + (full ? static_cast<double>(ux_[k]) : 0.0),
          node_y(j) + (full ? static_cast<double>(uy_[k]) : 0.0), settings_.rest_height + static_cast<double>(uz_[k])};
}

Eigen::Vector3d Surface::velocity(int i, int j) const {
  check_index("velocity", i, j);
  const std::size_t k = index(i, j);
  const bool full = settings_.mode == SurfaceMode::full_3d;
  return {full ? static_cast<double>(vx_[k]) : 0.0, full ? static_cast<double>(vy_[k]) : 0.0,
          static_cast<double>(vz_[k])};
}

// ---- world <-> node ------------------------------------------------------------------------

Eigen::Vector2d Surface::grid_coordinates(double x, double y) const {
  return {(x - settings_.origin_x) / spacing(), (y - settings_.origin_y) / spacing()};
}

std::optional<NodeIndex> Surface::nearest_node(double x, double y) const {
  const Eigen::Vector2d g = grid_coordinates(x, y);
  const double i = std::floor(g.x() + 0.5), j = std::floor(g.y() + 0.5);
  if (!(i >= 0.0 && j >= 0.0 && i <= nx() - 1 && j <= ny() - 1)) return std::nullopt;
  return NodeIndex{static_cast<int>(i), static_cast<int>(j)};
}

bool Surface::contains(double x, double y) const {
  const Eigen::Vector2d g = grid_coordinates(x, y);
  return g.x() >= 0.0 && g.y() >= 0.0 && g.x() <= nx() - 1 && g.y() <= ny() - 1;
}

namespace {
/// Bilinear sample of a node field at continuous grid coordinates, clamped to the grid.
double bilinear(const float* field, int nx, int ny, Eigen::Vector2d g) {
  const double gx = std::clamp(std::isfinite(g.x()) ? g.x() : 0.0, 0.0, static_cast<double>(nx - 1));
  const double gy = std::clamp(std::isfinite(g.y()) ? g.y() : 0.0, 0.0, static_cast<double>(ny - 1));
  const int i = std::min(static_cast<int>(gx), nx - 2), j = std::min(static_cast<int>(gy), ny - 2);
  const double s = gx - i, t = gy - j;
  const auto at = [&](int a, int b) {
    return static_cast<double>(
        field[static_cast<std::size_t>(b) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(a)]);
  };
  return (1 - t) * ((1 - s) * at(i, j) + s * at(i + 1, j)) + t * ((1 - s) * at(i, j + 1) + s * at(i + 1, j + 1));
}
}  // namespace

double Surface::height_at(double x, double y) const {
  return settings_.rest_height + bilinear(uz_, nx(), ny(), grid_coordinates(x, y));
}

double Surface::vertical_velocity_at(double x, double y) const {
  return bilinear(vz_, nx(), ny(), grid_coordinates(x, y));
}

// ---- output --------------------------------------------------------------------------------

void Surface::positions(std::vector<float>& xyz) const {
  xyz.resize(3 * node_count());
  const bool full = settings_.mode == SurfaceMode::full_3d;
  for (int j = 0; j < ny(); ++j) {
    for (int i = 0; i < nx(); ++i) {
      const std::size_t k = index(i, j);
      xyz[3 * k + 0] = static_cast<float>(node_x(i) + (full ? ux_[k] : 0.f));
      xyz[3 * k + 1] = static_cast<float>(node_y(j) + (full ? uy_[k] : 0.f));
      xyz[3 * k + 2] = static_cast<float>(settings_.rest_height + uz_[k]);
    }
  }
}

void Surface::normals(std::vector<float>& xyz) const {
  xyz.resize(3 * node_count());
  const bool full = settings_.mode == SurfaceMode::full_3d;
  const double h = spacing();
  // Differences in the displacement form, so the result does not depend on the origin.
  const auto rel = [&](int i, int j) {
    const std::size_t k = index(i, j);
    return Eigen::Vector3d(i * h + (full ? ux_[k] : 0.f), j * h + (full ? uy_[k] : 0.f), uz_[k]);
  };
  for (int j = 0; j < ny(); ++j) {
    for (int i = 0; i < nx(); ++i) {
      const Eigen::Vector3d dx = rel(std::min(i + 1, nx() - 1), j) - rel(std::max(i - 1, 0), j);
      const Eigen::Vector3d dy = rel(i, std::min(j + 1, ny() - 1)) - rel(i, std::max(j - 1, 0));
      Eigen::Vector3d n = dx.cross(dy);
      const double len = n.norm();
      n = len > 0.0 && std::isfinite(len) ? Eigen::Vector3d(n / len) : Eigen::Vector3d(0, 0, 1);
      const std::size_t k = index(i, j);
      xyz[3 * k + 0] = static_cast<float>(n.x());
      xyz[3 * k + 1] = static_cast<float>(n.y());
      xyz[3 * k + 2] = static_cast<float>(n.z());
    }
  }
}

void triangulate(int nx, int ny, std::vector<std::uint32_t>& indices) {
  indices.clear();
  if (nx < 2 || ny < 2) return;
  indices.reserve(6 * static_cast<std::size_t>(nx - 1) * static_cast<std::size_t>(ny - 1));
  const auto v = [nx](int i, int j) {
    return static_cast<std::uint32_t>(j) * static_cast<std::uint32_t>(nx) + static_cast<std::uint32_t>(i);
  };
  for (int j = 0; j + 1 < ny; ++j) {
    for (int i = 0; i + 1 < nx; ++i) {
      indices.insert(indices.end(), {v(i, j), v(i + 1, j), v(i, j + 1)});
      indices.insert(indices.end(), {v(i, j + 1), v(i + 1, j), v(i + 1, j + 1)});
    }
  }
}

void Surface::triangles(std::vector<std::uint32_t>& indices) const { triangulate(nx(), ny(), indices); }

Energy Surface::energy() const {
  const LatticeParameters& p = settings_.lattice;
  const std::size_t n = node_count();
  const bool full = settings_.mode == SurfaceMode::full_3d;
  const double h = p.spacing, c = p.stiffness, kt = p.transverse_stiffness();
  std::vector<double> fx(full ? n : 0, 0.0), fy(full ? n : 0, 0.0), fz(n, 0.0);
  double potential = 0.0;
  for_each_spring(nx(), ny(), [&](std::size_t a, std::size_t b, const SpringFamily& f) {
    if (!full) {
      const double dz = static_cast<double>(uz_[b]) - uz_[a];
      potential += 0.5 * kt * dz * dz;
      fz[a] += kt * dz;
      fz[b] -= kt * dz;
      return;
    }
    const double rest_dx = (f.bi - f.ai) * h, rest_dy = (f.bj - f.aj) * h;
    const double dx = rest_dx + (static_cast<double>(ux_[b]) - ux_[a]);
    const double dy = rest_dy + (static_cast<double>(uy_[b]) - uy_[a]);
    const double dz = static_cast<double>(uz_[b]) - uz_[a];
    const double l = std::sqrt(dx * dx + dy * dy + dz * dz);
    const double rest = f.rest_scale * p.rest_ratio * h;
    const double l0 = f.rest_scale * h;
    potential += 0.5 * c * ((l - rest) * (l - rest) - (l0 - rest) * (l0 - rest));
    const double s = l > 0.0 ? c * (1.0 - rest / l) : 0.0;
    fx[a] += s * dx;
    fy[a] += s * dy;
    fz[a] += s * dz;
    fx[b] -= s * dx;
    fy[b] -= s * dy;
    fz[b] -= s * dz;
  });
  const double dt = last_substep_;
  const double keep = 1.0 - p.damping * dt / p.mass, impulse = dt / p.mass;
  double kinetic = 0.0, centred = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double mh = constraints_[k] == NodeConstraint::free ? 1.0 : 0.0;
    const double mv = constraints_[k] != NodeConstraint::fixed ? 1.0 : 0.0;
    const double vz = vz_[k];
    double v2 = vz * vz;
    double vnext = vz * (vz * keep + fz[k] * impulse) * mv;
    if (full) {
      const double vx = vx_[k], vy = vy_[k];
      v2 += vx * vx + vy * vy;
      vnext += (vx * (vx * keep + fx[k] * impulse) + vy * (vy * keep + fy[k] * impulse)) * mh;
    }
    kinetic += 0.5 * p.mass * v2;
    centred += 0.5 * p.mass * (dt > 0.0 ? vnext : v2);
  }
  Energy e;
  e.kinetic = kinetic;
  e.potential = potential;
  e.total = kinetic + potential;
  e.centred = centred + potential;
  return e;
}

std::uint64_t Surface::state_hash() const {
  StateHash h;
  h.add(nx());
  h.add(ny());
  h.add(static_cast<std::uint8_t>(settings_.mode));
  for (const float* a : {ux_, uy_, uz_, vx_, vy_, vz_}) h.add(field(a));
  h.add(std::span<const NodeConstraint>(constraints_));
  return h.value();
}

Surface::View Surface::view() const {
  return {field(ux_), field(uy_), field(uz_), field(vx_), field(vy_), field(vz_), constraints_};
}

}  // namespace shore::water
