#pragma once
// What the renderer draws, as GPU objects: one simplified chunked mesh per soil and per
// water surface (surface_mesh.h: only changed chunks are uploaded, chunks outside the view
// are not drawn), and one mesh per collision shape (drawn at each body's pose).

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "gl_util.h"
#include "shore/render/renderer.h"
#include "shore/render/shape_mesh.h"
#include "shore/scenes/contents.h"
#include "soil_map.h"
#include "surface_mesh.h"

namespace shore::render {

struct SoilLayer {
  scenes::SoilContents contents;
  shore::GridRect region;  // the drawn columns
  std::unique_ptr<SurfaceMesh> mesh;
  SoilMapTexture map;                                         // the material map, if the soil is painted
  double max_delta = 0, max_sinkage = 0, zmin = 0, zmax = 0;  // over the vertices uploaded so far
};

struct WaterLayer {
  scenes::WaterContents contents;
  std::unique_ptr<SurfaceMesh> mesh;
  double scale_height = 0, scale_velocity = 0, steepest = 0;  // now, over the nodes
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
  /// Brings every surface's mesh up to date for the eye (a view `viewport_height` pixels
  /// high) and uploads the chunks that changed.
  void update(const Eigen::Vector3d& eye, double fov_y_deg, int viewport_height, const RenderSettings& settings,
              FrameStats& stats);
  /// Colour scales and per-frame state before drawing.
  void prepare(const RenderSettings& settings, FrameStats& stats);
  /// Each returns what it drew; a null frustum draws every chunk (the shadow pass).
  ChunkDraw draw_soils(GLuint program, const Frustum* frustum, bool depth_only, const RenderSettings& settings = {});
  std::int64_t draw_bodies(GLuint program, bool depth_only);
  ChunkDraw draw_waters(GLuint program, const Frustum* frustum, const RenderSettings& settings);
  [[nodiscard]] scenes::Bounds bounds() const { return contents_.bounds; }
  [[nodiscard]] double mid_height() const;
  [[nodiscard]] std::optional<Eigen::Vector3d> pick(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) const;
  ~Layers();
  int bodies_drawn = 0;  ///< by the last draw_bodies

 private:
  GpuMesh& mesh_of(const btCollisionShape* shape);
  /// A raycast wheel's cylinder for drawing (one per radius and width, kept).
  const btCollisionShape* wheel_shape(double radius, double width);
  void build_surfaces();
  void add_soil(const scenes::SoilContents& s);
  void add_water(const scenes::WaterContents& w);
  void measure_water(WaterLayer& layer) const;
  [[nodiscard]] bool is_soil_tile(const btCollisionObject* object) const;

  scenes::SceneContents contents_;
  std::vector<std::unique_ptr<SoilLayer>> soils_;
  std::vector<std::unique_ptr<WaterLayer>> waters_;
  std::unordered_map<const btCollisionShape*, GpuMesh> meshes_;  // drawing only: never hashed or summed
  std::map<std::pair<double, double>, std::unique_ptr<btCollisionShape>> wheel_shapes_;
  RenderSettings settings_;
  double mesh_error_pixels_ = 1.0;  // the bound the meshes are made with
  double ground_scale_ = 0, water_scale_ = 0, wave_gain_ = 1;
};

}  // namespace shore::render
