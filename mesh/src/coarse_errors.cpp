// Coarse level: triangles larger than a chunk. Their errors are bounded from the chunks'
// summaries (a fitted plane plus the largest distance from it) and the base plane, found by
// descending the quadtree of squares only where there is detail; then saturated upwards like
// the fine level. Kept sparse: a vertex over untouched base ground has error 0 and no entry.
#include <algorithm>

#include "impl.h"

namespace shore::mesh {

using detail::Tri;

std::uint64_t ChunkedMesh::Impl::square_key(Node origin, std::int64_t side) const {
  int lg = 0;
  while ((std::int64_t{1} << lg) < side) ++lg;
  return (static_cast<std::uint64_t>(lg) << 58) | (static_cast<std::uint64_t>(origin.j / side) << 29) |
         static_cast<std::uint64_t>(origin.i / side);
}

double ChunkedMesh::Impl::coarse_error(const Tri& t) {
  std::array<std::array<Node, 3>, 5> pieces;
  const int n = detail::clip_to_domain(t, dom, pieces);
  const std::int64_t side = detail::square_side(t);
  const Node origin = detail::square_origin(t, side);
  double worst = 0.0;
  for (int k = 0; k < n; ++k) {
    const std::array<Node, 3>& q = pieces[static_cast<std::size_t>(k)];
    std::array<detail::Vec3, 3> p;
    for (std::size_t c = 0; c < 3; ++c) {
      p[c] = node_position(q[c]);
      if (!std::isfinite(p[c][2])) return detail::kInf;
    }
    worst = std::max(worst, bound_over(q, detail::Interpolant(q, p), origin, side));
  }
  return worst;
}

double ChunkedMesh::Impl::bound_over(const std::array<Node, 3>& piece, const detail::Interpolant& l, Node origin,
                                     std::int64_t side) {
  const std::int64_t bi1 = std::min(origin.i + side, dom.ni - 1), bj1 = std::min(origin.j + side, dom.nj - 1);
  if (std::max({piece[0].i, piece[1].i, piece[2].i}) < origin.i ||
      std::min({piece[0].i, piece[1].i, piece[2].i}) > bi1 ||
      std::max({piece[0].j, piece[1].j, piece[2].j}) < origin.j || std::min({piece[0].j, piece[1].j, piece[2].j}) > bj1)
    return 0.0;  // clear of the square
  const double i1 = static_cast<double>(bi1), j1 = static_cast<double>(bj1);
  std::array<std::array<double, 2>, 9> poly;
  const int n = detail::clip_polygon(piece, static_cast<double>(origin.i), static_cast<double>(origin.j), i1, j1, poly);
  if (n == 0) return 0.0;
  // The distance between two affine maps is convex: its largest value over the polygon is
  // at a corner.
  auto worst_from = [&](auto&& plane) {
    double w = 0.0;
    for (int k = 0; k < n; ++k) {
      const auto& x = poly[static_cast<std::size_t>(k)];
      const detail::Vec3 a = plane(x[0], x[1]);
      w = std::max(w, detail::distance(a, l.at(x[0], x[1]), height_field));
    }
    return w;
  };
  auto from_base = [&] { return base ? worst_from([&](double i, double j) { return base->at(i, j); }) : 0.0; };
  if (side == C) {
    const auto it = data.find(chunk_of(origin));
    if (it == data.end() || !it->second.detailed) return from_base();
    const detail::Summary& sm = it->second.summary;
    if (sm.holes) return detail::kInf;
    return sm.residual + worst_from([&](double i, double j) { return sm.plane(i, j); });
  }
  if (!detailed_count.count(square_key(origin, side))) return from_base();
  const std::int64_t h = side / 2;
  double w = 0.0;
  for (const Node o :
       {origin, Node{origin.i + h, origin.j}, Node{origin.i, origin.j + h}, Node{origin.i + h, origin.j + h}})
    w = std::max(w, bound_over(piece, l, o, h));
  return w;
}

double ChunkedMesh::Impl::coarse_f(Node v) const {
  const auto it = coarse.find(node_key(v));
  return it == coarse.end() ? 0.0 : it->second.f;
}

double ChunkedMesh::Impl::vertex_f(Node v) const {
  if (is_coarse(v)) return coarse_f(v);
  const std::int64_t cx = std::min(v.i / C, S / C - 1), cy = std::min(v.j / C, S / C - 1);
  return fine_f(v, chunk_index(cx, cy));
}

namespace {

/// Multiples m of `step` offset by `offset` (m = offset + k step) within [lo, hi].
template <class Fn>
void each_multiple(std::int64_t lo, std::int64_t hi, std::int64_t offset, std::int64_t step, Fn&& fn) {
  std::int64_t k = (lo - offset) >= 0 ? (lo - offset + step - 1) / step : -((offset - lo) / step);
  for (std::int64_t m = offset + k * step; m <= hi; m += step)
    if (m >= lo) fn(m);
}

}  // namespace

void ChunkedMesh::Impl::update_coarse(const std::vector<std::uint64_t>& error_dirty,
                                      const std::vector<std::uint64_t>& centres) {
  // Coarse vertices whose diamond may reach a changed chunk: each class within its reach.
  std::set<std::uint64_t> candidates;
  for (const std::uint64_t index : error_dirty) {
    const Node o = chunk_origin(index);
    for (std::int64_t t = C; t < S; t *= 2) {
      const std::int64_t i_lo = std::max<std::int64_t>(0, o.i - t), i_hi = std::min(S, o.i + C + t);
      const std::int64_t j_lo = std::max<std::int64_t>(0, o.j - t), j_hi = std::min(S, o.j + C + t);
      auto add = [&](std::int64_t i, std::int64_t j) {
        if (is_coarse({i, j})) candidates.insert(node_key({i, j}));
      };
      each_multiple(i_lo, i_hi, t, 2 * t, [&](std::int64_t i) {
        each_multiple(j_lo, j_hi, t, 2 * t, [&](std::int64_t j) { add(i, j); });  // centres
        each_multiple(j_lo, j_hi, 0, 2 * t, [&](std::int64_t j) { add(i, j); });  // edges along i
      });
      each_multiple(i_lo, i_hi, 0, 2 * t, [&](std::int64_t i) {
        each_multiple(j_lo, j_hi, t, 2 * t, [&](std::int64_t j) { add(i, j); });  // edges along j
      });
    }
  }
  std::vector<std::vector<std::uint64_t>> queue(64);
  auto push_parents = [&](Node v) {
    std::array<Node, 2> ps;
    const int k = detail::parents(v, S, ps);
    for (int q = 0; q < k; ++q)
      queue[static_cast<std::size_t>(detail::classify(ps[static_cast<std::size_t>(q)], S).rank())].push_back(
          node_key(ps[static_cast<std::size_t>(q)]));
  };
  for (const std::uint64_t key : candidates) {
    const Node v = node_of(key);
    std::array<Tri, 2> tris;
    const int k = detail::diamond(v, S, tris);
    double e = 0.0;
    for (int q = 0; q < k; ++q) e = std::max(e, coarse_error(tris[static_cast<std::size_t>(q)]));
    const auto it = coarse.find(key);
    if (it == coarse.end() ? e == 0.0 : it->second.e == e) continue;
    coarse[key].e = e;
    queue[static_cast<std::size_t>(detail::classify(v, S).rank())].push_back(key);
  }
  for (const std::uint64_t index : centres) {
    const Node o = chunk_origin(index);
    push_parents({o.i + C / 2, o.j + C / 2});
  }
  for (std::vector<std::uint64_t>& rank : queue) {
    std::sort(rank.begin(), rank.end());
    rank.erase(std::unique(rank.begin(), rank.end()), rank.end());
    for (const std::uint64_t key : rank) {
      const Node v = node_of(key);
      const auto it = coarse.find(key);
      double f = it == coarse.end() ? 0.0 : it->second.e;
      std::array<Node, 4> kids;
      const int k = detail::children(v, S, kids);
      for (int q = 0; q < k; ++q) f = std::max(f, vertex_f(kids[static_cast<std::size_t>(q)]));
      const double before = it == coarse.end() ? 0.0 : it->second.f;
      if (f != before) {
        coarse[key].f = f;
        push_parents(v);
      }
      const auto now = coarse.find(key);
      if (now != coarse.end() && now->second.e == 0.0 && now->second.f == 0.0) coarse.erase(now);
    }
  }
}

detail::Box ChunkedMesh::Impl::base_box(Node origin, std::int64_t side) const {
  Box b;
  const std::int64_t i1 = std::min(origin.i + side, dom.ni - 1), j1 = std::min(origin.j + side, dom.nj - 1);
  if (!base || origin.i > i1 || origin.j > j1) return b;
  for (const std::int64_t i : {origin.i, i1})
    for (const std::int64_t j : {origin.j, j1}) b.add(base->at(static_cast<double>(i), static_cast<double>(j)));
  return b;
}

detail::Box ChunkedMesh::Impl::square_box(Node origin, std::int64_t side) const {
  if (side == C) {
    const auto it = data.find(chunk_of(origin));
    return it != data.end() && it->second.detailed ? it->second.summary.box : base_box(origin, side);
  }
  const auto it = square_boxes.find(square_key(origin, side));
  return it != square_boxes.end() ? it->second : base_box(origin, side);
}

void ChunkedMesh::Impl::update_square_boxes(const std::vector<std::uint64_t>& error_dirty) {
  std::vector<Node> squares;
  for (const std::uint64_t index : error_dirty) squares.push_back(chunk_origin(index));
  for (std::int64_t side = 2 * C; side <= S; side *= 2) {
    std::set<std::pair<std::int64_t, std::int64_t>> up;
    for (const Node n : squares) up.insert({n.j / side * side, n.i / side * side});
    squares.clear();
    for (const auto& [j, i] : up) {
      const Node o{i, j};
      const std::int64_t h = side / 2;
      Box b;
      for (const Node c : {o, Node{o.i + h, o.j}, Node{o.i, o.j + h}, Node{o.i + h, o.j + h}}) b.add(square_box(c, h));
      square_boxes[square_key(o, side)] = b;
      squares.push_back(o);
    }
  }
}

}  // namespace shore::mesh
