// What the surface gives out: meshes, normals, energy, totals, the state hash, tile
// statistics and dense copies.
#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include <Eigen/Geometry>

#include "shore/core/hash.h"
#include "surface_state.h"

namespace shore::water {

namespace {

/// A node's displacement and velocity as doubles (zeros for a tile not created).
struct NodeValue {
  double ux = 0, uy = 0, uz = 0, vx = 0, vy = 0, vz = 0;
  NodeConstraint c = NodeConstraint::free;
};

NodeValue node_value(const Surface& surface, const Surface::State& s, int i, int j) {
  NodeValue v;
  const TileData* t = s.find(i >> s.shift, j >> s.shift);
  if (!t) {
    v.c = default_constraint(surface.settings().boundary, i, j, surface.nx(), surface.ny());
    return v;
  }
  const std::size_t k = t->at(i & (s.T - 1), j & (s.T - 1), s.T);
  v.uz = t->uz[k];
  v.vz = t->vz[k];
  v.c = static_cast<NodeConstraint>(t->flags[k]);
  if (s.full) {
    v.ux = t->ux[k];
    v.uy = t->uy[k];
    v.vx = t->vx[k];
    v.vy = t->vy[k];
  }
  return v;
}

/// The springs of node (i, j) as (di, dj) to the other end: the four "forward" ones it
/// starts and the four "backward" ones that end at it.
constexpr int kSpringDi[8] = {1, 0, 1, -1, -1, 0, -1, 1};
constexpr int kSpringDj[8] = {0, 1, 1, 1, 0, -1, -1, -1};

}  // namespace

void Surface::positions(std::vector<float>& xyz) const {
  xyz.resize(3 * node_count());
  for (int j = 0; j < ny(); ++j)
    for (int i = 0; i < nx(); ++i) {
      const NodeValue v = node_value(*this, *s_, i, j);
      const std::size_t k = static_cast<std::size_t>(j) * static_cast<std::size_t>(nx()) + static_cast<std::size_t>(i);
      xyz[3 * k + 0] = static_cast<float>(node_x(i) + v.ux);
      xyz[3 * k + 1] = static_cast<float>(node_y(j) + v.uy);
      xyz[3 * k + 2] = static_cast<float>(settings_.rest_height + v.uz);
    }
}

void Surface::normals(std::vector<float>& xyz) const {
  xyz.resize(3 * node_count());
  const double h = spacing();
  // Differences in the displacement form, so the result does not depend on the origin.
  const auto rel = [&](int i, int j) {
    const NodeValue v = node_value(*this, *s_, i, j);
    return Eigen::Vector3d(i * h + v.ux, j * h + v.uy, v.uz);
  };
  for (int j = 0; j < ny(); ++j)
    for (int i = 0; i < nx(); ++i) {
      const Eigen::Vector3d dx = rel(std::min(i + 1, nx() - 1), j) - rel(std::max(i - 1, 0), j);
      const Eigen::Vector3d dy = rel(i, std::min(j + 1, ny() - 1)) - rel(i, std::max(j - 1, 0));
      Eigen::Vector3d n = dx.cross(dy);
      const double len = n.norm();
      n = len > 0.0 && std::isfinite(len) ? Eigen::Vector3d(n / len) : Eigen::Vector3d(0, 0, 1);
      const std::size_t k = static_cast<std::size_t>(j) * static_cast<std::size_t>(nx()) + static_cast<std::size_t>(i);
      xyz[3 * k + 0] = static_cast<float>(n.x());
      xyz[3 * k + 1] = static_cast<float>(n.y());
      xyz[3 * k + 2] = static_cast<float>(n.z());
    }
}

void triangulate(int nx, int ny, std::vector<std::uint32_t>& indices) {
  indices.clear();
  if (nx < 2 || ny < 2) return;
  indices.reserve(6 * static_cast<std::size_t>(nx - 1) * static_cast<std::size_t>(ny - 1));
  const auto v = [nx](int i, int j) {
    return static_cast<std::uint32_t>(j) * static_cast<std::uint32_t>(nx) + static_cast<std::uint32_t>(i);
  };
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      indices.insert(indices.end(), {v(i, j), v(i + 1, j), v(i, j + 1)});
      indices.insert(indices.end(), {v(i, j + 1), v(i + 1, j), v(i + 1, j + 1)});
    }
}

void Surface::triangles(std::vector<std::uint32_t>& indices) const { triangulate(nx(), ny(), indices); }

