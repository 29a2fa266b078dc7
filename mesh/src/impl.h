#pragma once
// Private: the state behind ChunkedMesh. docs/mesh.md describes the method; in short:
//   fine level   (chunk_cells C): per chunk of C x C cells that holds changed nodes, the
//                exact error of every bisection triangle inside it (e), and the saturated
//                error of every vertex (f: the largest error of the vertex and everything
//                below it in the bisection tree, across chunk borders);
//   coarse level (triangles larger than a chunk): errors bounded from per-chunk
//                summaries (a plane and the largest distance from it) and the base plane,
//                saturated the same way, kept only where they are not zero;
//   output       a chunk's triangles are the leaves of the tree inside its square; a chunk
//                is rebuilt when its errors, its nodes or the camera distances it was built
//                with change, and reported changed when its triangles or nodes did.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <unordered_map>
#include <vector>

#include "bintree.h"
#include "block.h"
#include "shore/mesh/chunked_mesh.h"

namespace shore::mesh::detail {

/// An axis-aligned box of positions (empty: lo > hi).
struct Box {
  Vec3 lo{kInf, kInf, kInf}, hi{-kInf, -kInf, -kInf};
  [[nodiscard]] bool empty() const { return lo[0] > hi[0]; }
  void add(const double* p) {
    for (std::size_t k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  }
  void add(const Vec3& p) {
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  }
  void add(const Box& b) {
    if (b.empty()) return;
    add(b.lo);
    add(b.hi);
  }
  friend bool operator==(const Box&, const Box&) = default;
};

/// A chunk's nodes in brief: a plane fitted to them and how far they lie from it.
struct Summary {
  Vec3 a{}, gi{}, gj{};  ///< plane: a + gi (i - ci) + gj (j - cj)
  double ci = 0.0, cj = 0.0;
  double residual = 0.0;  ///< largest distance of a node from the plane
  bool holes = false;
  Box box;
  [[nodiscard]] Vec3 plane(double i, double j) const {
    return {a[0] + gi[0] * (i - ci) + gj[0] * (j - cj), a[1] + gi[1] * (i - ci) + gj[1] * (j - cj),
            a[2] + gi[2] * (i - ci) + gj[2] * (j - cj)};
  }
};

/// A fine chunk's errors, per node of its closed square ((C + 1)^2, row by row).
struct ChunkData {
  std::array<std::vector<float>, 2> e;  ///< the errors of the node's two diamond triangles, those inside
  std::vector<float> f;                 ///< saturated error of the node's vertex
  std::vector<std::uint32_t> queued;    ///< the saturation pass that last queued the node's vertex
  bool detailed = false;                ///< holds nodes off the base (errors computed)
  Summary summary;                      ///< when detailed
  std::uint64_t version = 0;            ///< bumped (once per saturation pass) when f changes
  std::uint32_t bumped = 0;             ///< the pass that last bumped version
};

struct CoarseVertex {
  double e = 0.0;  ///< bound on the error of its diamond's triangles
  double f = 0.0;  ///< saturated
};

/// What a fine chunk's triangles depend on besides its errors.
struct Signature {
  std::uint64_t version = 0;
  int halves = 0;  ///< which of its two halves the coarse tree reaches
  /// Quantised camera distances of the chunk and its 8 neighbours ([dx + 1][dy + 1]): a
  /// vertex's distance is the smallest over the chunks its subtree reaches (reach()).
  std::array<std::array<double, 3>, 3> distance{};
  friend bool operator==(const Signature&, const Signature&) = default;
};

struct Built {
  Signature signature;
  std::vector<Tri> leaves;
};

/// How far (grid cells, each way along i and j) the diamonds of a vertex and of all its
/// descendants reach: 2t for an edge of half-length t, 3t for a centre (its children, edges
/// of the same t, lie t away and reach 2t; an edge's children, centres of t/2, lie t/2 away).
/// Nested: a child's reach lies inside its parent's, so distances taken over it only shrink
/// towards the root, which keeps activity saturated.
inline std::int64_t reach(const VertexClass& c) { return c.kind == Kind::centre ? 3 * c.t : 2 * c.t; }

/// Rounds to float upwards (errors stay bounds).
inline float float_up(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

}  // namespace shore::mesh::detail

namespace shore::mesh {

struct ChunkedMesh::Impl {
  using Node = detail::Node;
  using Tri = detail::Tri;
  using Box = detail::Box;
  using Block = detail::Block;
  using Signature = detail::Signature;

