// Fine level: the exact error of every bisection triangle inside a chunk, the chunk's
// summary for the coarse level, and the saturation of the fine vertices across chunks.
#include <algorithm>

#include "impl.h"

namespace shore::mesh {

using detail::ChunkData;
using detail::Tri;

void ChunkedMesh::Impl::compute_errors(std::uint64_t index, const GridRect& changed, RankQueue& seeds) {
  const Node o = chunk_origin(index);
  ChunkData& cd = data.at(index);
  const Block& b = chunk_block(index);
  std::array<Tri, 2> halves;
  const int n = detail::diamond({o.i + C / 2, o.j + C / 2}, S, halves);
  std::vector<Tri> stack(halves.begin(), halves.begin() + n);
  const std::int64_t ci1 = changed.i0 + changed.nx - 1, cj1 = changed.j0 + changed.ny - 1;
  while (!stack.empty()) {
    const Tri t = stack.back();
    stack.pop_back();
    if (!detail::has_split(t)) continue;
    // Triangles clear of the changed nodes keep their errors, and so does everything below.
    const std::int64_t i0 = std::min({t.p0.i, t.apex.i, t.p2.i}), i1 = std::max({t.p0.i, t.apex.i, t.p2.i});
    const std::int64_t j0 = std::min({t.p0.j, t.apex.j, t.p2.j}), j1 = std::max({t.p0.j, t.apex.j, t.p2.j});
    if (i1 < changed.i0 || i0 > ci1 || j1 < changed.j0 || j0 > cj1) continue;
    const Node m = detail::split_vertex(t);
    const float err = detail::float_up(detail::triangle_error(b, t, dom, height_field));
    float& slot = cd.e[static_cast<std::size_t>(detail::diamond_side(t, m))][local(o, m)];
    if (slot != err) {  // its vertex's saturated error may change
      slot = err;
      enqueue(seeds, m);
    }
    stack.push_back(detail::first_child(t, m));
    stack.push_back(detail::second_child(t, m));
  }
}

void ChunkedMesh::Impl::summarise(std::uint64_t index) {
  const Node o = chunk_origin(index);
  const Block& b = chunk_block(index);
  detail::Summary sm;
  const std::int64_t i1 = std::min(o.i + C, dom.ni - 1), j1 = std::min(o.j + C, dom.nj - 1);
  sm.ci = 0.5 * static_cast<double>(o.i + i1);
  sm.cj = 0.5 * static_cast<double>(o.j + j1);
  // Least squares plane through the nodes: normal equations in centred coordinates.
  double n = 0, si = 0, sj = 0, sii = 0, sjj = 0, sij = 0;
  detail::Vec3 sp{}, spi{}, spj{};
  for (std::int64_t j = o.j; j <= j1; ++j)
    for (std::int64_t i = o.i; i <= i1; ++i) {
      const double* p = b.at({i, j});
      if (detail::is_hole(p)) {
        sm.holes = true;
        continue;
      }
      sm.box.add(p);
      const double di = static_cast<double>(i) - sm.ci, dj = static_cast<double>(j) - sm.cj;
      n += 1, si += di, sj += dj, sii += di * di, sjj += dj * dj, sij += di * dj;
      for (std::size_t k = 0; k < 3; ++k) sp[k] += p[k], spi[k] += p[k] * di, spj[k] += p[k] * dj;
    }
  if (n > 0) {
    const double det = n * (sii * sjj - sij * sij) - si * (si * sjj - sij * sj) + sj * (si * sij - sii * sj);
    for (std::size_t k = 0; k < 3; ++k) {
      if (std::abs(det) > 1e-9 * std::max(1.0, n * sii * sjj)) {  // Cramer's rule
        sm.a[k] = (sp[k] * (sii * sjj - sij * sij) - si * (spi[k] * sjj - sij * spj[k]) +
                   sj * (spi[k] * sij - sii * spj[k])) /
                  det;
        sm.gi[k] =
            (n * (spi[k] * sjj - sij * spj[k]) - sp[k] * (si * sjj - sij * sj) + sj * (si * spj[k] - spi[k] * sj)) /
            det;
        sm.gj[k] =
            (n * (sii * spj[k] - spi[k] * sij) - si * (si * spj[k] - spi[k] * sj) + sp[k] * (si * sij - sii * sj)) /
            det;
      } else {
        sm.a[k] = sp[k] / n;  // a line of nodes: any plane will do, the residual says how far
      }
    }
  }
  for (std::int64_t j = o.j; j <= j1; ++j)
    for (std::int64_t i = o.i; i <= i1; ++i) {
      const double* p = b.at({i, j});
      if (!detail::is_hole(p))
        sm.residual = std::max(
            sm.residual, detail::distance(p, sm.plane(static_cast<double>(i), static_cast<double>(j)), height_field));
    }
  data.at(index).summary = sm;
}

double ChunkedMesh::Impl::fine_f(Node n, std::uint64_t hint) const {
  const Node o = chunk_origin(hint);
  if (n.i >= o.i && n.j >= o.j && n.i <= o.i + C && n.j <= o.j + C) {
    const auto it = data.find(hint);
    return it == data.end() ? 0.0 : static_cast<double>(it->second.f[local(o, n)]);
  }
  const std::int64_t cx = std::min(n.i / C, S / C - 1), cy = std::min(n.j / C, S / C - 1);
  const detail::ChunkData* d = chunk_data(chunk_index(cx, cy));
  return d ? static_cast<double>(d->f[local({cx * C, cy * C}, n)]) : 0.0;
}

void ChunkedMesh::Impl::enqueue(RankQueue& queue, Node v) {
  const std::int64_t cx = std::min(v.i / C, S / C - 1), cy = std::min(v.j / C, S / C - 1);
  if (detail::ChunkData* d = chunk_data(chunk_index(cx, cy))) {
    std::uint32_t& mark = d->queued[local({cx * C, cy * C}, v)];
    if (mark == pass) return;
    mark = pass;
  }
  queue[static_cast<std::size_t>(detail::classify(v, S).rank())].push_back(node_key(v));
}

std::vector<std::uint64_t> ChunkedMesh::Impl::saturate_fine(RankQueue& queue) {
  std::vector<std::uint64_t> centres;
  const int top = detail::classify({C / 2, C / 2}, S).rank();  // a chunk's centre
  for (int r = 0; r <= top; ++r) {
    std::vector<std::uint64_t>& rank = queue[static_cast<std::size_t>(r)];
    for (const std::uint64_t key : rank) {
      const Node v = node_of(key);
      // The chunks whose closed square holds v: one, or two for a vertex on a chunk's side.
      std::array<std::uint64_t, 2> holders{};
      int count = 0;
      const std::int64_t cx = std::min(v.i / C, S / C - 1), cy = std::min(v.j / C, S / C - 1);
      holders[static_cast<std::size_t>(count++)] = chunk_index(cx, cy);
      if (v.i % C == 0 && v.i > 0 && v.i < S) holders[static_cast<std::size_t>(count++)] = chunk_index(cx - 1, cy);
      if (v.j % C == 0 && v.j > 0 && v.j < S) holders[static_cast<std::size_t>(count++)] = chunk_index(cx, cy - 1);
      double f = 0.0;  // its own error, in whichever chunk its diamond's triangles lie ...
      std::array<detail::ChunkData*, 2> held{};
      for (int q = 0; q < count; ++q) {
        detail::ChunkData* d = held[static_cast<std::size_t>(q)] = chunk_data(holders[static_cast<std::size_t>(q)]);
        if (!d) continue;
        const std::size_t k = local(chunk_origin(holders[static_cast<std::size_t>(q)]), v);
        f = std::max({f, static_cast<double>(d->e[0][k]), static_cast<double>(d->e[1][k])});
      }
      std::array<Node, 4> kids;  // ... and its children's saturated errors
      const int nk = detail::children(v, S, kids);
      for (int q = 0; q < nk; ++q) f = std::max(f, fine_f(kids[static_cast<std::size_t>(q)], holders[0]));
      const float value = detail::float_up(f);
      bool moved = false;
      for (int q = 0; q < count; ++q) {
        detail::ChunkData* d = held[static_cast<std::size_t>(q)];
        if (!d) continue;
        float& slot = d->f[local(chunk_origin(holders[static_cast<std::size_t>(q)]), v)];
        if (slot == value) continue;
        slot = value;
        moved = true;
        if (d->bumped != pass) d->bumped = pass, ++d->version;
      }
      if (!moved) continue;
      if (r == top) {  // a chunk's centre: its parents are coarse
        centres.push_back(holders[0]);
        continue;
      }
      std::array<Node, 2> ps;
      const int np = detail::parents(v, S, ps);
      for (int q = 0; q < np; ++q) enqueue(queue, ps[static_cast<std::size_t>(q)]);
    }
    rank.clear();
  }
  std::sort(centres.begin(), centres.end());
  return centres;
}

}  // namespace shore::mesh
