// The surface: construction, tiles, constraints, edits and queries.
#include "shore/water/surface.h"

#include <algorithm>
#include <cmath>
#include <thread>

#include "shore/core/det_math.h"
#include "shore/core/error.h"
#include "shore/water/stability.h"
#include "surface_state.h"

namespace shore::water {

NodeConstraint default_constraint(Boundary b, int i, int j, int nx, int ny) {
  if (i > 0 && j > 0 && i < nx - 1 && j < ny - 1) return NodeConstraint::free;
  switch (b) {
    case Boundary::fixed:
      return NodeConstraint::fixed;
    case Boundary::vertical_only:
    case Boundary::open:
      return NodeConstraint::vertical_only;
    case Boundary::free:
      break;
  }
  return NodeConstraint::free;
}

namespace {

/// The velocity scale of the disturbance cap and the velocity quantum: the top frequency
/// at rest times the spacing.
double top_frequency(const SurfaceSettings& s) {
  return s.mode == SurfaceMode::full_3d ? omega_max_at_rest(s.lattice) : omega_max_vertical(s.lattice);
}

int hardware_threads() { return std::max(1, static_cast<int>(std::thread::hardware_concurrency())); }

/// Tile index and in-tile offset of a node index.
struct Split {
  int tile, local;
};
Split split(int i, int shift) { return {i >> shift, i & ((1 << shift) - 1)}; }

}  // namespace

// ---- tiles ---------------------------------------------------------------------------------

TileData* Surface::State::find(int tx, int ty) const {
  if (!inside(tx, ty)) return nullptr;
  const std::int32_t k =
      slot[static_cast<std::size_t>(ty) * static_cast<std::size_t>(tiles_x) + static_cast<std::size_t>(tx)];
  return k < 0 ? nullptr : tiles[static_cast<std::size_t>(k)].get();
}

TileData& Surface::State::obtain(const SurfaceSettings& s, int tx, int ty) {
  if (TileData* t = find(tx, ty)) return *t;
  auto t = std::make_unique<TileData>();
  t->tx = tx;
  t->ty = ty;
  t->w = std::min(T, s.nx - tx * T);
  t->h = std::min(T, s.ny - ty * T);
  const std::size_t n = static_cast<std::size_t>(T) * static_cast<std::size_t>(T);
  t->uz.assign(n, 0.0);
  t->vz.assign(n, 0.0);
  if (full) {
    t->ux.assign(n, 0.f);
    t->uy.assign(n, 0.f);
    t->vx.assign(n, 0.f);
    t->vy.assign(n, 0.f);
  }
  t->flags.assign(n, static_cast<std::uint8_t>(NodeConstraint::free));
  // Only the grid's outermost nodes have a default other than free: a tile that holds none
  // keeps the fill (a growing wake creates tiles every few substeps, nearly all inside).
  const bool on_grid_edge = tx == 0 || ty == 0 || tx * T + t->w == s.nx || ty * T + t->h == s.ny;
  // Nor does it need its masks remade (refresh_masks: none where no node is constrained).
  t->masks_stale = on_grid_edge;
  if (on_grid_edge)
    for (int j = 0; j < t->h; ++j)
      for (int i = 0; i < t->w; ++i)
        t->flags[t->at(i, j, T)] =
            static_cast<std::uint8_t>(default_constraint(s.boundary, tx * T + i, ty * T + j, s.nx, s.ny));
  const std::size_t e = 4 * static_cast<std::size_t>(T);
  for (TileData::Edges& ed : t->edges) {
    ed.z.assign(e, 0.0);
    if (full) {
      ed.x.assign(e, 0.f);
      ed.y.assign(e, 0.f);
      ed.vx.assign(e, 0.f);
      ed.vy.assign(e, 0.f);
      ed.vz.assign(e, 0.0);
    }
  }
  fill_sponge(s, *t);
  tile_bytes += bytes_of(*t);
  slot[static_cast<std::size_t>(ty) * static_cast<std::size_t>(tiles_x) + static_cast<std::size_t>(tx)] =
      static_cast<std::int32_t>(tiles.size());
  tiles.push_back(std::move(t));
  return *tiles.back();
}

void Surface::State::fill_sponge(const SurfaceSettings& s, TileData& t) const {
  t.sponge.clear();
  if (s.boundary != Boundary::open || sigma.empty()) return;
  const int width = static_cast<int>(sigma.size());
  const int gi0 = t.tx * T, gj0 = t.ty * T;
  const auto distance = [&](int i, int j) {
    return std::min(std::min(gi0 + i, s.nx - 1 - (gi0 + i)), std::min(gj0 + j, s.ny - 1 - (gj0 + j)));
  };
  // The tile's nearest node to an edge lies on one of its own sides: the least of the
  // four sides' distances (a test per node before, for every tile created).
  const int nearest = std::min(std::min(gi0, s.nx - 1 - (gi0 + t.w - 1)), std::min(gj0, s.ny - 1 - (gj0 + t.h - 1)));
  if (nearest >= width) return;
  t.sponge.assign(static_cast<std::size_t>(T) * static_cast<std::size_t>(T), 0.0);
  for (int j = 0; j < t.h; ++j)
    for (int i = 0; i < t.w; ++i) {
      const int d = distance(i, j);
      if (d < width) t.sponge[t.at(i, j, T)] = sigma[static_cast<std::size_t>(d)];
    }
}

void Surface::State::set_layer(const SurfaceSettings& s) {
  sigma.clear();
  sigma_max = 0.0;
  if (s.boundary != Boundary::open) return;
  const OpenBoundarySettings& o = s.open;
  sigma_max = o.strength * s.lattice.wave_speed() / (o.width * s.lattice.spacing);
  for (int d = 0; d < o.width; ++d) {
    const double r = double(o.width - d) / o.width;
    sigma.push_back(sigma_max * r * r);
  }
}

void Surface::State::set_awake(TileData& t) {
  if (t.awake) {
    t.calm = 0;
    return;
  }
  t.awake = true;
  t.calm = 0;
  if (!t.ever_awake) ++ever_awake;
  t.ever_awake = true;
  const std::int32_t s = t.ty * tiles_x + t.tx;
  awake.insert(std::lower_bound(awake.begin(), awake.end(), s), s);
}

void Surface::State::wake_around(const SurfaceSettings& s, int tx, int ty) {
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (inside(tx + dx, ty + dy)) set_awake(obtain(s, tx + dx, ty + dy));
}

void Surface::State::rebuild_awake_list() {
  awake.clear();
  for (const auto& t : tiles)
    if (t->awake) awake.push_back(t->ty * tiles_x + t->tx);
  std::sort(awake.begin(), awake.end());
}

void Surface::State::refresh_edges(TileData& t, int parity) const {
  TileData::Edges& e = t.edges[static_cast<std::size_t>(parity)];
  // Component by component, rows as plain copies (it runs for every tile and substep).
  const std::size_t south = static_cast<std::size_t>(kernel::kSouth * T),
                    north = static_cast<std::size_t>(kernel::kNorth * T);
  const std::size_t west = static_cast<std::size_t>(kernel::kWest * T),
                    east = static_cast<std::size_t>(kernel::kEast * T);
  const std::size_t top = t.at(0, t.h - 1, T);
  const auto edges = [&](const auto& from, auto& to) {
    std::copy_n(from.data(), t.w, to.data() + south);
    std::copy_n(from.data() + top, t.w, to.data() + north);
    // Unrolled: the columns' loop paid its increment, compare and branch per entry.
#pragma GCC unroll 4
    for (int j = 0; j < t.h; ++j) {
      to[west + static_cast<std::size_t>(j)] = from[t.at(0, j, T)];
      to[east + static_cast<std::size_t>(j)] = from[t.at(t.w - 1, j, T)];
    }
  };
  edges(t.uz, e.z);
  if (full) {
    edges(t.ux, e.x);
    edges(t.uy, e.y);
    edges(t.vx, e.vx);
    edges(t.vy, e.vy);
    edges(t.vz, e.vz);
  }
}

std::size_t bytes_of(const TileData& t) {
  std::size_t b =
      sizeof(TileData) + t.uz.capacity() * 8 + t.vz.capacity() * 8 + t.flags.capacity() + t.sponge.capacity() * 8;
  b += (t.ux.capacity() + t.uy.capacity() + t.vx.capacity() + t.vy.capacity()) * 4 + mask_bytes(t);
  for (const TileData::Edges& e : t.edges)
    b += (e.z.capacity() + e.vz.capacity()) * 8 +
         (e.x.capacity() + e.y.capacity() + e.vx.capacity() + e.vy.capacity()) * 4;
  return b;
}

std::size_t Surface::State::memory_bytes() const {
  std::size_t b = slot.capacity() * sizeof(std::int32_t) + awake.capacity() * sizeof(std::int32_t) +
                  tiles.capacity() * sizeof(void*) + tile_bytes;
  for (const Scratch& s : scratch)
    b += s.bz.capacity() * 8 + (s.bx.capacity() + s.by.capacity()) * 4 + s.rows.capacity();
  return b;
}

// ---- construction --------------------------------------------------------------------------

namespace {
// KernelChoice::automatic takes the AVX-512 variant only where every variant gives the same
// bits (the default build): without SHORE_CROSS_PLATFORM_DETERMINISTIC the wide variants may
// contract multiply-adds each its own way, and one binary must still give the same bits on
// every CPU with AVX2 + FMA.
#ifdef SHORE_CROSS_PLATFORM_DETERMINISTIC
constexpr bool kAutomaticAvx512 = true;
#else
constexpr bool kAutomaticAvx512 = false;
#endif
bool automatic_avx512() { return kAutomaticAvx512 && kernel::avx512_available(); }
}  // namespace

Surface::Surface(const SurfaceSettings& settings) : settings_(settings), s_(std::make_unique<State>()) {
  settings_.validate();
  State& s = *s_;
  const bool automatic = settings_.kernel == KernelChoice::automatic;
  const bool avx512 = settings_.kernel == KernelChoice::avx512 || (automatic && automatic_avx512());
  const bool avx2 = settings_.kernel == KernelChoice::avx2 || (automatic && kernel::avx2_available());
  s.variant = settings_.kernel == KernelChoice::unfused ? kernel::Variant::unfused
              : avx512                                  ? kernel::Variant::avx512
              : avx2                                    ? kernel::Variant::avx2
                                                        : kernel::Variant::generic;
  s.full = settings_.mode == SurfaceMode::full_3d;
  s.T = settings_.sleep.tile;
  s.shift = std::countr_zero(static_cast<unsigned>(s.T));
  s.tiles_x = (settings_.nx + s.T - 1) / s.T;
  s.tiles_y = (settings_.ny + s.T - 1) / s.T;
  s.slot.assign(static_cast<std::size_t>(s.tiles_x) * static_cast<std::size_t>(s.tiles_y), -1);
  const double h = settings_.lattice.spacing, omega = top_frequency(settings_);
  s.qu = quantum::Quantum::for_scale(h, quantum::kKeepBitsHeight);
  s.qv = quantum::Quantum::for_scale(h * omega, quantum::kKeepBitsVelocity);
  s.sleep_u = settings_.sleep.height > 0.0 ? settings_.sleep.height : 1e-5 * h;
  s.sleep_v =
      settings_.sleep.velocity > 0.0 ? settings_.sleep.velocity : s.sleep_u * omega_max_vertical(settings_.lattice);
  s.set_layer(settings_);
  s.threads = settings_.threads > 0 ? settings_.threads : hardware_threads();
  s.last_substep = 0.0;
  // Tiles at rest need not exist, except a free edge of the 3-D lattice: its missing
  // springs' pre-tension pulls it inwards from the start.
  const bool free_edges = s.full && settings_.boundary == Boundary::free;
  for (int ty = 0; ty < s.tiles_y; ++ty)
    for (int tx = 0; tx < s.tiles_x; ++tx) {
      const bool edge = tx == 0 || ty == 0 || tx == s.tiles_x - 1 || ty == s.tiles_y - 1;
      if (!settings_.sleep.enabled || (free_edges && edge)) s.set_awake(s.obtain(settings_, tx, ty));
    }
}

Surface::~Surface() = default;
Surface::Surface(Surface&&) noexcept = default;
Surface& Surface::operator=(Surface&&) noexcept = default;

void Surface::set_threads(int threads) {
  Check{"water.Surface"}.at_least("threads", threads, 0);
  settings_.threads = threads;
  s_->threads = threads > 0 ? threads : hardware_threads();
  s_->team.reset();
  s_->pacer = Pacer{};
}

const char* Surface::fast_kernel_isa() {
  return automatic_avx512() ? "avx512" : kernel::avx2_available() ? "avx2" : "generic";
}
bool Surface::kernel_available(KernelChoice choice) {
  if (choice == KernelChoice::avx2) return kernel::avx2_available();
  if (choice == KernelChoice::avx512) return kernel::avx512_available();
  return true;
}
const char* Surface::kernel_isa() const noexcept {
  return s_->variant == kernel::Variant::avx512    ? "avx512"
         : s_->variant == kernel::Variant::avx2    ? "avx2"
         : s_->variant == kernel::Variant::unfused ? "unfused"
                                                   : "generic";
}
const StepStats& Surface::last_stats() const { return s_->last_stats; }
double Surface::time() const { return s_->time; }
double Surface::sleep_height() const { return s_->sleep_u; }
double Surface::sleep_velocity() const { return s_->sleep_v; }

// ---- node helpers --------------------------------------------------------------------------

namespace {
void check_index(const Surface& s, const char* what, int i, int j) {
  if (i >= 0 && j >= 0 && i < s.nx() && j < s.ny()) return;  // the common case builds no message
  const Check c{std::string("water.Surface.") + what};
  c.in_closed("i", i, 0, s.nx() - 1);
  c.in_closed("j", j, 0, s.ny() - 1);
}
}  // namespace

// ---- constraints ---------------------------------------------------------------------------

void Surface::set_constraint(int i, int j, NodeConstraint c) {
  check_index(*this, "set_constraint", i, j);
  Check{"water.Surface.set_constraint"}.in_closed("constraint", static_cast<int>(c), 0, 2);
  State& s = *s_;
  const Split a = split(i, s.shift), b = split(j, s.shift);
  s.wake_around(settings_, a.tile, b.tile);
  TileData& t = *s.find(a.tile, b.tile);
  const std::size_t k = t.at(a.local, b.local, s.T);
  t.flags[k] = static_cast<std::uint8_t>(c);
  t.masks_stale = true;
  if (c == NodeConstraint::fixed) t.vz[k] = 0.0;
  if (c != NodeConstraint::free && s.full) {
    t.vx[k] = 0.f;
    t.vy[k] = 0.f;
  }
  s.refresh_edges(t, t.cur);
}

NodeConstraint Surface::constraint(int i, int j) const {
  check_index(*this, "constraint", i, j);
  const Split a = split(i, s_->shift), b = split(j, s_->shift);
  if (const TileData* t = s_->find(a.tile, b.tile))
    return static_cast<NodeConstraint>(t->flags[t->at(a.local, b.local, s_->T)]);
  return default_constraint(settings_.boundary, i, j, nx(), ny());
}

void Surface::apply_boundary(Boundary b) {
  Check{"water.Surface.apply_boundary"}.in_closed("boundary", static_cast<int>(b), 0, 3);
  SurfaceSettings changed = settings_;
  changed.boundary = b;
  changed.validate();
  settings_.boundary = b;
  State& s = *s_;
  s.set_layer(settings_);
  const NodeConstraint c = default_constraint(b, 0, 0, nx(), ny());
  s.tile_bytes = 0;
  for (const auto& t : s.tiles) {
    s.fill_sponge(settings_, *t);
    s.tile_bytes += bytes_of(*t);
  }
  for (int i = 0; i < nx(); ++i) {
    if (constraint(i, 0) != c || s.find(i >> s.shift, 0)) set_constraint(i, 0, c);
    if (constraint(i, ny() - 1) != c || s.find(i >> s.shift, (ny() - 1) >> s.shift)) set_constraint(i, ny() - 1, c);
  }
  for (int j = 0; j < ny(); ++j) {
    if (constraint(0, j) != c || s.find(0, j >> s.shift)) set_constraint(0, j, c);
    if (constraint(nx() - 1, j) != c || s.find((nx() - 1) >> s.shift, j >> s.shift)) set_constraint(nx() - 1, j, c);
  }
}

// ---- disturbances and edits ----------------------------------------------------------------

namespace {
double velocity_cap(const SurfaceSettings& s) {
  return s.guard.max_disturbance_spacings * s.lattice.spacing * top_frequency(s);
}
}  // namespace

void Surface::disturb(std::span<const Disturbance> ds) {
  const double height_cap = settings_.guard.max_disturbance_spacings * spacing();
  const double speed_cap = velocity_cap(settings_);
  for (const Disturbance& d : ds) {
    d.validate();
    const bool height = d.target == Disturbance::Target::height;
    const double cap = height ? height_cap : speed_cap;
    if (!(std::abs(d.amplitude) <= cap))
      throw InvalidSetting("water.Disturbance.amplitude", detail::to_text(d.amplitude),
                           "must be within +-" + detail::to_text(cap) + (height ? " m" : " m/s") +
                               " (GuardSettings::max_disturbance_spacings)");
  }
  State& s = *s_;
  s.deformation.reset();
  for (const Disturbance& d : ds) {
    const DisturbanceAxis ax = tabulate_axis(d, d.x, d.half_x, settings_.origin_x, spacing(), nx());
    const DisturbanceAxis ay = tabulate_axis(d, d.y, d.half_y, settings_.origin_y, spacing(), ny());
    if (ax.weights.empty() || ay.weights.empty()) continue;
    const bool height = d.target == Disturbance::Target::height;
    const quantum::Quantum& q = height ? s.qu : s.qv;
    const int i0 = ax.first, i1 = ax.first + static_cast<int>(ax.weights.size()) - 1;
    const int j0 = ay.first, j1 = ay.first + static_cast<int>(ay.weights.size()) - 1;
    for (int ty = j0 >> s.shift; ty <= j1 >> s.shift; ++ty)
      for (int tx = i0 >> s.shift; tx <= i1 >> s.shift; ++tx) s.wake_around(settings_, tx, ty);
    for (std::size_t b = 0; b < ay.weights.size(); ++b) {
      const double wy = d.amplitude * ay.weights[b];
      const int j = j0 + static_cast<int>(b);
      for (std::size_t a = 0; a < ax.weights.size(); ++a) {
        const int i = i0 + static_cast<int>(a);
        TileData& t = *s.find(i >> s.shift, j >> s.shift);
        const std::size_t k = t.at(i & (s.T - 1), j & (s.T - 1), s.T);
        if (t.flags[k] == static_cast<std::uint8_t>(NodeConstraint::fixed)) continue;
        double& target = height ? t.uz[k] : t.vz[k];
        target = quantum::saturate(target + quantum::round_to(wy * ax.weights[a], q.magic), q.keep);
      }
    }
    for (int ty = j0 >> s.shift; ty <= j1 >> s.shift; ++ty)
      for (int tx = i0 >> s.shift; tx <= i1 >> s.shift; ++tx) s.refresh_edges(*s.find(tx, ty), s.find(tx, ty)->cur);
  }
}

void Surface::wake(double x0, double y0, double x1, double y1) {
  const Check c{"water.Surface.wake"};
  c.finite("x0", x0);
  c.finite("y0", y0);
  c.finite("x1", x1);
  c.finite("y1", y1);
  const Eigen::Vector2d a = grid_coordinates(std::min(x0, x1), std::min(y0, y1));
  const Eigen::Vector2d b = grid_coordinates(std::max(x0, x1), std::max(y0, y1));
  const auto clamp_i = [&](double g, int n) { return static_cast<int>(std::clamp(g, 0.0, double(n - 1))); };
  const int i0 = clamp_i(std::floor(a.x()), nx()), i1 = clamp_i(std::ceil(b.x()), nx());
  const int j0 = clamp_i(std::floor(a.y()), ny()), j1 = clamp_i(std::ceil(b.y()), ny());
  State& s = *s_;
  for (int ty = j0 >> s.shift; ty <= j1 >> s.shift; ++ty)
    for (int tx = i0 >> s.shift; tx <= i1 >> s.shift; ++tx) s.wake_around(settings_, tx, ty);
}

namespace {
struct NodeRef {
  TileData* tile;
  std::size_t k;
};
}  // namespace

namespace {
/// Adds `delta` (rounded to the field's quantum) to a node's height (or vertical velocity):
/// checked against the cap, refused at a fixed node, waking the node's tile.
bool edit_node(const Surface& surface, Surface::State& s, int i, int j, double delta, bool height) {
  const char* what = height ? "add_height" : "add_vertical_velocity";
  check_index(surface, what, i, j);
  const SurfaceSettings& set = surface.settings();
  const double cap = height ? set.guard.max_disturbance_spacings * set.lattice.spacing : velocity_cap(set);
  if (!(std::abs(delta) <= cap))
    throw InvalidSetting(std::string("water.Surface.") + what + (height ? ".dz" : ".dv"), detail::to_text(delta),
                         "must be finite and within +-" + detail::to_text(cap) + (height ? " m" : " m/s"));
  if (surface.constraint(i, j) == NodeConstraint::fixed) return false;
  s.wake_around(set, i >> s.shift, j >> s.shift);
  TileData& t = *s.find(i >> s.shift, j >> s.shift);
  const std::size_t k = t.at(i & (s.T - 1), j & (s.T - 1), s.T);
  const quantum::Quantum& q = height ? s.qu : s.qv;
  double& target = height ? t.uz[k] : t.vz[k];
  target = quantum::saturate(target + quantum::round_to(delta, q.magic), q.keep);
  s.refresh_edges(t, t.cur);
  if (height) s.deformation.reset();
  return true;
}
}  // namespace

bool Surface::add_height(int i, int j, double dz) { return edit_node(*this, *s_, i, j, dz, true); }

bool Surface::add_vertical_velocity(int i, int j, double dv) { return edit_node(*this, *s_, i, j, dv, false); }

namespace {
/// Copies a field of the nodes of a window, row-major, nodes beyond the grid clamped to the
/// nearest edge node, tiles not created read as 0: one tile lookup per row and tile.
void read_window(const Surface::State& s, int nx, int ny, int i0, int j0, int w, int h,
                 std::vector<double> TileData::*field, std::vector<double>& out) {
  out.assign(static_cast<std::size_t>(std::max(w, 0)) * static_cast<std::size_t>(std::max(h, 0)), 0.0);
  for (int b = 0; b < h; ++b) {
    const int j = std::clamp(j0 + b, 0, ny - 1);
    double* row = out.data() + static_cast<std::size_t>(b) * static_cast<std::size_t>(w);
    for (int a = 0; a < w;) {
      const int i = std::clamp(i0 + a, 0, nx - 1);
      const TileData* t = s.find(i >> s.shift, j >> s.shift);
      // The run of window nodes inside this tile (nodes clamped to the edge: one at a time).
      const bool inside = i0 + a >= 0 && i0 + a < nx;
      const int run = inside ? std::min(w - a, std::min(nx - 1, ((i >> s.shift) + 1) * s.T - 1) - i + 1) : 1;
      if (t) {
        const double* src = (t->*field).data() + t->at(i & (s.T - 1), j & (s.T - 1), s.T);
        std::copy_n(src, run, row + a);
      }
      a += run;
    }
  }
}
}  // namespace

void Surface::heights_above_rest(int i0, int j0, int w, int h, std::vector<double>& out) const {
  read_window(*s_, nx(), ny(), i0, j0, w, h, &TileData::uz, out);
}

void Surface::vertical_velocities(int i0, int j0, int w, int h, std::vector<double>& out) const {
  read_window(*s_, nx(), ny(), i0, j0, w, h, &TileData::vz, out);
}

double Surface::add_heights(int i0, int j0, int w, int h, std::span<const double> dz) {
  if (w <= 0 || h <= 0) return 0.0;
  if (dz.size() != static_cast<std::size_t>(w) * static_cast<std::size_t>(h))
    throw InvalidSetting("water.Surface.add_heights.dz", std::to_string(dz.size()) + " values",
                         "must hold w * h = " + std::to_string(std::int64_t(w) * h));
  const double cap = settings_.guard.max_disturbance_spacings * spacing();
  for (double d : dz)
    if (!(std::abs(d) <= cap))
      throw InvalidSetting("water.Surface.add_heights.dz", detail::to_text(d),
                           "must be finite and within +-" + detail::to_text(cap) + " m");
  State& s = *s_;
  const int a0 = std::max(i0, 0), a1 = std::min(i0 + w - 1, nx() - 1);
  const int b0 = std::max(j0, 0), b1 = std::min(j0 + h - 1, ny() - 1);
  if (a0 > a1 || b0 > b1) return 0.0;
  for (int ty = b0 >> s.shift; ty <= b1 >> s.shift; ++ty)
    for (int tx = a0 >> s.shift; tx <= a1 >> s.shift; ++tx) s.wake_around(settings_, tx, ty);
  quantum::Wide quanta = 0;
  for (int j = b0; j <= b1; ++j)
    for (int i = a0; i <= a1; ++i) {
      const double d =
          dz[static_cast<std::size_t>(j - j0) * static_cast<std::size_t>(w) + static_cast<std::size_t>(i - i0)];
      if (d == 0.0) continue;
      TileData& t = *s.find(i >> s.shift, j >> s.shift);
      const std::size_t k = t.at(i & (s.T - 1), j & (s.T - 1), s.T);
      if (t.flags[k] == static_cast<std::uint8_t>(NodeConstraint::fixed)) continue;
      const double before = t.uz[k];
      t.uz[k] = quantum::saturate(before + quantum::round_to(d, s.qu.magic), s.qu.keep);
      quanta += quantum::count(t.uz[k], s.qu.inv) - quantum::count(before, s.qu.inv);
    }
  for (int ty = b0 >> s.shift; ty <= b1 >> s.shift; ++ty)
    for (int tx = a0 >> s.shift; tx <= a1 >> s.shift; ++tx) s.refresh_edges(*s.find(tx, ty), s.find(tx, ty)->cur);
  s.deformation.reset();
  return static_cast<double>(quanta) * s.qu.q * spacing() * spacing();
}

// ---- node access ---------------------------------------------------------------------------

double Surface::height(int i, int j) const {
  check_index(*this, "height", i, j);
  const TileData* t = s_->find(i >> s_->shift, j >> s_->shift);
  return settings_.rest_height + (t ? t->uz[t->at(i & (s_->T - 1), j & (s_->T - 1), s_->T)] : 0.0);
}

double Surface::vertical_velocity(int i, int j) const {
  check_index(*this, "vertical_velocity", i, j);
  const TileData* t = s_->find(i >> s_->shift, j >> s_->shift);
  return t ? t->vz[t->at(i & (s_->T - 1), j & (s_->T - 1), s_->T)] : 0.0;
}

Eigen::Vector3d Surface::position(int i, int j) const {
  check_index(*this, "position", i, j);
  const TileData* t = s_->find(i >> s_->shift, j >> s_->shift);
  const std::size_t k = t ? t->at(i & (s_->T - 1), j & (s_->T - 1), s_->T) : 0;
  const bool full = t && s_->full;
  return {node_x(i) + (full ? static_cast<double>(t->ux[k]) : 0.0),
          node_y(j) + (full ? static_cast<double>(t->uy[k]) : 0.0), settings_.rest_height + (t ? t->uz[k] : 0.0)};
}

Eigen::Vector3d Surface::velocity(int i, int j) const {
  check_index(*this, "velocity", i, j);
  const TileData* t = s_->find(i >> s_->shift, j >> s_->shift);
  const std::size_t k = t ? t->at(i & (s_->T - 1), j & (s_->T - 1), s_->T) : 0;
  const bool full = t && s_->full;
  return {full ? static_cast<double>(t->vx[k]) : 0.0, full ? static_cast<double>(t->vy[k]) : 0.0, t ? t->vz[k] : 0.0};
}

bool Surface::awake(int i, int j) const {
  check_index(*this, "awake", i, j);
  const TileData* t = s_->find(i >> s_->shift, j >> s_->shift);
  return t && t->awake;
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
/// Bilinear sample of a node value at continuous grid coordinates, clamped to the grid.
template <class Value>
double bilinear(int nx, int ny, Eigen::Vector2d g, Value&& value) {
  const double gx = std::clamp(std::isfinite(g.x()) ? g.x() : 0.0, 0.0, static_cast<double>(nx - 1));
  const double gy = std::clamp(std::isfinite(g.y()) ? g.y() : 0.0, 0.0, static_cast<double>(ny - 1));
  const int i = std::min(static_cast<int>(gx), nx - 2), j = std::min(static_cast<int>(gy), ny - 2);
  const double s = gx - i, t = gy - j;
  return (1 - t) * ((1 - s) * value(i, j) + s * value(i + 1, j)) +
         t * ((1 - s) * value(i, j + 1) + s * value(i + 1, j + 1));
}
}  // namespace

double Surface::height_at(double x, double y) const {
  return settings_.rest_height + bilinear(nx(), ny(), grid_coordinates(x, y), [&](int i, int j) {
           const TileData* t = s_->find(i >> s_->shift, j >> s_->shift);
           return t ? t->uz[t->at(i & (s_->T - 1), j & (s_->T - 1), s_->T)] : 0.0;
         });
}

double Surface::vertical_velocity_at(double x, double y) const {
  return bilinear(nx(), ny(), grid_coordinates(x, y), [&](int i, int j) {
    const TileData* t = s_->find(i >> s_->shift, j >> s_->shift);
    return t ? t->vz[t->at(i & (s_->T - 1), j & (s_->T - 1), s_->T)] : 0.0;
  });
}

double Surface::level_around(double x, double y, double radius) const {
  const Check c{"water.Surface.level_around"};
  c.finite("x", x);
  c.finite("y", y);
  c.positive("radius", radius);
  constexpr int kPoints = 32;
  double sum = 0.0;
  for (int k = 0; k < kPoints; ++k) {
    const double a = 2.0 * det::detail::kPi * k / kPoints;
    sum += height_at(x + radius * det::cos(a), y + radius * det::sin(a));
  }
  return sum / kPoints;
}

}  // namespace shore::water