  explicit Impl(MeshSettings settings);

  MeshSettings s;
  std::vector<double> distance_steps;  ///< mantissas 0.5 2^(k / steps), k < steps

  // ---- the field ----
  bool initialised = false;
  detail::Domain dom;
  bool height_field = true;
  std::optional<BasePlane> base;
  std::int64_t C = 64, S = 64;  ///< chunk and root square sides (cells)
  int chunk_log = 6;

  // ---- errors ----
  std::unordered_map<std::uint64_t, detail::ChunkData> data;       ///< by chunk index
  std::unordered_map<std::uint64_t, int> detailed_count;           ///< detailed chunks per square (side > C)
  std::unordered_map<std::uint64_t, Box> square_boxes;             ///< boxes of squares (side > C) holding detail
  std::unordered_map<std::uint64_t, detail::CoarseVertex> coarse;  ///< by node key, where not zero

  // ---- output ----
  std::map<ChunkKey, Chunk> chunks;
  std::map<ChunkKey, detail::Built> built;
  std::size_t triangles = 0;
  MeshUpdate last;

  // ---- one update's scratch ----
  const Field* field = nullptr;
  const Camera* camera = nullptr;
  double pixels_per_radian = 0.0;
  std::int64_t nodes_read = 0;
  std::vector<GridRect> dirty_output;  ///< changed rectangles grown by one node (normals)
  std::set<std::uint64_t> dirty_output_chunks;
  std::map<std::uint64_t, Block> blocks;  ///< chunk blocks read this update (with a 1-node halo)
  std::map<std::uint64_t, detail::Vec3> node_positions;

  /// The chunk's data, or null if it has none; remembers the last two asked for (the
  /// saturation asks for the same few chunks over and over). Pointers into `data` stay
  /// valid: it is never erased from, and allocate() forgets the remembered ones.
  [[nodiscard]] detail::ChunkData* chunk_data(std::uint64_t index) const;
  mutable std::array<std::uint64_t, 2> recent_index{~0ull, ~0ull};
  mutable std::array<detail::ChunkData*, 2> recent_data{nullptr, nullptr};

  // ---- keys ----
  [[nodiscard]] std::uint64_t chunk_index(std::int64_t cx, std::int64_t cy) const {
    return (static_cast<std::uint64_t>(cy) << 32) | static_cast<std::uint64_t>(cx);
  }
  [[nodiscard]] std::uint64_t chunk_of(Node origin) const { return chunk_index(origin.i / C, origin.j / C); }
  [[nodiscard]] Node chunk_origin(std::uint64_t index) const {
    return {static_cast<std::int64_t>(index & 0xffffffffu) * C, static_cast<std::int64_t>(index >> 32) * C};
  }
  [[nodiscard]] std::uint64_t square_key(Node origin, std::int64_t side) const;
  [[nodiscard]] std::uint64_t node_key(Node n) const {
    return static_cast<std::uint64_t>(n.j) * static_cast<std::uint64_t>(S + 1) + static_cast<std::uint64_t>(n.i);
  }
  [[nodiscard]] Node node_of(std::uint64_t key) const {
    return {static_cast<std::int64_t>(key % static_cast<std::uint64_t>(S + 1)),
            static_cast<std::int64_t>(key / static_cast<std::uint64_t>(S + 1))};
  }
  [[nodiscard]] std::size_t local(Node origin, Node n) const {
    return static_cast<std::size_t>((n.j - origin.j) * (C + 1) + (n.i - origin.i));
  }
  [[nodiscard]] bool is_coarse(Node v) const { return detail::classify(v, S).t >= C; }

