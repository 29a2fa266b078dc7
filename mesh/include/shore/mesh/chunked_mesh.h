#pragma once
// A triangle mesh of a Field (shore/mesh/field.h) simplified within an error bound, kept in
// chunks that are rebuilt only when they change: plain vertex, normal and index arrays for
// any engine or renderer. docs/mesh.md explains the method (right-triangle bisection with
// saturated errors: crack-free without stitching).
//
//   shore::terrain::TerrainField ground(soil, region);   // or shore::water::SurfaceField
//   shore::mesh::ChunkedMesh mesh;                        // MeshSettings: the bounds, chunk size
//   shore::mesh::Camera eye{.position = {1, -2, 2}};     // 60 deg, 1080 lines
//   const shore::mesh::MeshUpdate& u = mesh.update(ground, &eye);  // every frame
//   for (const ChunkKey& k : u.changed) upload(mesh.chunks().at(k));
//   for (const ChunkKey& k : u.removed) drop(k);
//
// The bound. Every node's position lies within the bound of the mesh point with the same
// grid coordinates (i, j): vertically for a height field, in 3-D otherwise. Without a
// camera the bound is max_error metres. With one, it is max_error_pixels projected: the
// error, seen from the eye, subtends at most max_error_pixels / pixels_per_radian radians
// (a pixel's angle at the image centre; the camera has no direction, so this holds for any).
//
// The mesh. It covers the grid (holes aside: the cells touching a missing node are left
// out); every edge is shared by two triangles except along the grid's border and holes,
// with opposite directions (consistent winding: counter-clockwise in (i, j), seen from +z
// for ground); no vertex lies inside another triangle's edge (no T-junctions), across
// chunks and across changes of detail. Vertices are grid nodes at their exact positions;
// normals are the full-resolution surface's at the node.
//
// One mesh follows one field: the first update builds it, later ones rebuild what the
// field's changes or the camera's move made different. The result equals a build from
// scratch with the same field and camera, bit for bit.

#include <array>
#include <compare>
#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include "shore/core/vec3.h"
#include "shore/mesh/field.h"

namespace shore::mesh {

struct MeshSettings {
  /// m, without a camera: the largest distance from a node to the mesh. 0 is lossless (only
  /// parts that are planar to the last bit are simplified), > 0 simplifies. Finite, >= 0.
  double max_error = 0.001;
  /// pixels, with a camera: the largest projected error. Finite, > 0.
  double max_error_pixels = 1.0;
  /// Grid cells along a chunk's side: a power of two in [4, 1024]. Far from the camera and
  /// over flat ground, chunks of 2, 4, ... times this size hold the few large triangles.
  int chunk_cells = 64;
  /// With a camera, each chunk's distance is rounded down to one of this many steps per
  /// doubling, so its detail changes in steps as the camera moves (a chunk is rebuilt when
  /// its step changes), at the price of a mesh up to 2^(1/steps) times finer than needed.
  /// In [1, 64].
  int distance_steps_per_octave = 4;

  /// Throws shore::InvalidSetting naming the field, the value and the allowed range.
  void validate() const;
};

/// An eye for the pixel bound: where it is and how many pixels an angle covers.
struct Camera {
  Vec3 position;               ///< m, world position of the eye, finite
  double fov_y_deg = 60.0;     ///< vertical field of view, degrees, in (0, 180)
  int viewport_height = 1080;  ///< pixels, >= 1

  /// Throws shore::InvalidSetting naming the field, the value and the allowed range.
  void validate() const;
  /// Pixels per radian at the image centre: viewport_height / (2 tan(fov_y / 2)).
  [[nodiscard]] double pixels_per_radian() const;
};

/// A chunk: the square of grid cells [i0, i0 + cells] x [j0, j0 + cells]. Chunks of
/// chunk_cells tile the grid; larger ones (2, 4, ... times) hold the triangles that span
/// several. Ordered by (cells, j0, i0).
struct ChunkKey {
  std::int64_t cells = 0;
  std::int64_t j0 = 0, i0 = 0;
  friend auto operator<=>(const ChunkKey&, const ChunkKey&) = default;
};

struct Chunk {
  std::vector<float> positions;        ///< m, world x, y, z per vertex
  std::vector<float> normals;          ///< unit x, y, z per vertex (the surface's at the node)
  std::vector<std::uint32_t> indices;  ///< 3 per triangle, into the vertices
  /// Per vertex, its grid node j ni + i: a node shared by several chunks is one point, so a
  /// renderer or a check can weld them.
  std::vector<std::uint64_t> nodes;
  std::array<float, 3> lo{}, hi{};  ///< bounds of the positions (culling)
  [[nodiscard]] std::size_t triangle_count() const { return indices.size() / 3; }
};

struct MeshUpdate {
  std::vector<ChunkKey> changed;  ///< new or rebuilt chunks, in key order: upload these
  std::vector<ChunkKey> removed;  ///< chunks that are gone, in key order: drop these
  std::size_t triangles = 0;      ///< in the whole mesh after the update
  std::size_t chunks = 0;         ///< chunks in the whole mesh after the update
  std::int64_t nodes_read = 0;    ///< field nodes read by this update (its cost)
};

class ChunkedMesh {
 public:
  explicit ChunkedMesh(MeshSettings settings = {});  ///< validates
  ~ChunkedMesh();
  ChunkedMesh(ChunkedMesh&&) noexcept;
  ChunkedMesh& operator=(ChunkedMesh&&) noexcept;

  /// Takes the field's changes and brings the mesh up to date for the camera (null: the
  /// metres bound). The result stays valid until the next update. Throws InvalidSetting if
  /// the camera is invalid or the field's size differs from the first update's (the mesh is
  /// then unchanged); an exception from the field propagates and leaves the mesh to be
  /// rebuilt (a new ChunkedMesh). One thread at a time.
  const MeshUpdate& update(Field& field, const Camera* camera = nullptr);

  [[nodiscard]] const std::map<ChunkKey, Chunk>& chunks() const noexcept;
  [[nodiscard]] std::size_t triangle_count() const noexcept;
  [[nodiscard]] const MeshSettings& settings() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// All chunks of a mesh in one, shared nodes welded (vertices in node order).
struct TriangleMesh {
  std::vector<double> positions;       ///< m, x, y, z per vertex
  std::vector<float> normals;          ///< unit x, y, z per vertex
  std::vector<std::uint32_t> indices;  ///< 3 per triangle
  std::vector<std::uint64_t> nodes;    ///< grid node j ni + i per vertex, ascending
  [[nodiscard]] std::size_t triangle_count() const { return indices.size() / 3; }
};

/// The welded mesh; positions are read again from the field in double precision (the
/// chunks hold floats for the GPU), so the field must be the one the mesh follows.
TriangleMesh merge(const ChunkedMesh& mesh, const Field& field);

}  // namespace shore::mesh
