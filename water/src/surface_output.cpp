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

/// Nodes per side of the blocks the state hash digests one by one: a multiple of every
/// tile size, so the digest does not depend on the tile size.
constexpr int kHashBlock = 256;

/// FNV-1a digest of the nodes of hash block (bx, by): row by row, the constraints, then
/// u_z, v_z (and in 3-D u_x, u_y, v_x, v_y) of the whole row. Nodes of tiles not created
/// count at rest with their default constraints.
std::uint64_t block_digest(const Surface& surface, const Surface::State& s, int bx, int by) {
  const int i0 = bx * kHashBlock, j0 = by * kHashBlock;
  const int w = std::min(kHashBlock, surface.nx() - i0), h = std::min(kHashBlock, surface.ny() - j0);
  StateHash d;
  d.add(w);
  d.add(h);
  std::vector<std::uint8_t> flags(static_cast<std::size_t>(w));
  std::vector<double> z(static_cast<std::size_t>(w)), vz(static_cast<std::size_t>(w));
  std::vector<float> f[4];
  for (auto& v : f) v.assign(s.full ? static_cast<std::size_t>(w) : 0, 0.f);
  for (int r = 0; r < h; ++r) {
    const int j = j0 + r;
    for (int a = 0; a < w; ++a) {
      const int i = i0 + a;
      const TileData* t = s.find(i >> s.shift, j >> s.shift);
      const std::size_t n = static_cast<std::size_t>(a);
      if (!t) {
        flags[n] = static_cast<std::uint8_t>(
            default_constraint(surface.settings().boundary, i, j, surface.nx(), surface.ny()));
        z[n] = vz[n] = 0.0;
        for (auto& v : f)
          if (s.full) v[n] = 0.f;
        continue;
      }
      const std::size_t k = t->at(i & (s.T - 1), j & (s.T - 1), s.T);
      flags[n] = t->flags[k];
      z[n] = t->uz[k];
      vz[n] = t->vz[k];
      if (s.full) {
        f[0][n] = t->ux[k];
        f[1][n] = t->uy[k];
        f[2][n] = t->vx[k];
        f[3][n] = t->vy[k];
      }
    }
    d.add(std::span<const std::uint8_t>(flags));
    d.add(std::span<const double>(z));
    d.add(std::span<const double>(vz));
    if (s.full)
      for (const auto& v : f) d.add(std::span<const float>(v));
  }
  return d.value();
}

/// Whether any tile of hash block (bx, by) exists.
bool block_has_tiles(const Surface::State& s, int bx, int by) {
  const int per = kHashBlock / s.T;
  for (int ty = by * per; ty < std::min((by + 1) * per, s.tiles_y); ++ty)
    for (int tx = bx * per; tx < std::min((bx + 1) * per, s.tiles_x); ++tx)
      if (s.find(tx, ty)) return true;
  return false;
}

}  // namespace

std::uint64_t Surface::state_hash() const {
  const State& s = *s_;
  StateHash h;
  h.add(nx());
  h.add(ny());
  h.add(static_cast<std::uint8_t>(settings_.mode));
  const int bxs = (nx() + kHashBlock - 1) / kHashBlock, bys = (ny() + kHashBlock - 1) / kHashBlock;
  // Blocks without tiles differ only by which grid edges they touch and their size.
  std::map<std::tuple<int, int, int, int>, std::uint64_t> rest;
  for (int by = 0; by < bys; ++by)
    for (int bx = 0; bx < bxs; ++bx) {
      if (block_has_tiles(s, bx, by)) {
        h.add(block_digest(*this, s, bx, by));
        continue;
      }
      const auto key =
          std::make_tuple(bx == 0         ? 0
                          : bx == bxs - 1 ? 2
                                          : 1,
                          by == 0         ? 0
                          : by == bys - 1 ? 2
                                          : 1,
                          std::min(kHashBlock, nx() - bx * kHashBlock), std::min(kHashBlock, ny() - by * kHashBlock));
      auto it = rest.find(key);
      if (it == rest.end()) it = rest.emplace(key, block_digest(*this, s, bx, by)).first;
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
