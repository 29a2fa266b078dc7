// Fine level: the exact error of every bisection triangle inside a chunk, the chunk's
// summary for the coarse level, and the saturation of the fine vertices across chunks.
#include <algorithm>

#include "impl.h"

namespace shore::mesh {

using detail::ChunkData;
using detail::Tri;

namespace {

/// A chunk and its eight neighbours (null where not allocated).
struct Neighbourhood {
  detail::Node origin;
  std::int64_t C = 0;
  std::array<std::array<ChunkData*, 3>, 3> at{};  // [dx + 1][dy + 1]

  /// The chunk holding n (n within one chunk of the centre one): the centre one if n lies
  /// in its closed square, else the neighbour n lies in.
  [[nodiscard]] std::pair<ChunkData*, detail::Node> owner(detail::Node n) const {
    const int dx = n.i < origin.i ? -1 : (n.i > origin.i + C ? 1 : 0);
    const int dy = n.j < origin.j ? -1 : (n.j > origin.j + C ? 1 : 0);
    return {at[static_cast<std::size_t>(dx + 1)][static_cast<std::size_t>(dy + 1)],
            {origin.i + dx * C, origin.j + dy * C}};
  }
};

}  // namespace

void ChunkedMesh::Impl::compute_errors(std::uint64_t index, const NodeRect& changed) {
  const Node o = chunk_origin(index);
  ChunkData& cd = data.at(index);
  const Block& b = chunk_block(index);
  std::array<Tri, 2> halves;
  const int n = detail::diamond({o.i + C / 2, o.j + C / 2}, S, halves);
  std::vector<Tri> stack(halves.begin(), halves.begin() + n);
  const std::int64_t ci1 = changed.i0 + changed.ni - 1, cj1 = changed.j0 + changed.nj - 1;
  while (!stack.empty()) {
    const Tri t = stack.back();
    stack.pop_back();
    if (!detail::has_split(t)) continue;
    // Triangles clear of the changed nodes keep their errors, and so does everything below.
    const std::int64_t i0 = std::min({t.p0.i, t.apex.i, t.p2.i}), i1 = std::max({t.p0.i, t.apex.i, t.p2.i});
    const std::int64_t j0 = std::min({t.p0.j, t.apex.j, t.p2.j}), j1 = std::max({t.p0.j, t.apex.j, t.p2.j});
    if (i1 < changed.i0 || i0 > ci1 || j1 < changed.j0 || j0 > cj1) continue;
    const Node m = detail::split_vertex(t);
    const double err = detail::triangle_error(b, t, dom, height_field);
    cd.e[static_cast<std::size_t>(detail::diamond_side(t, m))][local(o, m)] = detail::float_up(err);
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
  const auto it = data.find(chunk_index(cx, cy));
  return it == data.end() ? 0.0 : static_cast<double>(it->second.f[local({cx * C, cy * C}, n)]);
}

std::vector<std::uint64_t> ChunkedMesh::Impl::saturate_fine(const std::vector<std::uint64_t>& indices) {
  std::vector<Neighbourhood> hoods;
  for (const std::uint64_t index : indices) {
    Neighbourhood h;
    h.origin = chunk_origin(index);
    h.C = C;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy) {
        const std::int64_t cx = h.origin.i / C + dx, cy = h.origin.j / C + dy;
        if (cx < 0 || cy < 0 || cx * C >= S || cy * C >= S) continue;
        const auto it = data.find(chunk_index(cx, cy));
        if (it != data.end()) h.at[static_cast<std::size_t>(dx + 1)][static_cast<std::size_t>(dy + 1)] = &it->second;
      }
    hoods.push_back(h);
  }
  std::set<ChunkData*> changed;
  std::vector<std::uint64_t> centres;
  // One vertex: its own error and its children's saturated errors, stored in every chunk
  // that holds it (a vertex on a chunk's side is in both).
  auto saturate = [&](const Neighbourhood& h, Node v) {
    // The chunks whose closed square holds v: this one, and the one across the side v is on.
    std::array<std::pair<int, int>, 2> holders{{{0, 0}, {0, 0}}};
    int count = 1;
    if (v.i == h.origin.i) holders[static_cast<std::size_t>(count++)] = {-1, 0};
    if (v.i == h.origin.i + C) holders[static_cast<std::size_t>(count++)] = {1, 0};
    if (v.j == h.origin.j) holders[static_cast<std::size_t>(count++)] = {0, -1};
    if (v.j == h.origin.j + C) holders[static_cast<std::size_t>(count++)] = {0, 1};
    // Its own error: the largest of its diamond's triangles, in whichever chunk they lie.
    double f = 0.0;
    for (int q = 0; q < count; ++q) {
      const auto [dx, dy] = holders[static_cast<std::size_t>(q)];
      const ChunkData* c = h.at[static_cast<std::size_t>(dx + 1)][static_cast<std::size_t>(dy + 1)];
      if (!c) continue;
      const std::size_t k = local({h.origin.i + dx * C, h.origin.j + dy * C}, v);
      f = std::max({f, static_cast<double>(c->e[0][k]), static_cast<double>(c->e[1][k])});
    }
    // And its children's saturated errors.
    std::array<Node, 4> kids;
    const int nk = detail::children(v, S, kids);
    for (int q = 0; q < nk; ++q) {
      const auto [owner, origin] = h.owner(kids[static_cast<std::size_t>(q)]);
      if (owner) f = std::max(f, static_cast<double>(owner->f[local(origin, kids[static_cast<std::size_t>(q)])]));
    }
    const float value = detail::float_up(f);
    for (int q = 0; q < count; ++q) {
      const auto [dx, dy] = holders[static_cast<std::size_t>(q)];
      ChunkData* owner = h.at[static_cast<std::size_t>(dx + 1)][static_cast<std::size_t>(dy + 1)];
      if (!owner) continue;
      float& slot = owner->f[local({h.origin.i + dx * C, h.origin.j + dy * C}, v)];
      if (slot != value) {
        slot = value;
        changed.insert(owner);
      }
    }
  };
  std::vector<float> centre_before;
  for (const Neighbourhood& h : hoods)
    centre_before.push_back(h.at[1][1]->f[local(h.origin, {h.origin.i + C / 2, h.origin.j + C / 2})]);
  for (std::int64_t t = 1; t <= C / 2; t *= 2) {
    for (const Neighbourhood& h : hoods) {  // edges of half-length t
      for (std::int64_t b = 0; b <= C / (2 * t); ++b)
        for (std::int64_t a = 0; a < C / (2 * t); ++a) {
          saturate(h, {h.origin.i + t * (2 * a + 1), h.origin.j + 2 * t * b});
          saturate(h, {h.origin.i + 2 * t * b, h.origin.j + t * (2 * a + 1)});
        }
    }
    for (const Neighbourhood& h : hoods)  // centres of squares of side 2t
      for (std::int64_t b = 0; b < C / (2 * t); ++b)
        for (std::int64_t a = 0; a < C / (2 * t); ++a)
          saturate(h, {h.origin.i + t * (2 * a + 1), h.origin.j + t * (2 * b + 1)});
  }
  for (std::size_t q = 0; q < indices.size(); ++q) {
    const Neighbourhood& h = hoods[q];
    if (h.at[1][1]->f[local(h.origin, {h.origin.i + C / 2, h.origin.j + C / 2})] != centre_before[q])
      centres.push_back(indices[q]);
  }
  for (ChunkData* c : changed) ++c->version;
  return centres;
}

}  // namespace shore::mesh