  // ---- update steps (chunked_mesh.cpp) ----
  void initialise(const Field& f);
  void apply_changes(const std::vector<GridRect>& rects, std::map<std::uint64_t, GridRect>& error_dirty);
  void allocate(std::uint64_t index);
  const Block& chunk_block(std::uint64_t index);
  [[nodiscard]] detail::Vec3 node_position(Node n);

  // ---- fine errors (fine_errors.cpp) ----
  /// Vertices (node keys) by rank whose saturated error must be brought up to date.
  using RankQueue = std::vector<std::vector<std::uint64_t>>;
  std::uint32_t pass = 0;  ///< saturation passes so far (ChunkData::queued)
  /// Queues a fine vertex once per pass (the order within a rank does not matter: a vertex
  /// reads only lower ranks).
  void enqueue(RankQueue& queue, Node v);
  /// The errors of the chunk's triangles that meet the changed nodes; the vertices whose
  /// error changed go into seeds.
  void compute_errors(std::uint64_t index, const GridRect& changed, RankQueue& seeds);
  void summarise(std::uint64_t index);
  /// Saturates the queued fine vertices and, rank by rank, the parents of those that
  /// changed; returns the chunks whose centre changed (their parents are coarse).
  std::vector<std::uint64_t> saturate_fine(RankQueue& queue);
  [[nodiscard]] double fine_f(Node n, std::uint64_t hint) const;

  // ---- coarse errors (coarse_errors.cpp) ----
  void update_coarse(const std::vector<std::uint64_t>& error_dirty, const std::vector<std::uint64_t>& centres);
  [[nodiscard]] double coarse_error(const Tri& t);
  [[nodiscard]] double bound_over(const std::array<Node, 3>& piece, const detail::Interpolant& l, Node origin,
                                  std::int64_t side);
  [[nodiscard]] double coarse_f(Node v) const;
  [[nodiscard]] double vertex_f(Node v) const;  ///< coarse or fine, wherever v lives
  void update_square_boxes(const std::vector<std::uint64_t>& error_dirty);
  [[nodiscard]] Box square_box(Node origin, std::int64_t side) const;
  [[nodiscard]] Box base_box(Node origin, std::int64_t side) const;

  // ---- output (emit.cpp) ----
  [[nodiscard]] double quantised_distance(const Box& b) const;
  [[nodiscard]] double square_distance(Node origin, std::int64_t side) const;
  [[nodiscard]] bool active(double f, double distance) const;
  [[nodiscard]] double coarse_vertex_distance(Node v) const;
  void rebuild_output(MeshUpdate& u);
  void collect(const Tri& t, std::map<std::uint64_t, int>& reached,
               std::map<ChunkKey, std::vector<Tri>>& coarse_leaves);
  void fine_leaves(std::uint64_t index, const detail::Signature& sig, std::vector<Tri>& out) const;
  [[nodiscard]] bool output_dirty(const ChunkKey& key) const;
  Chunk emit(const ChunkKey& key, const std::vector<Tri>& leaves);
  using Piece = std::array<Node, 3>;  ///< a leaf triangle clipped to the domain
  [[nodiscard]] std::vector<std::uint64_t> used_nodes(const ChunkKey& key, const std::vector<Piece>& pieces) const;
  void sample_nodes(const ChunkKey& key, const std::vector<std::uint64_t>& keys, std::vector<detail::Vec3>& pos,
                    std::vector<detail::Vec3>& nrm);
  [[nodiscard]] Chunk assemble(const ChunkKey& key, const std::vector<Piece>& pieces,
                               const std::vector<std::uint64_t>& keys, const std::vector<detail::Vec3>& pos,
                               const std::vector<detail::Vec3>& nrm) const;
};

}  // namespace shore::mesh
