// Output: which triangles are leaves (their split vertex is not active), chunk by chunk,
// and the vertex, normal and index arrays of the chunks that changed.
#include <algorithm>

#include "impl.h"

namespace shore::mesh {

using detail::Tri;

double ChunkedMesh::Impl::quantised_distance(const Box& b) const {
  if (b.empty()) return detail::kInf;
  double d2 = 0.0;
  const double eye[3] = {camera->position.x, camera->position.y, camera->position.z};
  for (std::size_t k = 0; k < 3; ++k) {
    const double gap = std::max({b.lo[k] - eye[k], eye[k] - b.hi[k], 0.0});
    d2 += gap * gap;
  }
  const double d = std::sqrt(d2);
  if (!(d > 0.0)) return 0.0;
  // Rounded down to the ladder 2^e 0.5 2^(k / steps): the mantissa picks the step.
  int e = 0;
  const double m = std::frexp(d, &e);
  std::size_t k = distance_steps.size() - 1;
  while (k > 0 && distance_steps[k] > m) --k;
  return std::ldexp(distance_steps[k], e);
}

double ChunkedMesh::Impl::square_distance(Node origin, std::int64_t side) const {
  return quantised_distance(square_box(origin, side));
}

bool ChunkedMesh::Impl::active(double f, double distance) const {
  if (!camera) return f > s.max_error;
  // The error subtends at most f / distance radians from the eye.
  return f * pixels_per_radian > s.max_error_pixels * distance;
}

double ChunkedMesh::Impl::coarse_vertex_distance(Node v) const {
  if (!camera) return 0.0;
  const detail::VertexClass c = detail::classify(v, S);
  const std::int64_t r = detail::reach(c), side = 2 * c.t;
  // The squares of side 2t (as coarse as the vertex's own) overlapping its reach.
  double d = detail::kInf;
  for (std::int64_t j = std::max<std::int64_t>(0, (v.j - r) / side * side); j < std::min(S, v.j + r); j += side)
    for (std::int64_t i = std::max<std::int64_t>(0, (v.i - r) / side * side); i < std::min(S, v.i + r); i += side)
      if (i + side > v.i - r && j + side > v.j - r) d = std::min(d, square_distance({i, j}, side));
  return d;
}

void ChunkedMesh::Impl::collect(const Tri& t, std::map<std::uint64_t, int>& reached,
                                std::map<ChunkKey, std::vector<Tri>>& coarse_leaves) {
  const std::int64_t i0 = std::min({t.p0.i, t.apex.i, t.p2.i}), j0 = std::min({t.p0.j, t.apex.j, t.p2.j});
  if (i0 > dom.ni - 1 || j0 > dom.nj - 1) return;  // beyond the grid
  const std::int64_t side = detail::square_side(t);
  const Node m = detail::split_vertex(t);
  if (side <= C) {  // a half of a fine chunk: the chunk takes it from here
    reached[chunk_of(detail::square_origin(t, C))] |= 1 << detail::diamond_side(t, m);
    return;
  }
  if (active(coarse_f(m), coarse_vertex_distance(m))) {
    collect(detail::first_child(t, m), reached, coarse_leaves);
    collect(detail::second_child(t, m), reached, coarse_leaves);
    return;
  }
  const Node o = detail::square_origin(t, side);
  coarse_leaves[ChunkKey{side, o.j, o.i}].push_back(t);
}

void ChunkedMesh::Impl::fine_leaves(std::uint64_t index, const detail::Signature& sig, std::vector<Tri>& out) const {
  const Node o = chunk_origin(index);
  const auto found = data.find(index);
  const std::vector<float>* f = found == data.end() ? nullptr : &found->second.f;
  std::array<Tri, 2> halves;
  const int n = detail::diamond({o.i + C / 2, o.j + C / 2}, S, halves);
  std::vector<Tri> stack;
  stack.reserve(64);  // depth first: at most two per level
  for (int k = n - 1; k >= 0; --k)
    if (sig.halves & (1 << detail::diamond_side(halves[static_cast<std::size_t>(k)], {o.i + C / 2, o.j + C / 2})))
      stack.push_back(halves[static_cast<std::size_t>(k)]);
  while (!stack.empty()) {
    const Tri t = stack.back();
    stack.pop_back();
    if (std::min({t.p0.i, t.apex.i, t.p2.i}) > dom.ni - 1 || std::min({t.p0.j, t.apex.j, t.p2.j}) > dom.nj - 1)
      continue;
    if (detail::has_split(t)) {
      const Node m = detail::split_vertex(t);
      const double err = f ? static_cast<double>((*f)[local(o, m)]) : 0.0;
      double d = 0.0;
      if (camera && err > 0.0) {  // the nearest of the chunks the vertex's subtree reaches
        const std::int64_t r = detail::reach(detail::classify(m, S));
        if (m.i - r >= o.i && m.i + r <= o.i + C && m.j - r >= o.j && m.j + r <= o.j + C) {
          d = sig.distance[1][1];  // this chunk's alone
        } else {
          d = detail::kInf;
          for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy) {
              const std::int64_t i0 = o.i + dx * C, j0 = o.j + dy * C;
              if (i0 < m.i + r && i0 + C > m.i - r && j0 < m.j + r && j0 + C > m.j - r)
                d = std::min(d, sig.distance[static_cast<std::size_t>(dx + 1)][static_cast<std::size_t>(dy + 1)]);
            }
        }
      }
      if (err > 0.0 && active(err, d)) {
        stack.push_back(detail::second_child(t, m));  // first child on top: depth first, first child first
        stack.push_back(detail::first_child(t, m));
        continue;
      }
    }
    out.push_back(t);
  }
}