namespace {

/// Spring force on end a (towards b) and its potential, in double precision: 3-D Hooke with
/// pre-tension, or the linearised vertical form.
struct SpringTerm {
  Eigen::Vector3d f;
  double potential;
};
SpringTerm spring_term(const LatticeParameters& p, bool full, const NodeValue& a, const NodeValue& b, int di, int dj) {
  const double h = p.spacing;
  if (!full) {
    const double dz = b.uz - a.uz, kt = p.transverse_stiffness();
    return {Eigen::Vector3d(0, 0, kt * dz), 0.5 * kt * dz * dz};
  }
  const Eigen::Vector3d d(di * h + (b.ux - a.ux), dj * h + (b.uy - a.uy), b.uz - a.uz);
  const double l0 = std::sqrt(double(di * di + dj * dj)) * h, rest = p.rest_ratio * l0;
  const double l = d.norm();
  const double s = l > 0.0 ? p.stiffness * (1.0 - rest / l) : 0.0;
  return {s * d, 0.5 * p.stiffness * ((l - rest) * (l - rest) - (l0 - rest) * (l0 - rest))};
}

}  // namespace

Energy Surface::energy() const {
  const LatticeParameters& p = settings_.lattice;
  const State& s = *s_;
  const double dt = s.last_substep;
  const double keep = 1.0 - p.damping * dt / p.mass, impulse = dt / p.mass;
  double potential = 0.0, kinetic = 0.0, centred = 0.0;
  for (const auto& tile : s.tiles) {
    const TileData& t = *tile;
    for (int lj = 0; lj < t.h; ++lj)
      for (int li = 0; li < t.w; ++li) {
        const int i = t.tx * s.T + li, j = t.ty * s.T + lj;
        const NodeValue a = node_value(*this, s, i, j);
        Eigen::Vector3d f = Eigen::Vector3d::Zero();
        for (int k = 0; k < 8; ++k) {
          const int bi = i + kSpringDi[k], bj = j + kSpringDj[k];
          if (bi < 0 || bj < 0 || bi >= nx() || bj >= ny()) continue;
          const NodeValue b = node_value(*this, s, bi, bj);
          const SpringTerm term = spring_term(p, s.full, a, b, kSpringDi[k], kSpringDj[k]);
          f += term.f;
          // Each spring once: by its first end (forward springs), or by its second end when
          // the first end's tile does not exist.
          const bool forward = k < 4;
          if (forward || !s.find(bi >> s.shift, bj >> s.shift)) potential += term.potential;
        }
        const double mh = a.c == NodeConstraint::free ? 1.0 : 0.0;
        const double mv = a.c != NodeConstraint::fixed ? 1.0 : 0.0;
        double v2 = a.vz * a.vz;
        double vnext = a.vz * (a.vz * keep + f.z() * impulse) * mv;
        if (s.full) {
          v2 += a.vx * a.vx + a.vy * a.vy;
          vnext += (a.vx * (a.vx * keep + f.x() * impulse) + a.vy * (a.vy * keep + f.y() * impulse)) * mh;
        }
        kinetic += 0.5 * p.mass * v2;
        centred += 0.5 * p.mass * (dt > 0.0 ? vnext : v2);
      }
  }
  Energy e;
  e.kinetic = kinetic;
  e.potential = potential;
  e.total = kinetic + potential;
  e.centred = centred + potential;
  return e;
}

