#pragma once
// What the renderer draws, as GPU objects: one height-field layer per soil and per water
// surface (a texture of heights and a second value, drawn in tiles of a grid mesh), and
// one mesh per collision shape (drawn at each body's pose).

#include <cstdint>
#include <memory>
#include <optional>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "gl_util.h"
#include "shore/render/renderer.h"
#include "shore/render/shape_mesh.h"
#include "shore/scenes/contents.h"

namespace shore::render {

/// The index buffer of one tile of `cells` x `cells` cells over (cells + 1)^2 vertices
/// (a, b) with a, b in [0, cells]. The one place a simplified (level-of-detail) mesh of a
/// tile would come in.
struct TileMesh {
  std::vector<std::int32_t> vertices;  ///< a, b per vertex
  std::vector<std::uint32_t> indices;
};
TileMesh tile_mesh(int cells);

/// A tile mesh on the GPU.
struct GpuTile {
  gl::VertexArray vao;
  gl::Buffer vbo, ibo;
  GLsizei index_count = 0;
  int cells = 0;
};

/// A regular grid of values on the GPU: texel (i, j) = world (x0 + i cell, y0 + j cell).
struct FieldTexture {
  int nx = 0, ny = 0;
  double x0 = 0, y0 = 0, cell = 0;
  gl::Texture field;  // RG32F: height, second value
  gl::Texture base;   // R32F: reference height
  void create(int columns_x, int columns_y, const std::vector<float>& base_heights);
  /// Uploads a rectangle of texels (rg pairs, row-major); returns bytes uploaded.
  std::int64_t upload(int i0, int j0, int w, int h, const std::vector<float>& rg);
};

struct SoilLayer {
  scenes::SoilContents contents;
  std::int64_t i0 = 0, j0 = 0;  // global index of texel (0, 0)
  FieldTexture tex;
  std::vector<terrain::ColumnRect> pending;  // pushed since the last sync
  bool whole = true;                         // upload everything at the next sync
  double max_delta = 0, max_sinkage = 0, zmin = 0, zmax = 0;
};

struct WaterLayer {
  scenes::WaterContents contents;
  FieldTexture tex;
  double scale_height = 0, scale_velocity = 0, steepest = 0;
};

struct GpuMesh {
  gl::VertexArray vao;
  gl::Buffer vbo, ibo;
  GLsizei index_count = 0;
};

class Layers {
 public:
  void set(const scenes::SceneContents& contents);
  void clear();
  void sync(FrameStats& stats);
  /// Colour scales and per-frame state before drawing.
  void prepare(const RenderSettings& settings, FrameStats& stats);
  /// Each returns the triangles drawn.
  std::int64_t draw_soils(GLuint program, bool depth_only, const RenderSettings& settings = {});
  std::int64_t draw_bodies(GLuint program, bool depth_only);
  std::int64_t draw_waters(GLuint program, const RenderSettings& settings);
  [[nodiscard]] scenes::Bounds bounds() const { return contents_.bounds; }
  [[nodiscard]] double mid_height() const;
  [[nodiscard]] std::optional<Eigen::Vector3d> pick(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) const;
  ~Layers();
  int bodies_drawn = 0;  ///< by the last draw_bodies

 private:
  GpuTile& tile(int cells);
  GpuMesh& mesh_of(const btCollisionShape* shape);
  std::int64_t draw_field(GLuint program, const FieldTexture& tex, int tile_cells);
  void upload_soil(SoilLayer& layer, const terrain::ColumnRect& rect, FrameStats& stats);
  void sync_water(WaterLayer& layer, FrameStats& stats);
  [[nodiscard]] bool is_soil_tile(const btCollisionObject* object) const;

  scenes::SceneContents contents_;
  std::vector<std::unique_ptr<SoilLayer>> soils_;
  std::vector<std::unique_ptr<WaterLayer>> waters_;
  std::unordered_map<int, GpuTile> tiles_;
  std::unordered_map<const btCollisionShape*, GpuMesh> meshes_;  // drawing only: never hashed or summed
  RenderSettings settings_;
  double ground_scale_ = 0, water_scale_ = 0, wave_gain_ = 1;
};

}  // namespace shore::render