bool ChunkedMesh::Impl::output_dirty(const ChunkKey& key) const {
  if (key.cells == C) return dirty_output_chunks.count(chunk_of({key.i0, key.j0})) > 0;
  for (const GridRect& r : dirty_output)
    if (r.i0 <= key.i0 + key.cells && r.i0 + r.nx - 1 >= key.i0 && r.j0 <= key.j0 + key.cells &&
        r.j0 + r.ny - 1 >= key.j0)
      return true;
  return false;
}

void ChunkedMesh::Impl::rebuild_output(MeshUpdate& u) {
  std::map<std::uint64_t, int> reached;
  std::map<ChunkKey, std::vector<Tri>> coarse_leaves;
  std::array<Tri, 2> roots;
  const int n = detail::diamond({S / 2, S / 2}, S, roots);
  for (int k = 0; k < n; ++k) collect(roots[static_cast<std::size_t>(k)], reached, coarse_leaves);

  std::set<ChunkKey> present;
  // A chunk's new leaves replace its old ones; it is reported when they, or its nodes, changed.
  auto settle = [&](const ChunkKey& key, const detail::Signature& sig, std::vector<Tri> leaves) {
    auto it = built.find(key);
    const bool dirty = output_dirty(key);
    if (it != built.end() && !dirty && it->second.leaves == leaves) {
      it->second.signature = sig;
      present.insert(key);
      return;
    }
    Chunk c = emit(key, leaves);
    if (c.indices.empty()) return;  // nothing of the grid in it
    chunks[key] = std::move(c);
    built[key] = {sig, std::move(leaves)};
    present.insert(key);
    u.changed.push_back(key);
  };
  for (const auto& [index, halves] : reached) {
    const Node o = chunk_origin(index);
    const ChunkKey key{C, o.j, o.i};
    Signature sig;
    const auto d = data.find(index);
    sig.version = d == data.end() ? 0 : d->second.version;
    sig.halves = halves;
    if (camera)
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy) {
          const Node a{o.i + dx * C, o.j + dy * C};
          const bool inside = a.i >= 0 && a.j >= 0 && a.i < S && a.j < S;
          sig.distance[static_cast<std::size_t>(dx + 1)][static_cast<std::size_t>(dy + 1)] =
              inside ? square_distance(a, C) : detail::kInf;
        }
    const auto b = built.find(key);
    if (b != built.end() && b->second.signature == sig && !output_dirty(key)) {
      present.insert(key);
      continue;
    }
    std::vector<Tri> leaves;
    fine_leaves(index, sig, leaves);
    settle(key, sig, std::move(leaves));
  }
  for (auto& [key, leaves] : coarse_leaves) settle(key, Signature{}, std::move(leaves));

  for (auto it = built.begin(); it != built.end();) {
    if (present.count(it->first)) {
      ++it;
      continue;
    }
    u.removed.push_back(it->first);
    chunks.erase(it->first);
    it = built.erase(it);
  }
  std::sort(u.changed.begin(), u.changed.end());
  triangles = 0;
  for (const auto& [key, c] : chunks) triangles += c.triangle_count();
}

