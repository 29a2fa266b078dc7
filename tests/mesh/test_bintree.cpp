// The bisection tree's closed forms (bintree.h: a vertex's diamond, children and parents
// from its coordinates) against the tree built by splitting triangles from the root.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <vector>

#include "bintree.h"

using namespace shore::mesh::detail;

namespace {

std::uint64_t key(Node n) { return static_cast<std::uint64_t>(n.j) * 1000 + static_cast<std::uint64_t>(n.i); }

}  // namespace

TEST(Bintree, ClosedFormsMatchTheTreeBuiltBySplitting) {
  for (const std::int64_t root : {2, 4, 16, 64}) {
    // Every triangle of the full tree, by splitting from the root's two halves.
    std::array<Tri, 2> start;
    ASSERT_EQ(diamond({root / 2, root / 2}, root, start), 2);
    EXPECT_EQ(cross(start[0].p0, start[0].apex, start[0].p2), root * root);
    std::vector<Tri> all, stack(start.begin(), start.end());
    std::map<std::uint64_t, std::vector<Tri>> by_vertex;  // triangles each vertex splits
    std::map<std::uint64_t, std::set<std::uint64_t>> kids;
    while (!stack.empty()) {
      const Tri t = stack.back();
      stack.pop_back();
      all.push_back(t);
      EXPECT_GT(cross(t.p0, t.apex, t.p2), 0) << "counter-clockwise";
      EXPECT_EQ((t.apex.i - t.p0.i) * (t.p2.i - t.apex.i) + (t.apex.j - t.p0.j) * (t.p2.j - t.apex.j), 0)
          << "right angle at the apex";
      if (!has_split(t)) continue;
      const Node m = split_vertex(t);
      by_vertex[key(m)].push_back(t);
      for (const Tri& c : {first_child(t, m), second_child(t, m)}) {
        if (has_split(c)) kids[key(m)].insert(key(split_vertex(c)));
        stack.push_back(c);
      }
    }
    // Every node but the four corners splits exactly one diamond, the one diamond() gives.
    int vertices = 0;
    for (std::int64_t j = 0; j <= root; ++j)
      for (std::int64_t i = 0; i <= root; ++i) {
        const Node n{i, j};
        const bool corner = (i == 0 || i == root) && (j == 0 || j == root);
        const auto it = by_vertex.find(key(n));
        if (corner) {
          EXPECT_EQ(it, by_vertex.end());
          EXPECT_EQ(classify(n, root).kind, Kind::corner);
          continue;
        }
        ASSERT_NE(it, by_vertex.end()) << i << "," << j;
        ++vertices;
        std::array<Tri, 2> d;
        const int k = diamond(n, root, d);
        ASSERT_EQ(static_cast<std::size_t>(k), it->second.size()) << i << "," << j;
        for (int q = 0; q < k; ++q) {
          bool found = false;
          for (const Tri& t : it->second) found = found || t == d[static_cast<std::size_t>(q)];
          EXPECT_TRUE(found) << "diamond of " << i << "," << j;
          if (k == 2) {
            EXPECT_EQ(diamond_side(d[static_cast<std::size_t>(q)], n), q);
          }
        }
        std::array<Node, 4> c;
        const int nc = children(n, root, c);
        std::set<std::uint64_t> closed;
        for (int q = 0; q < nc; ++q) closed.insert(key(c[static_cast<std::size_t>(q)]));
        EXPECT_EQ(closed, kids[key(n)]) << "children of " << i << "," << j;
        for (int q = 0; q < nc; ++q) {  // and each child names n among its parents, at a lower rank
          std::array<Node, 2> p;
          const int np = parents(c[static_cast<std::size_t>(q)], root, p);
          bool back = false;
          for (int r = 0; r < np; ++r) back = back || p[static_cast<std::size_t>(r)] == n;
          EXPECT_TRUE(back);
          EXPECT_LT(classify(c[static_cast<std::size_t>(q)], root).rank(), classify(n, root).rank());
        }
      }
    EXPECT_EQ(vertices, (root + 1) * (root + 1) - 4);
  }
}
