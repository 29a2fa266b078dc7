#pragma once
// A soil or a water surface as the renderer draws it: a shore::mesh::ChunkedMesh of its
// field, simplified to a pixel bound for the frame's camera, whose chunks live on the GPU
// one vertex and index buffer each. Only the chunks the mesh reports changed are uploaded;
// chunks outside the view frustum are not drawn.

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>

#include <Eigen/Core>

#include "gl_util.h"
#include "shore/mesh/chunked_mesh.h"

namespace shore::render {

/// The six planes (a, b, c, d: a x + b y + c z + d >= 0 inside) of a view-projection's
/// frustum (Gribb and Hartmann's extraction from the matrix's rows).
struct Frustum {
  std::array<Eigen::Vector4f, 6> planes;
  explicit Frustum(const Eigen::Matrix4f& view_proj);
  /// False only if the box lies wholly outside one plane (conservative: may keep a box
  /// that is outside near a corner).
  [[nodiscard]] bool may_see(const std::array<float, 3>& lo, const std::array<float, 3>& hi) const;
};

/// Per vertex: position, normal, then (deformation, second value, column i, column j).
inline constexpr int kVertexFloats = 10;
inline constexpr std::int64_t kVertexBytes = kVertexFloats * static_cast<std::int64_t>(sizeof(float));

/// Fills the last four floats of a vertex from its field node (i, j) and position z.
using VertexExtras = std::function<void(std::int64_t i, std::int64_t j, float z, float* extra)>;

/// What drawing the chunks did.
struct ChunkDraw {
  std::int64_t triangles = 0;
  int drawn = 0, culled = 0;
};

class SurfaceMesh {
 public:
  /// The field must outlive this; max_error_pixels: the mesh's projected error bound.
  SurfaceMesh(std::unique_ptr<mesh::Field> field, VertexExtras extras, double max_error_pixels);
  /// Brings the mesh up to date for the eye and uploads the chunks that changed (dropping
  /// removed ones); returns the bytes uploaded.
  std::int64_t update(const mesh::Camera& eye);
  /// Draws the chunks the frustum may see, every chunk if it is null (the shadow pass)
  /// (vertex attributes 0 position, 1 normal, 2 extras).
  ChunkDraw draw(const Frustum* frustum) const;

  [[nodiscard]] std::int64_t nodes() const { return field_->ni() * field_->nj(); }
  /// Triangles of the full-resolution mesh of the same field: two per cell.
  [[nodiscard]] std::int64_t full_triangles() const { return 2 * (field_->ni() - 1) * (field_->nj() - 1); }
  /// Bytes of uploading the full-resolution mesh once: every node and every cell's indices.
  [[nodiscard]] std::int64_t full_bytes() const {
    return nodes() * kVertexBytes + full_triangles() * 3 * static_cast<std::int64_t>(sizeof(std::uint32_t));
  }
  [[nodiscard]] std::int64_t triangles() const { return static_cast<std::int64_t>(mesh_.triangle_count()); }
  [[nodiscard]] std::size_t chunk_count() const { return gpu_.size(); }

 private:
  struct GpuChunk {
    gl::VertexArray vao;
    gl::Buffer vbo, ibo;
    GLsizei index_count = 0;
    std::array<float, 3> lo{}, hi{};
  };
  std::int64_t upload(const mesh::ChunkKey& key, const mesh::Chunk& chunk);

  std::unique_ptr<mesh::Field> field_;
  VertexExtras extras_;
  mesh::ChunkedMesh mesh_;
  std::map<mesh::ChunkKey, GpuChunk> gpu_;
  std::vector<float> staging_;
};

}  // namespace shore::render