namespace {

/// Unit normal of the full-resolution surface at a node: central differences along i and j
/// (one-sided at the grid's border or next to a hole).
detail::Vec3 node_normal(const detail::Block& b, const detail::Domain& dom, detail::Node n) {
  auto get = [&](detail::Node x) -> const double* {
    if (!dom.contains(x) || !b.holds(x)) return nullptr;
    const double* p = b.at(x);
    return detail::is_hole(p) ? nullptr : p;
  };
  const double* c = get(n);
  auto diff = [&](detail::Node step) {
    const double* fwd = get(n + step);
    const double* back = get(n - step);
    detail::Vec3 d{0.0, 0.0, 0.0};
    const double* hi = fwd ? fwd : c;
    const double* lo = back ? back : c;
    if (hi && lo && hi != lo)
      for (std::size_t k = 0; k < 3; ++k) d[k] = hi[k] - lo[k];
    return d;
  };
  const detail::Vec3 u = diff({1, 0}), v = diff({0, 1});
  detail::Vec3 nrm{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  const double len = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
  if (!(len > 0.0) || !std::isfinite(len)) return {0.0, 0.0, 1.0};
  return {nrm[0] / len, nrm[1] / len, nrm[2] / len};
}

}  // namespace

std::vector<std::uint64_t> ChunkedMesh::Impl::used_nodes(const ChunkKey& key, const std::vector<Piece>& pieces) const {
  // The nodes used, in node key order (row by row).
  std::vector<std::uint64_t> keys;
  if (key.cells == C) {  // a fine chunk: a flag per node of the chunk's square beats sorting
    const Node o{key.i0, key.j0};
    std::vector<char> used(static_cast<std::size_t>((C + 1) * (C + 1)), 0);
    for (const auto& p : pieces)
      for (const Node& q : p) used[local(o, q)] = 1;
    for (std::int64_t j = 0; j <= C; ++j)
      for (std::int64_t i = 0; i <= C; ++i)
        if (used[static_cast<std::size_t>(j * (C + 1) + i)]) keys.push_back(node_key({o.i + i, o.j + j}));
    return keys;
  }
  for (const auto& p : pieces)
    for (const Node& q : p) keys.push_back(node_key(q));
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

void ChunkedMesh::Impl::sample_nodes(const ChunkKey& key, const std::vector<std::uint64_t>& keys,
                                     std::vector<detail::Vec3>& pos, std::vector<detail::Vec3>& nrm) {
  // From the chunk's block (with its halo) for a fine chunk, from a 3 x 3 read around each
  // node for a coarse one (it has few).
  const bool fine = key.cells == C;
  pos.resize(keys.size());
  nrm.resize(keys.size());
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const Node q = node_of(keys[k]);
    if (fine) {
      const Block& b = chunk_block(chunk_of({key.i0, key.j0}));
      pos[k] = b.position(q);
      nrm[k] = node_normal(b, dom, q);
    } else {
      Block b;
      b.read(*field, dom, {q.i - 1, q.j - 1, 3, 3}, &nodes_read);
      pos[k] = b.position(q);
      nrm[k] = node_normal(b, dom, q);
    }
  }
}

Chunk ChunkedMesh::Impl::assemble(const ChunkKey& key, const std::vector<Piece>& pieces,
                                  const std::vector<std::uint64_t>& keys, const std::vector<detail::Vec3>& pos,
                                  const std::vector<detail::Vec3>& nrm) const {
  const bool fine = key.cells == C;
  std::vector<std::uint32_t> slot;  // fine chunks: node of the square -> position in keys
  if (fine) {
    slot.assign(static_cast<std::size_t>((C + 1) * (C + 1)), 0);
    for (std::size_t k = 0; k < keys.size(); ++k)
      slot[local({key.i0, key.j0}, node_of(keys[k]))] = static_cast<std::uint32_t>(k);
  }
  auto index_of = [&](Node q) {
    if (fine) return static_cast<std::size_t>(slot[local({key.i0, key.j0}, q)]);
    return static_cast<std::size_t>(std::lower_bound(keys.begin(), keys.end(), node_key(q)) - keys.begin());
  };
  // Pieces touching a hole are dropped, and so are the nodes only they used.
  std::vector<std::array<std::size_t, 3>> kept;
  std::vector<std::uint32_t> remap(keys.size(), 0);
  std::vector<char> used(keys.size(), 0);
  for (const auto& p : pieces) {
    const std::array<std::size_t, 3> idx{index_of(p[0]), index_of(p[1]), index_of(p[2])};
    if (!std::isfinite(pos[idx[0]][2]) || !std::isfinite(pos[idx[1]][2]) || !std::isfinite(pos[idx[2]][2])) continue;
    kept.push_back(idx);
    for (const std::size_t k : idx) used[k] = 1;
  }
  Chunk c;
  c.lo = {std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
          std::numeric_limits<float>::infinity()};
  c.hi = {-c.lo[0], -c.lo[1], -c.lo[2]};
  for (std::size_t k = 0; k < keys.size(); ++k) {
    if (!used[k]) continue;
    remap[k] = static_cast<std::uint32_t>(c.nodes.size());
    const Node q = node_of(keys[k]);
    for (std::size_t a = 0; a < 3; ++a) {
      const float x = static_cast<float>(pos[k][a]);
      c.positions.push_back(x);
      c.normals.push_back(static_cast<float>(nrm[k][a]));
      c.lo[a] = std::min(c.lo[a], x);
      c.hi[a] = std::max(c.hi[a], x);
    }
    c.nodes.push_back(static_cast<std::uint64_t>(q.j) * static_cast<std::uint64_t>(dom.ni) +
                      static_cast<std::uint64_t>(q.i));
  }
  for (const auto& idx : kept)
    for (const std::size_t k : idx) c.indices.push_back(remap[k]);
  return c;
}

Chunk ChunkedMesh::Impl::emit(const ChunkKey& key, const std::vector<Tri>& leaves) {
  std::vector<Piece> pieces;
  for (const Tri& t : leaves) {
    std::array<Piece, 5> out;
    const int n = detail::clip_to_domain(t, dom, out);
    for (int k = 0; k < n; ++k) pieces.push_back(out[static_cast<std::size_t>(k)]);
  }
  const std::vector<std::uint64_t> keys = used_nodes(key, pieces);
  std::vector<detail::Vec3> pos, nrm;
  sample_nodes(key, keys, pos, nrm);
  return assemble(key, pieces, keys, pos, nrm);
}

}  // namespace shore::mesh
