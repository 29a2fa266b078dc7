// The substep: gathering tiles, running the kernels (on the team when it pays), putting
// the rounding of damping and rise back, the stability guard, and sleeping.
#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <limits>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "shore/core/error.h"
#include "shore/water/stability.h"
#include "surface_state.h"

namespace shore::water {

// ---- blocks --------------------------------------------------------------------------------

kernel::Side Surface::State::side_of(const TileData& t, int side) const {
  const int tx = t.tx + kSideDx[side], ty = t.ty + kSideDy[side];
  if (!inside(tx, ty)) return kernel::Side::absent;
  const TileData* n = find(tx, ty);
  return n && n->awake ? kernel::Side::live : kernel::Side::frozen;
}

namespace {
/// Copies `count` entries of a neighbour's edge (or zeros for a tile not created) to a
/// block row or column: to[k * step].
template <class V>
void copy_edge(const std::vector<V>* edge, std::size_t first, int count, V* to, std::ptrdiff_t step) {
  // The test out of the loop, and rows as plain copies: this ran once per entry, per ghost
  // and component, for every tile and substep.
  // Columns (step > 1) unrolled: at -O2 their loops paid an increment, a compare and a
  // branch per entry.
  if (!edge && step == 1) {
    std::fill_n(to, count, V{});
  } else if (!edge) {
#pragma GCC unroll 4
    for (int k = 0; k < count; ++k) to[k * step] = V{};
  } else if (step == 1) {
    std::copy_n(edge->data() + first, count, to);
  } else {
    const V* from = edge->data() + first;
#pragma GCC unroll 4
    for (int k = 0; k < count; ++k) to[k * step] = from[k];
  }
}

// The largest steps between a side's ghosts (a[q], the neighbour's edge snapshot as stored,
// contiguous for every side; null: zeros, a tile not created) and the tile's nodes their
// springs reach (b[q], its own snapshot). Max of non-negative values is exact in any order
// and a NaN entry is skipped (max keeps its first operand), so the lanes below, each
// skipping NaN the same way and merged at the end, give the sequential loop's value: this
// ran over every side of every awake tile each substep, a scalar max and a test per entry.
// With kCopy the ghosts are also written to the block (to[q * step]) from the same loads: a
// side the kernel reads is copied and measured in one pass instead of two. (Copied as K for
// the fused vertical-only kernels: kernel::scaled_ghosts.)
template <bool kGhosts, bool kCopy>
double largest_step_of(const double* a, const double* b, int count, double* to, std::ptrdiff_t step) {
  static_assert(kGhosts || !kCopy, "only a neighbour's edge is copied");
  double m = 0.0;
  int q = 0;
#if defined(__SSE2__)
  const __m128d sign = _mm_set1_pd(-0.0);
  __m128d m0 = _mm_setzero_pd(), m1 = _mm_setzero_pd();
  for (; q + 4 <= count; q += 4) {
    __m128d d0 = _mm_loadu_pd(b + q), d1 = _mm_loadu_pd(b + q + 2);
    if constexpr (kGhosts) {
      const __m128d g0 = _mm_loadu_pd(a + q), g1 = _mm_loadu_pd(a + q + 2);
      if constexpr (kCopy) {
        double* at = to + q * step;
        if (step == 1) {
          _mm_storeu_pd(at, g0);
          _mm_storeu_pd(at + 2, g1);
        } else {
          _mm_storel_pd(at, g0);
          _mm_storeh_pd(at + step, g0);
          _mm_storel_pd(at + 2 * step, g1);
          _mm_storeh_pd(at + 3 * step, g1);
        }
      }
      d0 = _mm_sub_pd(g0, d0);
      d1 = _mm_sub_pd(g1, d1);
    }
    // max_pd(d, m) is d > m ? d : m: m where d is NaN, as std::max(m, d).
    m0 = _mm_max_pd(_mm_andnot_pd(sign, d0), m0);
    m1 = _mm_max_pd(_mm_andnot_pd(sign, d1), m1);
  }
  if (count >= 4) {  // (a corner's single entry has no lanes to merge)
    alignas(16) double lanes[4];
    _mm_store_pd(lanes, m0);
    _mm_store_pd(lanes + 2, m1);
    for (const double l : lanes) m = std::max(m, l);
  }
  for (; q < count; ++q) {
    if constexpr (kCopy) to[q * step] = a[q];
    m = std::max(m, std::abs((kGhosts ? a[q] : 0.0) - b[q]));
  }
#else
  for (; q < count; ++q) {
    if constexpr (kCopy) to[q * step] = a[q];
    m = std::max(m, std::abs((kGhosts ? a[q] : 0.0) - b[q]));
  }
#endif
  return m;
}
double largest_step(const double* a, const double* b, int count) {
  return a ? largest_step_of<true, false>(a, b, count, nullptr, 0)
           : largest_step_of<false, false>(a, b, count, nullptr, 0);
}
/// The same for the in-plane components: max over entries of max(|dx|, |dy|).
float largest_step_xy(const float* ax, const float* ay, std::ptrdiff_t as, const float* bx, const float* by,
                      std::size_t bs, int count) {
  float m = 0.f;
  for (int q = 0; q < count; ++q) {
    const std::size_t b = static_cast<std::size_t>(q) * bs;
    m = std::max(m, std::max(std::abs(ax[q * as] - bx[b]), std::abs(ay[q * as] - by[b])));
  }
  return m;
}
}  // namespace

void Surface::State::refresh_masks(TileData& t) {
  const std::size_t count = static_cast<std::size_t>(t.h) * static_cast<std::size_t>(T);
  const auto fixed = static_cast<std::uint8_t>(NodeConstraint::fixed);
  const auto free = static_cast<std::uint8_t>(NodeConstraint::free);
  const bool any = std::any_of(t.flags.begin(), t.flags.begin() + static_cast<std::ptrdiff_t>(count),
                               [&](std::uint8_t f) { return full ? f != free : f == fixed; });
  tile_bytes -= mask_bytes(t);
  t.moving.clear();
  t.free_nodes.clear();
  if (any) {
    t.moving.resize(count);
    for (std::size_t k = 0; k < count; ++k) t.moving[k] = t.flags[k] != fixed ? ~std::uint64_t{0} : 0u;
    if (full) {
      t.free_nodes.resize(count);
      for (std::size_t k = 0; k < count; ++k) t.free_nodes[k] = t.flags[k] == free ? ~std::uint32_t{0} : 0u;
    }
  }
  t.moving.shrink_to_fit();
  t.free_nodes.shrink_to_fit();
  tile_bytes += mask_bytes(t);
  t.masks_stale = false;
}

kernel::Tile Surface::State::gather(TileData& t, Scratch& sc, const kernel::Coefficients* scale) const {
  const int bs = T + 2;
  const std::size_t cells = static_cast<std::size_t>(bs) * static_cast<std::size_t>(bs);
  if (sc.bz.size() < cells) {
    sc.bz.assign(cells, 0.0);
    sc.bx.assign(full ? cells : 0, 0.f);
    sc.by.assign(full ? cells : 0, 0.f);
  }
  if (sc.rows.size() < kernel::workspace_bytes(T) + 64) sc.rows.assign(kernel::workspace_bytes(T) + 64, 0);
  kernel::Tile k;
  k.w = t.w;
  k.h = t.h;
  k.stride = T;
  k.block_stride = bs;
  k.uz = t.uz.data();
  k.vz = t.vz.data();
  k.flags = t.flags.data();
  // The masks kept with the tile (step_tiles remakes stale ones before it forks); the
  // unfused reference makes its own per row.
  if (variant != kernel::Variant::unfused && !t.masks_stale) {
    k.masks_given = true;
    k.moving = t.moving.empty() ? nullptr : t.moving.data();
    k.free_nodes = t.free_nodes.empty() ? nullptr : t.free_nodes.data();
  }
  k.sponge = t.sponge.empty() ? nullptr : t.sponge.data();
  double* bz = sc.bz.data() + bs + 1;
  float* bx = full ? sc.bx.data() + bs + 1 : nullptr;
  float* by = full ? sc.by.data() + bs + 1 : nullptr;
  k.bz = bz;
  if (full) {
    k.ux = t.ux.data();
    k.uy = t.uy.data();
    k.vx = t.vx.data();
    k.vy = t.vy.data();
    k.bx = bx;
    k.by = by;
  }
  // The interior: the 3-D kernels read it; the fused vertical-only kernel makes its K from
  // the storage directly (the unfused one reads the block).
  if (full || variant == kernel::Variant::unfused)
    for (int r = 0; r < t.h; ++r) {
      const std::size_t o = t.at(0, r, T);
      std::copy_n(t.uz.data() + o, t.w, bz + r * bs);
      if (full) {
        std::copy_n(t.ux.data() + o, t.w, bx + r * bs);
        std::copy_n(t.uy.data() + o, t.w, by + r * bs);
      }
    }
  // Each neighbour looked up once, for its side's state and for its edge below.
  const TileData* around[kernel::kSides];
  for (int side = 0; side < kernel::kSides; ++side) {
    const int tx = t.tx + kSideDx[side], ty = t.ty + kSideDy[side];
    around[side] = inside(tx, ty) ? find(tx, ty) : nullptr;
    k.sides[side] = !inside(tx, ty)                       ? kernel::Side::absent
                    : around[side] && around[side]->awake ? kernel::Side::live
                                                          : kernel::Side::frozen;
  }
  // The ghost ring: each side from the facing edge of the neighbour (zeros where there is
  // none: rest, or beyond the grid, where the kernel ignores them).
  struct Ghost {
    int side;                 // of this tile
    int facing;               // the neighbour's edge that faces it
    int first;                // first entry of that edge
    int count;                // entries
    std::ptrdiff_t at, step;  // block offset of the first ghost and the step between ghosts
    std::size_t own;          // entry of the tile's own edge snapshot (edges[cur]) the first
                              // ghost's spring reaches; the next ones follow it
  };
  const std::ptrdiff_t hs = static_cast<std::ptrdiff_t>(t.h) * bs;
  const auto edge = [this](int side) { return static_cast<std::size_t>(side * T); };
  const std::size_t right = static_cast<std::size_t>(t.w - 1);
  const Ghost ghosts[] = {
      {kernel::kSouth, kernel::kNorth, 0, t.w, -bs, 1, edge(kernel::kSouth)},
      {kernel::kNorth, kernel::kSouth, 0, t.w, hs, 1, edge(kernel::kNorth)},
      {kernel::kWest, kernel::kEast, 0, t.h, -1, bs, edge(kernel::kWest)},
      {kernel::kEast, kernel::kWest, 0, t.h, t.w, bs, edge(kernel::kEast)},
      {kernel::kSouthWest, kernel::kNorth, T - 1, 1, -bs - 1, 1, edge(kernel::kSouth)},
      {kernel::kSouthEast, kernel::kNorth, 0, 1, -bs + t.w, 1, edge(kernel::kSouth) + right},
      {kernel::kNorthWest, kernel::kSouth, T - 1, 1, hs - 1, 1, edge(kernel::kNorth)},
      {kernel::kNorthEast, kernel::kSouth, 0, 1, hs + t.w, 1, edge(kernel::kNorth) + right},
  };
  // The tile's own nodes along each side, from its edge snapshot: the same values as its
  // storage (every change of the storage rewrites edges[cur]), in four short rows rather
  // than two columns of the storage with each entry on a cache line of its own.
  const TileData::Edges& mine = t.edges[static_cast<std::size_t>(t.cur)];
  // Which ghosts the kernel reads: all of them in 3-D mode (a frozen side's in-plane
  // springs act) and in the unfused reference; in the fused vertical-only kernel only a
  // live side's (it writes the K of the others as 0 itself): a side whose neighbour sleeps
  // or was never created costs its measure only, not a copy.
  const bool whole_ring = full || variant == kernel::Variant::unfused;
  // Those ghosts as K already where the caller gives the substep's coefficients (the
  // kernel's scaling of them, a strided pass over the ring's columns, then goes).
  k.ring_scaled = scale && !whole_ring;
  const double kappa = scale ? scale->kappa : 1.0, v_magic = scale ? scale->v_magic : 1.0;
  for (const Ghost& g : ghosts) {
    const kernel::Side side = k.sides[g.side];
    const TileData* n = side == kernel::Side::absent ? nullptr : around[g.side];
    const TileData::Edges* e = n ? &n->edges[static_cast<std::size_t>(n->cur)] : nullptr;
    const std::size_t first = static_cast<std::size_t>(g.facing * T + g.first);
    const bool copy = whole_ring || side == kernel::Side::live;
    if (full) {
      copy_edge(e ? &e->x : nullptr, first, g.count, bx + g.at, g.step);
      copy_edge(e ? &e->y : nullptr, first, g.count, by + g.at, g.step);
    }
    k.boundary_activity[g.side] = 0.0;
    if (side == kernel::Side::absent) {
      if (copy) copy_edge<double>(nullptr, first, g.count, bz + g.at, g.step);
      continue;
    }
    // The steps across this side: a tile at rest next to water at another level is not at
    // rest (with the copy of the ghosts where the kernel reads them, from the same loads).
    const double* own = mine.z.data() + g.own;
    double step = 0.0;
    if (copy && e && k.ring_scaled) {  // as K, in the kernel's width
      step = kernel::scaled_ghosts(variant, e->z.data() + first, own, g.count, bz + g.at, g.step, kappa, v_magic);
    } else if (copy && e) {
      step = largest_step_of<true, true>(e->z.data() + first, own, g.count, bz + g.at, g.step);
    } else {
      if (copy) copy_edge<double>(nullptr, first, g.count, bz + g.at, g.step);
      step = largest_step(e ? e->z.data() + first : nullptr, own, g.count);
    }
    if (full)
      step = std::max(step, static_cast<double>(largest_step_xy(bx + g.at, by + g.at, g.step, mine.x.data() + g.own,
                                                                mine.y.data() + g.own, 1, g.count)));
    k.boundary_activity[g.side] = step / sleep_u;
  }
  return k;
}

// ---- the guard -----------------------------------------------------------------------------

namespace {
float from_bits(std::uint32_t b) { return std::bit_cast<float>(b); }
std::uint32_t to_bits(float f) { return std::bit_cast<std::uint32_t>(f); }

/// Turns the kernel's raw measures into the guard's (max tension, max sin), for positions
/// that may have moved by up to `slack` along every spring since they were measured.
Deformation deformation_of(const kernel::Extremes& e, double rest, double rest_diag, double slack_axis,
                           double slack_diag) {
  const auto family = [](double rest_length, std::uint32_t longest2, std::uint32_t shortest2, std::uint32_t across2,
                         double slack, double& tension, double& sine) {
    const double longest = std::sqrt(static_cast<double>(from_bits(longest2))) + slack;
    const double shortest = std::sqrt(static_cast<double>(from_bits(shortest2))) - slack;
    const double across = std::sqrt(static_cast<double>(from_bits(across2))) + slack;
    tension = std::max(tension, longest > 0.0 ? 1.0 - rest_length / longest : 0.0);
    sine = std::max(sine, shortest > 0.0 ? std::min(1.0, across / shortest) : 1.0);
  };
  Deformation d;
  family(rest, e.long_axis, e.short_axis, e.across_axis, slack_axis, d.max_tension, d.max_sin);
  family(rest_diag, e.long_diag, e.short_diag, e.across_diag, slack_diag, d.max_tension, d.max_sin);
  return d;
}

/// The springs of tiles that are not stepped: at rest within the sleep height.
kernel::Extremes resting_extremes(double h, double eps, double eps_v) {
  kernel::Extremes e;
  const double d = std::sqrt(2.0) * h;
  e.long_axis = to_bits(static_cast<float>((h + 2 * eps) * (h + 2 * eps)));
  e.short_axis = to_bits(static_cast<float>((h - 2 * eps) * (h - 2 * eps)));
  e.across_axis = to_bits(static_cast<float>(4 * eps * eps));
  e.long_diag = to_bits(static_cast<float>((d + 2 * eps) * (d + 2 * eps)));
  e.short_diag = to_bits(static_cast<float>((d - 2 * eps) * (d - 2 * eps)));
  e.across_diag = e.across_axis;
  e.relative = to_bits(static_cast<float>(4 * eps_v * eps_v));
  return e;
}

kernel::Coefficients coefficients(const SurfaceSettings& s, const Surface::State& st, double dt) {
  const LatticeParameters& p = s.lattice;
  kernel::Coefficients k;
  k.h = static_cast<float>(p.spacing);
  k.c = static_cast<float>(p.stiffness);
  k.rest = static_cast<float>(p.rest_ratio * p.spacing);
  k.rest_diag = static_cast<float>(std::sqrt(2.0) * p.rest_ratio * p.spacing);
  k.s0 = static_cast<float>(p.stiffness * (1.0 - p.rest_ratio));
  k.damping = static_cast<float>(p.damping);
  k.impulse = static_cast<float>(dt / p.mass);
  k.dt = static_cast<float>(dt);
  k.impulse_z = dt / p.mass;
  k.kappa = p.transverse_stiffness() * dt / p.mass;
  k.beta = p.damping * dt / p.mass;
  k.dt_z = dt;
  k.u_magic = st.qu.magic;
  k.u_inv = st.qu.inv;
  k.v_magic = st.qv.magic;
  k.v_inv = st.qv.inv;
  k.u_keep = st.qu.keep;
  k.v_keep = st.qv.keep;
  k.activity = s.sleep.enabled;
  k.u_scale = 1.0 / st.sleep_u;
  k.v_scale = 1.0 / st.sleep_v;
  return k;
}

/// Effective damping (N s/m) and frequency bound with the open boundary's layer.
double layer_damping(const SurfaceSettings& s, const Surface::State& st) {
  return s.lattice.damping + 2.0 * st.sigma_max * s.lattice.mass;
}
}  // namespace

double Surface::omega_bound() const {
  const LatticeParameters& p = settings_.lattice;
  State& s = *s_;
  const double layer = s.sigma_max * s.sigma_max;
  if (settings_.mode == SurfaceMode::vertical_only) {
    const double w = omega_max_vertical(p);
    return std::sqrt(w * w + layer);
  }
  if (!s.deformation) {
    const kernel::Coefficients k = coefficients(settings_, s, 1.0);
    if (s.scratch.empty()) s.scratch.resize(1);
    kernel::Extremes e;
    for (const auto& t : s.tiles) {
      const kernel::Tile view = s.gather(*t, s.scratch[0]);
      e.merge(kernel::measure_3d(s.variant, view, k, s.scratch[0].workspace()));
    }
    if (static_cast<std::size_t>(s.tiles_x) * static_cast<std::size_t>(s.tiles_y) != s.awake.size())
      e.merge(resting_extremes(p.spacing, s.sleep_u, s.sleep_v));
    s.deformation = deformation_of(e, p.rest_ratio * p.spacing, std::sqrt(2.0) * p.rest_ratio * p.spacing, 0.0, 0.0);
  }
  const double w = omega_bound_3d(p, s.deformation->max_tension, s.deformation->max_sin);
  return std::sqrt(w * w + layer);
}

// ---- the substep ---------------------------------------------------------------------------

namespace {

/// Largest |v_o - v_m|^2 (bit patterns) of count entries; o null: velocities of 0.
std::uint32_t largest_relative(const float* ox, const float* oy, const double* oz, const float* mx, const float* my,
                               const double* mz, int count) {
  std::uint32_t m = 0u;
  if (!ox) {
    for (int k = 0; k < count; ++k) {
      const float dx = 0.f - mx[k], dy = 0.f - my[k], dz = static_cast<float>(0.0 - mz[k]);
      m = std::max(m, std::bit_cast<std::uint32_t>(dx * dx + dy * dy + dz * dz));
    }
    return m;
  }
  for (int k = 0; k < count; ++k) {
    const float dx = ox[k] - mx[k], dy = oy[k] - my[k], dz = static_cast<float>(oz[k] - mz[k]);
    m = std::max(m, std::bit_cast<std::uint32_t>(dx * dx + dy * dy + dz * dz));
  }
  return m;
}

/// Largest |v_b - v_a|^2 over the axis springs across a tile's side, from the edges' new
/// velocities (3-D): the kernel measures only the springs inside a tile.
std::uint32_t relative_across(const Surface::State& s, const TileData& t, int side) {
  const TileData* n = s.find(t.tx + kSideDx[side], t.ty + kSideDy[side]);
  const TileData::Edges& mine = t.edges[static_cast<std::size_t>(t.cur)];
  const int facing = side == kernel::kSouth   ? kernel::kNorth
                     : side == kernel::kNorth ? kernel::kSouth
                     : side == kernel::kWest  ? kernel::kEast
                                              : kernel::kWest;
  const int count = side <= kernel::kNorth ? t.w : t.h;
  const std::size_t a = static_cast<std::size_t>(side * s.T), b = static_cast<std::size_t>(facing * s.T);
  // The neighbour's test out of the loop (it ran per entry, every substep, on two sides of
  // every tile): where there is none its velocities read as 0, the same arithmetic.
  if (!n)
    return largest_relative(nullptr, nullptr, nullptr, mine.vx.data() + a, mine.vy.data() + a, mine.vz.data() + a,
                            count);
  const TileData::Edges& o = n->edges[static_cast<std::size_t>(n->cur)];
  return largest_relative(o.vx.data() + b, o.vy.data() + b, o.vz.data() + b, mine.vx.data() + a, mine.vy.data() + a,
                          mine.vz.data() + a, count);
}

/// The kernel's view of a tile's storage as the next one to step (kernel::Tile::next).
kernel::Tile::Next next_of(const TileData& t, int stride) {
  kernel::Tile::Next n;
  n.uz = t.uz.data();
  n.vz = t.vz.data();
  if (!t.ux.empty()) {  // 3-D
    n.ux = t.ux.data();
    n.uy = t.uy.data();
    n.vx = t.vx.data();
    n.vy = t.vy.data();
  }
  n.w = t.w;
  n.h = t.h;
  n.stride = stride;
  return n;
}

struct Totals {
  quantum::Wide v_before = 0, damped = 0, v_after = 0, rise = 0;
};

double nearest(double x) { return std::floor(x + 0.5); }

}  // namespace

namespace {

/// The node corrections go to: the first moving node of the first awake tile.
struct Anchor {
  TileData* tile = nullptr;
  std::size_t node = 0;
  bool on_edge = false;
};
Anchor find_anchor(const Surface::State& s) {
  for (std::int32_t slot : s.awake) {
    TileData& t = *s.tiles[static_cast<std::size_t>(s.slot[static_cast<std::size_t>(slot)])];
    for (int j = 0; j < t.h; ++j)
      for (int i = 0; i < t.w; ++i) {
        const std::size_t n = t.at(i, j, s.T);
        if (t.flags[n] != static_cast<std::uint8_t>(NodeConstraint::fixed))
          return {&t, n, i == 0 || j == 0 || i == t.w - 1 || j == t.h - 1};
      }
  }
  return {};
}

/// Adds dv and du (exact multiples of the quanta) to the anchor.
void kick_anchor(Surface::State& s, const Anchor& a, double dv, double du) {
  a.tile->vz[a.node] += dv;
  a.tile->uz[a.node] += du;
  if (a.on_edge) s.refresh_edges(*a.tile, a.tile->cur);
}

/// Puts the rounding of damping and of the rise back on the anchor: afterwards the sum of
/// the damping impulses equals round(gamma dt / m * sum v) and the sum of the rises
/// round(dt * sum v'), exactly. The volume then changes by exactly the latter.
void restore_totals(Surface::State& s, const Totals& tot, const kernel::Coefficients& k) {
  const Anchor a = find_anchor(s);
  if (!a.tile) return;  // nothing moves: no rise either
  const double target_damped = nearest(k.beta * static_cast<double>(tot.v_before));
  const double extra_v = static_cast<double>(tot.damped) - target_damped;  // quanta
  const double v_after = static_cast<double>(tot.v_after) + extra_v;
  const double target_rise = nearest(k.dt_z * v_after * s.qv.q * s.qu.inv);
  const double extra_u = target_rise - static_cast<double>(tot.rise);
  kick_anchor(s, a, extra_v * s.qv.q, extra_u * s.qu.q);
}

/// Shares `momentum` (velocity quanta) exactly among the moving nodes of the awake tiles
/// around tile t (all awake tiles if none is next to it): every node gets the same count,
/// the first few one more.
void spread_momentum(Surface::State& s, const TileData& t, quantum::Wide momentum) {
  if (momentum == 0) return;
  std::vector<TileData*> around;
  for (int side = 0; side < kernel::kSides; ++side)
    if (TileData* n = s.find(t.tx + kSideDx[side], t.ty + kSideDy[side]); n && n->awake) around.push_back(n);
  if (around.empty())
    for (std::int32_t slot : s.awake)
      around.push_back(s.tiles[static_cast<std::size_t>(s.slot[static_cast<std::size_t>(slot)])].get());
  std::int64_t nodes = 0;
  for (const TileData* n : around)
    for (int j = 0; j < n->h; ++j)
      for (int i = 0; i < n->w; ++i)
        nodes += n->flags[n->at(i, j, s.T)] != static_cast<std::uint8_t>(NodeConstraint::fixed);
  if (nodes == 0) return;  // nothing moves: the momentum has nowhere to go
  quantum::Wide share = momentum / nodes, rest = momentum - share * nodes;
  if (rest < 0) {
    share -= 1;
    rest += nodes;
  }
  for (TileData* n : around) {
    for (int j = 0; j < n->h; ++j)
      for (int i = 0; i < n->w; ++i) {
        const std::size_t k = n->at(i, j, s.T);
        if (n->flags[k] == static_cast<std::uint8_t>(NodeConstraint::fixed)) continue;
        const quantum::Wide q = share + (rest > 0 ? 1 : 0);
        if (rest > 0) --rest;
        n->vz[k] += static_cast<double>(q) * s.qv.q;
      }
    s.refresh_edges(*n, n->cur);
  }
}

/// A tile falls asleep at rest: its velocities (below the threshold) are zeroed and their
/// vertical momentum shared among the awake nodes around it, so the awake water keeps its
/// net momentum and the volume stays exact. Returns the momentum in velocity quanta.
quantum::Wide put_to_sleep(Surface::State& s, TileData& t) {
  quantum::Wide momentum = 0;
  for (int j = 0; j < t.h; ++j)
    for (int i = 0; i < t.w; ++i) {
      const std::size_t n = t.at(i, j, s.T);
      momentum += quantum::count(t.vz[n], s.qv.inv);
      t.vz[n] = 0.0;
      if (s.full) t.vx[n] = t.vy[n] = 0.f;
    }
  t.awake = false;
  s.refresh_edges(t, t.cur);
  return momentum;
}

/// Whether a tile and the facing nodes of its neighbours lie flat within half the sleep
/// height (every component): only then may it sleep, at whatever level it stands.
bool flat(const Surface::State& s, const TileData& t) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  double xlo = lo, xhi = hi, ylo = lo, yhi = hi;
  const auto take = [&](double z, double x, double y) {
    lo = std::min(lo, z);
    hi = std::max(hi, z);
    xlo = std::min(xlo, x);
    xhi = std::max(xhi, x);
    ylo = std::min(ylo, y);
    yhi = std::max(yhi, y);
  };
  for (int j = 0; j < t.h; ++j)
    for (int i = 0; i < t.w; ++i) {
      const std::size_t k = t.at(i, j, s.T);
      take(t.uz[k], s.full ? t.ux[k] : 0.0, s.full ? t.uy[k] : 0.0);
    }
  for (int side = 0; side < 4; ++side) {
    const int tx = t.tx + kSideDx[side], ty = t.ty + kSideDy[side];
    if (!s.inside(tx, ty)) continue;
    const TileData* n = s.find(tx, ty);
    const int count = side <= kernel::kNorth ? t.w : t.h;
    const int facing = side == kernel::kSouth   ? kernel::kNorth
                       : side == kernel::kNorth ? kernel::kSouth
                       : side == kernel::kWest  ? kernel::kEast
                                                : kernel::kWest;
    for (int q = 0; q < count; ++q) {
      if (!n) {
        take(0.0, 0.0, 0.0);  // at rest
        break;
      }
      const TileData::Edges& e = n->edges[static_cast<std::size_t>(n->cur)];
      const std::size_t k = static_cast<std::size_t>(facing * s.T + q);
      take(e.z[k], s.full ? e.x[k] : 0.0, s.full ? e.y[k] : 0.0);
    }
  }
  const double limit = kSleepLevel * s.sleep_u;
  return hi - lo <= limit && xhi - xlo <= limit && yhi - ylo <= limit;
}

/// Wakes neighbours an awake tile's edges reach, counts calm substeps, puts calm tiles to
/// sleep.
void update_sleep(const SurfaceSettings& settings, Surface::State& s, const std::vector<kernel::TileResult>& results,
                  const std::vector<std::int32_t>& stepped) {
  std::vector<std::int32_t> excited;
  for (std::size_t n = 0; n < stepped.size(); ++n) {
    TileData& t = *s.tiles[static_cast<std::size_t>(s.slot[static_cast<std::size_t>(stepped[n])])];
    const kernel::TileResult& r = results[n];
    t.calm = r.activity <= kSleepLevel ? t.calm + 1 : 0;
    for (int side = 0; side < kernel::kSides; ++side) {
      const int tx = t.tx + kSideDx[side], ty = t.ty + kSideDy[side];
      if (r.side_activity[side] > kWakeLevel && s.inside(tx, ty)) excited.push_back(ty * s.tiles_x + tx);
    }
  }
  for (std::int32_t e : excited) {
    // Most are awake already (their calm count restarts): found, not obtained (a call more).
    TileData* n = s.find(e % s.tiles_x, e / s.tiles_x);
    s.set_awake(n ? *n : s.obtain(settings, e % s.tiles_x, e / s.tiles_x));
  }
  if (!settings.sleep.enabled) return;
  std::vector<std::pair<TileData*, quantum::Wide>> slept;
  for (std::int32_t slot : stepped) {
    TileData& t = *s.tiles[static_cast<std::size_t>(s.slot[static_cast<std::size_t>(slot)])];
    if (!t.awake || t.calm < settings.sleep.calm_substeps) continue;
    if (!flat(s, t)) {
      t.calm = 0;  // still, but standing on a slope: the water has not settled
      continue;
    }
    slept.emplace_back(&t, put_to_sleep(s, t));
  }
  if (slept.empty()) return;
  // Only tiles left the list: dropping them keeps it ascending, in O(awake) rather than a
  // pass over every tile ever created (a large lake holds many more asleep than awake).
  std::erase_if(s.awake, [&s](std::int32_t slot) {
    return !s.tiles[static_cast<std::size_t>(s.slot[static_cast<std::size_t>(slot)])]->awake;
  });
  for (const auto& [t, momentum] : slept) spread_momentum(s, *t, momentum);
}

/// One substep of every awake tile; returns whether it ran on the team.
bool step_tiles(const SurfaceSettings& settings, Surface::State& s, double dt) {
  const kernel::Coefficients k = coefficients(settings, s, dt);
  const std::vector<std::int32_t> stepped = s.awake;
  const std::int64_t nodes = static_cast<std::int64_t>(stepped.size()) * s.T * s.T;
  const bool forced = settings.parallel_min_nodes == 0;
  const bool parallel = s.threads > 1 && nodes >= settings.parallel_min_nodes && (forced || s.pacer.choose_parallel());
  if (parallel && !s.team) s.team = std::make_unique<Team>(s.threads);
  const int slots = parallel ? s.team->size() : 1;
  if (static_cast<int>(s.scratch.size()) < slots) s.scratch.resize(static_cast<std::size_t>(slots));
  std::vector<kernel::TileResult> results(stepped.size());
  for (std::int32_t slot : stepped) {  // here, not in the tasks: it allocates and counts memory
    TileData& t = *s.tiles[static_cast<std::size_t>(s.slot[static_cast<std::size_t>(slot)])];
    if (t.masks_stale) s.refresh_masks(t);
  }
  const auto tile_at = [&](std::size_t n) -> TileData& {
    return *s.tiles[static_cast<std::size_t>(s.slot[static_cast<std::size_t>(stepped[n])])];
  };
  const auto one = [&](std::size_t n, const TileData* next, Scratch& sc) {
    TileData& t = tile_at(n);
    kernel::Tile view = s.gather(t, sc, &k);
    if (next) view.next = next_of(*next, s.T);
    results[n] = s.full ? kernel::step_3d(s.variant, view, k, sc.workspace())
                        : kernel::step_vertical(s.variant, view, k, sc.workspace());
    s.refresh_edges(t, 1 - t.cur);
  };
  // Tiles in runs of consecutive ones per thread, each tile's kernel asking for the next
  // one's storage (kernel::Tile::next): its first reads then overlap the arithmetic
  // instead of stalling the next gather. Runs short enough (at least eight per thread)
  // that a thread slowed by the machine's load leaves the rest to the others.
  const std::size_t count = stepped.size();
  const std::size_t run =
      parallel ? std::clamp<std::size_t>(count / (8 * static_cast<std::size_t>(slots)), 1, 8) : count;
  const auto steps_run = [&](int item, int slot_index) {
    Scratch& sc = s.scratch[static_cast<std::size_t>(slot_index)];
    const std::size_t first = static_cast<std::size_t>(item) * run, last = std::min(count, first + run);
    for (std::size_t n = first; n < last; ++n) one(n, n + 1 < last ? &tile_at(n + 1) : nullptr, sc);
  };
  const auto t0 = std::chrono::steady_clock::now();
  if (parallel) {
    s.team->run(static_cast<int>((count + run - 1) / run), steps_run);
  } else if (count > 0) {
    steps_run(0, 0);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (s.threads > 1 && !forced && nodes >= settings.parallel_min_nodes && nodes > 0)
    s.pacer.record(parallel, seconds / static_cast<double>(nodes));

  Totals tot;
  kernel::Extremes e;
  for (std::size_t n = 0; n < stepped.size(); ++n) {
    TileData& t = *s.tiles[static_cast<std::size_t>(s.slot[static_cast<std::size_t>(stepped[n])])];
    t.cur = 1 - t.cur;
    const kernel::TileResult& r = results[n];
    tot.v_before += r.v_before;
    tot.damped += r.damped;
    tot.v_after += r.v_after;
    tot.rise += r.rise;
    e.merge(r.extremes);
  }
  restore_totals(s, tot, k);
  if (s.full) {
    const LatticeParameters& p = settings.lattice;
    for (std::int32_t slot : stepped) {
      const TileData& t = *s.tiles[static_cast<std::size_t>(s.slot[static_cast<std::size_t>(slot)])];
      for (int side : {kernel::kSouth, kernel::kWest, kernel::kNorth, kernel::kEast}) {
        const bool mine = side == kernel::kSouth || side == kernel::kWest ||
                          s.side_of(t, side) == kernel::Side::frozen;  // awake neighbours do their own
        if (mine && s.side_of(t, side) != kernel::Side::absent)
          e.relative = std::max(e.relative, relative_across(s, t, side));
      }
    }
    if (static_cast<std::size_t>(s.tiles_x) * static_cast<std::size_t>(s.tiles_y) != s.awake.size())
      e.merge(resting_extremes(p.spacing, s.sleep_u, s.sleep_v));
    // Measured on the positions the substep started from; then every spring vector moved by
    // (v_b - v_a) dt with the new velocities: at most r dt for an axis spring, 2 r dt for a
    // diagonal (r the largest axis relative speed), plus a hair for rounding.
    const double slack = std::sqrt(static_cast<double>(from_bits(e.relative))) * dt * (1.0 + 1e-6) + 1e-7 * p.spacing;
    s.deformation =
        deformation_of(e, p.rest_ratio * p.spacing, std::sqrt(2.0) * p.rest_ratio * p.spacing, slack, 2.0 * slack);
  }
  update_sleep(settings, s, results, stepped);
  return parallel;
}

}  // namespace

StepStats Surface::step(double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw InvalidSetting("water.Surface.step.dt", detail::to_text(dt), "must be finite and > 0");
  const LatticeParameters& p = settings_.lattice;
  const GuardSettings& guard = settings_.guard;
  State& s = *s_;
  const double damping = layer_damping(settings_, s);
  double omega = omega_bound();
  SubstepPlan plan = plan_substeps(omega, dt, p.mass, damping, guard.safety, guard.max_substeps);
  StepStats stats;
  stats.omega_bound = omega;
  stats.time_clamped = plan.time_clamped;
  int left = plan.substeps;
  double remaining = dt;
  while (left > 0 && stats.substeps < guard.max_substeps) {
    if (!s.awake.empty() && step_tiles(settings_, s, plan.substep)) ++stats.parallel_substeps;
    --left;
    ++stats.substeps;
    stats.simulated += plan.substep;
    remaining -= plan.substep;
    s.last_substep = plan.substep;
    if (left == 0) break;
    // The lattice may have stiffened during the substep: re-plan what is left if needed.
    omega = omega_bound();
    stats.omega_bound = std::max(stats.omega_bound, omega);
    if (omega * plan.substep > 2.0 * guard.safety * std::sqrt(1.0 - 0.5 * damping * plan.substep / p.mass)) {
      const int budget = guard.max_substeps - stats.substeps;
      if (budget < 1) {
        stats.time_clamped = true;
        break;
      }
      plan = plan_substeps(omega, remaining, p.mass, damping, guard.safety, budget);
      stats.time_clamped = stats.time_clamped || plan.time_clamped;
      left = plan.substeps;
    }
  }
  stats.substep = stats.simulated / stats.substeps;
  s.last_stats = stats;
  s.time += stats.simulated;
  return stats;
}

}  // namespace shore::water