namespace {

/// FNV-1a digest of one tile's nodes (constraints and state, row by row); `t` null: a tile
/// not created (at rest, default constraints).
std::uint64_t tile_digest(const Surface& surface, const Surface::State& s, int tx, int ty, const TileData* t) {
  const int w = std::min(s.T, surface.nx() - tx * s.T), h = std::min(s.T, surface.ny() - ty * s.T);
  StateHash d;
  d.add(w);
  d.add(h);
  std::vector<std::uint8_t> flags(static_cast<std::size_t>(w));
  const std::vector<double> zeros_d(static_cast<std::size_t>(w), 0.0);
  const std::vector<float> zeros_f(static_cast<std::size_t>(w), 0.f);
  for (int r = 0; r < h; ++r) {
    const std::size_t o = static_cast<std::size_t>(r) * static_cast<std::size_t>(s.T);
    const auto row_d = [&](const std::vector<double>& v) {
      return t ? std::span<const double>(v.data() + o, static_cast<std::size_t>(w)) : std::span<const double>(zeros_d);
    };
    const auto row_f = [&](const std::vector<float>& v) {
      return t ? std::span<const float>(v.data() + o, static_cast<std::size_t>(w)) : std::span<const float>(zeros_f);
    };
    if (t) {
      d.add(std::span<const std::uint8_t>(t->flags.data() + o, static_cast<std::size_t>(w)));
    } else {
      for (int i = 0; i < w; ++i)
        flags[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(
            default_constraint(surface.settings().boundary, tx * s.T + i, ty * s.T + r, surface.nx(), surface.ny()));
      d.add(std::span<const std::uint8_t>(flags));
    }
    d.add(row_d(t ? t->uz : zeros_d));
    d.add(row_d(t ? t->vz : zeros_d));
    if (s.full) {
      d.add(row_f(t ? t->ux : zeros_f));
      d.add(row_f(t ? t->uy : zeros_f));
      d.add(row_f(t ? t->vx : zeros_f));
      d.add(row_f(t ? t->vy : zeros_f));
    }
  }
  return d.value();
}

}  // namespace

std::uint64_t Surface::state_hash() const {
  const State& s = *s_;
  StateHash h;
  h.add(nx());
  h.add(ny());
  h.add(static_cast<std::uint8_t>(settings_.mode));
  // Tiles not created differ only by which grid edges they touch and their size.
  std::map<std::tuple<int, int, int, int>, std::uint64_t> rest;
  for (int ty = 0; ty < s.tiles_y; ++ty)
    for (int tx = 0; tx < s.tiles_x; ++tx) {
      const TileData* t = s.find(tx, ty);
      if (t) {
        h.add(tile_digest(*this, s, tx, ty, t));
        continue;
      }
      const auto key = std::make_tuple(tx == 0 ? 0 : tx == s.tiles_x - 1 ? 2 : 1, ty == 0 ? 0 : ty == s.tiles_y - 1 ? 2 : 1,
                                       std::min(s.T, nx() - tx * s.T), std::min(s.T, ny() - ty * s.T));
      auto it = rest.find(key);
      if (it == rest.end()) it = rest.emplace(key, tile_digest(*this, s, tx, ty, nullptr)).first;
      h.add(it->second);
    }
  return h.value();
}

double Surface::volume() const {
  const State& s = *s_;
  quantum::Wide quanta = 0;
  for (const auto& t : s.tiles)
    for (int j = 0; j < t->h; ++j)
      for (int i = 0; i < t->w; ++i) quanta += quantum::count(t->uz[t->at(i, j, s.T)], s.qu.inv);
  return static_cast<double>(quanta) * s.qu.q * spacing() * spacing();
}

double Surface::mean_level() const {
  return settings_.rest_height + volume() / (static_cast<double>(node_count()) * spacing() * spacing());
}

TileStats Surface::tile_stats() const {
  const State& s = *s_;
  TileStats r;
  r.tile = s.T;
  r.tiles = static_cast<std::int64_t>(s.tiles_x) * s.tiles_y;
  r.created = static_cast<std::int64_t>(s.tiles.size());
  r.awake = static_cast<std::int64_t>(s.awake.size());
  for (std::int32_t slot : s.awake) {
    const TileData& t = *s.tiles[static_cast<std::size_t>(s.slot[static_cast<std::size_t>(slot)])];
    r.awake_nodes += static_cast<std::int64_t>(t.w) * t.h;
  }
  r.ever_awake = s.ever_awake;
  r.memory_bytes = s.memory_bytes();
  return r;
}

DenseState Surface::dense_state() const {
  DenseState d;
  const std::size_t n = node_count();
  d.uz.assign(n, 0.0);
  d.vz.assign(n, 0.0);
  d.constraints.assign(n, NodeConstraint::free);
  if (s_->full) {
    d.ux.assign(n, 0.f);
    d.uy.assign(n, 0.f);
    d.vx.assign(n, 0.f);
    d.vy.assign(n, 0.f);
  }
  for (int j = 0; j < ny(); ++j)
    for (int i = 0; i < nx(); ++i) {
      const std::size_t k = static_cast<std::size_t>(j) * static_cast<std::size_t>(nx()) + static_cast<std::size_t>(i);
      const NodeValue v = node_value(*this, *s_, i, j);
      d.uz[k] = v.uz;
      d.vz[k] = v.vz;
      d.constraints[k] = v.c;
      if (s_->full) {
        d.ux[k] = static_cast<float>(v.ux);
        d.uy[k] = static_cast<float>(v.uy);
        d.vx[k] = static_cast<float>(v.vx);
        d.vy[k] = static_cast<float>(v.vy);
      }
    }
  return d;
}

}  // namespace shore::water
