#include "layers.h"

#include <algorithm>
#include <cmath>

#include <btBulletDynamicsCommon.h>

#include "shore/scenes/world.h"
#include "shore/terrain/mesh_field.h"
#include "shore/water/mesh_field.h"

namespace shore::render {
namespace {

// Columns along a side of a drawn soil region: the meshes read only what changed over flat
// ground, but a base that is not flat is read whole on the first frame.
constexpr std::int64_t kMaxColumns = 1 << 16;

// Texture units: 2 colour maps and 3 shadow map (renderer.cpp), 4 a soil's material map.
constexpr int kMapTextureUnit = 4;

/// k: the object's index in the world's collision objects. A multibody's part is coloured by
/// its link instead (base first): the terrain coupling adds and removes its tiles during a
/// run and a checkpoint restore re-adds them, and Bullet's remove moves the last object into
/// the hole, so the parts' indices change while the same rover is drawn (a replay drew its
/// wheels in other colours than the run).
Eigen::Vector3d body_colour(const btCollisionObject& o, int k) {
  if (o.isStaticObject()) return {0.62, 0.60, 0.56};
  if (o.isKinematicObject()) return {0.85, 0.60, 0.35};
  static const Eigen::Vector3d palette[] = {{0.60, 0.66, 0.78}, {0.78, 0.42, 0.38}, {0.45, 0.65, 0.48},
                                            {0.82, 0.74, 0.42}, {0.62, 0.50, 0.74}, {0.40, 0.62, 0.70}};
  if (const btMultiBodyLinkCollider* part = btMultiBodyLinkCollider::upcast(&o)) k = part->m_link + 1;
  return palette[k % 6];
}

void uniform3(GLuint p, const char* n, const Eigen::Vector3d& v) {
  glUniform3f(glGetUniformLocation(p, n), float(v.x()), float(v.y()), float(v.z()));
}

}  // namespace

Layers::~Layers() { clear(); }

void Layers::add_soil(const scenes::SoilContents& s) {
  const terrain::Terrain& soil = *s.soil;
  const double cell = soil.settings().cell, ox = soil.settings().origin_x, oy = soil.settings().origin_y;
  const scenes::Bounds& b = contents_.bounds;
  const double x0 = std::max(s.region.x0, b.x0), x1 = std::min(s.region.x1, b.x1);
  const double y0 = std::max(s.region.y0, b.y0), y1 = std::min(s.region.y1, b.y1);
  if (!(x1 > x0 && y1 > y0)) return;
  auto layer = std::make_unique<SoilLayer>();
  layer->contents = s;
  const auto i0 = static_cast<std::int64_t>(std::ceil((x0 - ox) / cell - 1e-9));
  const auto j0 = static_cast<std::int64_t>(std::ceil((y0 - oy) / cell - 1e-9));
  const auto i1 = static_cast<std::int64_t>(std::floor((x1 - ox) / cell + 1e-9));
  const auto j1 = static_cast<std::int64_t>(std::floor((y1 - oy) / cell + 1e-9));
  layer->region = {i0, j0, static_cast<int>(std::clamp<std::int64_t>(i1 - i0 + 1, 2, kMaxColumns)),
                   static_cast<int>(std::clamp<std::int64_t>(j1 - j0 + 1, 2, kMaxColumns))};
  layer->zmin = layer->zmax = soil.base_height(i0, j0);
  SoilLayer* raw = layer.get();
  // Per vertex: height - untouched ground, plastic sinkage, the global column.
  auto extras = [raw](std::int64_t i, std::int64_t j, float z, float* out) {
    const terrain::Terrain& t = *raw->contents.soil;
    const std::int64_t ci = raw->region.i0 + i, cj = raw->region.j0 + j;
    const double delta = double(z) - t.base_height(ci, cj), sink = t.sinkage(ci, cj);
    out[0] = float(delta);
    out[1] = float(sink);
    out[2] = float(ci);
    out[3] = float(cj);
    raw->max_delta = std::max(raw->max_delta, std::abs(delta));
    raw->max_sinkage = std::max(raw->max_sinkage, std::abs(sink));
    raw->zmin = std::min(raw->zmin, double(z));
    raw->zmax = std::max(raw->zmax, double(z));
  };
  layer->mesh = std::make_unique<SurfaceMesh>(std::make_unique<terrain::TerrainField>(soil, layer->region), extras,
                                              mesh_error_pixels_);
  soils_.push_back(std::move(layer));
}

void Layers::add_water(const scenes::WaterContents& w) {
  auto layer = std::make_unique<WaterLayer>();
  layer->contents = w;
  const water::Surface* surface = w.surface;
  // Per vertex: height - rest level, vertical velocity, the node.
  auto extras = [surface](std::int64_t i, std::int64_t j, float z, float* out) {
    out[0] = float(double(z) - surface->settings().rest_height);
    out[1] = float(surface->vertical_velocity(static_cast<int>(i), static_cast<int>(j)));
    out[2] = float(i);
    out[3] = float(j);
  };
  layer->mesh =
      std::make_unique<SurfaceMesh>(std::make_unique<water::SurfaceField>(*surface), extras, mesh_error_pixels_);
  waters_.push_back(std::move(layer));
}

void Layers::set(const scenes::SceneContents& contents) {
  clear();
  contents_ = contents;
  build_surfaces();
}

void Layers::build_surfaces() {
  soils_.clear();
  waters_.clear();
  for (const scenes::SoilContents& s : contents_.soils) add_soil(s);
  for (const scenes::WaterContents& w : contents_.waters) add_water(w);
}

void Layers::clear() {
  soils_.clear();
  waters_.clear();
  meshes_.clear();
  contents_ = {};
}

void Layers::measure_water(WaterLayer& layer) const {
  const water::Surface& s = *layer.contents.surface;
  const double rest = s.settings().rest_height;
  layer.scale_height = layer.scale_velocity = layer.steepest = 0.0;
  for (int j = 0; j < s.ny(); ++j)
    for (int i = 0; i < s.nx(); ++i) {
      if (s.is_fixed(i, j)) continue;
      const double h = s.height(i, j);
      layer.scale_height = std::max(layer.scale_height, std::abs(h - rest));
      layer.scale_velocity = std::max(layer.scale_velocity, std::abs(s.vertical_velocity(i, j)));
      if (i > 0) layer.steepest = std::max(layer.steepest, std::abs(h - s.height(i - 1, j)) / s.spacing());
      if (j > 0) layer.steepest = std::max(layer.steepest, std::abs(h - s.height(i, j - 1)) / s.spacing());
    }
}

void Layers::update(const Eigen::Vector3d& eye, double fov_y_deg, int viewport_height, const RenderSettings& settings,
                    FrameStats& stats) {
  const double bound = std::max(settings.max_error_pixels, 0.05);
  if (bound != mesh_error_pixels_) {  // a new bound: new meshes (uploaded whole below)
    mesh_error_pixels_ = bound;
    build_surfaces();
  }
  const mesh::Camera camera{
      .position = {eye.x(), eye.y(), eye.z()}, .fov_y_deg = fov_y_deg, .viewport_height = std::max(viewport_height, 1)};
  stats.soil_bytes = stats.water_bytes = stats.whole_soil_bytes = stats.whole_water_bytes = stats.soil_columns = 0;
  stats.full_triangles = stats.surface_chunks = 0;
  for (auto& layer : soils_) {
    stats.soil_bytes += layer->mesh->update(camera);
    layer->map.update(*layer->contents.soil, layer->region);
    stats.soil_columns += layer->mesh->nodes();
    stats.whole_soil_bytes += layer->mesh->full_bytes();
    stats.full_triangles += layer->mesh->full_triangles();
    stats.surface_chunks += static_cast<int>(layer->mesh->chunk_count());
  }
  for (auto& layer : waters_) {
    stats.water_bytes += layer->mesh->update(camera);
    stats.whole_water_bytes += layer->mesh->full_bytes();
    stats.full_triangles += layer->mesh->full_triangles();
    stats.surface_chunks += static_cast<int>(layer->mesh->chunk_count());
    measure_water(*layer);
  }
}

void Layers::prepare(const RenderSettings& settings, FrameStats& stats) {
  settings_ = settings;
  double g = 0.0, w = 0.0, steep = 0.0;
  for (const auto& s : soils_)
    g = std::max(g, settings.ground == GroundColour::sinkage ? s->max_sinkage : s->max_delta);
  for (const auto& s : waters_) {
    w = std::max(w, settings.water == WaterColour::velocity ? s->scale_velocity : s->scale_height);
    steep = std::max(steep, s->steepest);
  }
  ground_scale_ = settings.ground_scale > 0.0 ? settings.ground_scale : (g > 0.0 ? g : 1e-3);
  water_scale_ = settings.water_scale > 0.0 ? settings.water_scale : (w > 0.0 ? w : 1e-3);
  // Small waves are far flatter than the cell: steepen the shading so the steepest slope reads ~0.25.
  wave_gain_ = settings.wave_exaggeration >= 1.0 ? settings.wave_exaggeration
                                                 : (steep > 0.0 ? std::clamp(0.25 / steep, 1.0, 30.0) : 1.0);
  stats.ground_scale = ground_scale_;
  stats.water_scale = water_scale_;
}

namespace {
void add(ChunkDraw& total, const ChunkDraw& d) {
  total.triangles += d.triangles;
  total.drawn += d.drawn;
  total.culled += d.culled;
}
}  // namespace

ChunkDraw Layers::draw_soils(GLuint p, const Frustum* frustum, bool depth_only, const RenderSettings& s) {
  ChunkDraw total;
  for (const auto& layer : soils_) {
    const terrain::TerrainSettings& ts = layer->contents.soil->settings();
    glUniform1f(glGetUniformLocation(p, "uSlopeGain"), 1.0f);
    if (!depth_only) {
      glUniform1i(glGetUniformLocation(p, "uMode"), static_cast<int>(s.ground));
      glUniform1f(glGetUniformLocation(p, "uScale"), float(ground_scale_));
      glUniform2f(glGetUniformLocation(p, "uHeightRange"), float(layer->zmin), float(layer->zmax));
      uniform3(p, "uTint", material_colour(ts.material.name, s));
      layer->map.bind(p, kMapTextureUnit, *layer->contents.soil, s);
      // Storage tile edges sit at multiples of tile_columns of the global column index.
      glUniform1i(glGetUniformLocation(p, "uTileColumns"), s.soil_tile_borders ? ts.tile_columns : 0);
    }
    add(total, layer->mesh->draw(frustum));
  }
  return total;
}

ChunkDraw Layers::draw_waters(GLuint p, const Frustum* frustum, const RenderSettings& s) {
  ChunkDraw total;
  for (const auto& layer : waters_) {
    glUniform1f(glGetUniformLocation(p, "uSlopeGain"), float(wave_gain_));
    glUniform1i(glGetUniformLocation(p, "uMode"), static_cast<int>(s.water));
    glUniform1f(glGetUniformLocation(p, "uScale"), float(water_scale_));
    add(total, layer->mesh->draw(frustum));
  }
  return total;
}

bool Layers::is_soil_tile(const btCollisionObject* o) const {
  for (const auto& s : soils_)
    if (s->contents.coupling != nullptr && s->contents.coupling->tiles().is_tile(o)) return true;
  for (const scenes::SoilContents& s : contents_.soils)  // soils outside the bounds
    if (s.coupling != nullptr && s.coupling->tiles().is_tile(o)) return true;
  return false;
}

GpuMesh& Layers::mesh_of(const btCollisionShape* shape) {
  auto it = meshes_.find(shape);
  if (it != meshes_.end()) return it->second;
  const ShapeMesh m = shape_mesh(*shape);
  std::vector<float> interleaved;
  interleaved.reserve(m.positions.size() * 2);
  for (std::size_t v = 0; v < m.vertex_count(); ++v) {
    interleaved.insert(interleaved.end(), m.positions.begin() + 3 * v, m.positions.begin() + 3 * v + 3);
    interleaved.insert(interleaved.end(), m.normals.begin() + 3 * v, m.normals.begin() + 3 * v + 3);
  }
  GpuMesh g;
  g.vao = gl::make_vertex_array();
  g.vbo = gl::make_buffer();
  g.ibo = gl::make_buffer();
  glBindVertexArray(g.vao.get());
  glBindBuffer(GL_ARRAY_BUFFER, g.vbo.get());
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(interleaved.size() * sizeof(float)), interleaved.data(),
               GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<const void*>(3 * sizeof(float)));
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.ibo.get());
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(m.indices.size() * sizeof(std::uint32_t)),
               m.indices.data(), GL_STATIC_DRAW);
  glBindVertexArray(0);
  g.index_count = static_cast<GLsizei>(m.indices.size());
  return meshes_.emplace(shape, std::move(g)).first->second;
}

std::int64_t Layers::draw_bodies(GLuint p, bool depth_only) {
  if (contents_.world == nullptr) return 0;
  const btCollisionObjectArray& objects = contents_.world->world().getCollisionObjectArray();
  const GLint model = glGetUniformLocation(p, "uModel");
  const GLint colour = glGetUniformLocation(p, "uColour");
  std::int64_t triangles = 0;
  bodies_drawn = 0;
  // Drawn in the ground's coordinates, as the soil and the water are (Y-up worlds too).
  const bullet::GroundFrame& ground = contents_.world->ground();
  const auto draw = [&](const btCollisionShape* shape, const btTransform& pose, const Eigen::Vector3d& c) {
    const GpuMesh& m = mesh_of(shape);
    btScalar gl_matrix[16];
    (ground.identity() ? pose : ground.to_ground() * pose).getOpenGLMatrix(gl_matrix);
    float f[16];
    for (int e = 0; e < 16; ++e) f[e] = float(gl_matrix[e]);
    glUniformMatrix4fv(model, 1, GL_FALSE, f);
    if (!depth_only) glUniform3f(colour, float(c.x()), float(c.y()), float(c.z()));
    glBindVertexArray(m.vao.get());
    glDrawElements(GL_TRIANGLES, m.index_count, GL_UNSIGNED_INT, nullptr);
    triangles += m.index_count / 3;
  };
  for (int k = 0; k < objects.size(); ++k) {
    const btCollisionObject* o = objects[k];
    if (o->getCollisionShape() == nullptr || is_soil_tile(o)) continue;
    draw(o->getCollisionShape(), o->getWorldTransform(), body_colour(*o, k));
    ++bodies_drawn;
  }
  // Raycast wheels have no collision object: a dark cylinder at Bullet's wheel transform
  // (local x along the axle, turned by the wheel's rotation).
  const Eigen::Vector3d tyre(0.13, 0.12, 0.12);
  for (const scenes::VehicleContents& v : contents_.vehicles)
    for (int k = 0; k < v.vehicle->getNumWheels(); ++k) {
      const btWheelInfo& w = v.vehicle->getWheelInfo(k);
      draw(wheel_shape(double(w.m_wheelsRadius), v.wheel_width), w.m_worldTransform, tyre);
    }
  glBindVertexArray(0);
  return triangles;
}

const btCollisionShape* Layers::wheel_shape(double radius, double width) {
  std::unique_ptr<btCollisionShape>& shape = wheel_shapes_[{radius, width}];
  if (!shape)
    shape = std::make_unique<btCylinderShapeX>(btVector3(btScalar(width / 2), btScalar(radius), btScalar(radius)));
  return shape.get();
}

double Layers::mid_height() const {
  double lo = 0.0, hi = 0.0;
  for (const auto& s : soils_) {
    lo = std::min(lo, s->zmin);
    hi = std::max(hi, s->zmax);
  }
  return 0.5 * (lo + hi);
}

std::optional<Eigen::Vector3d> Layers::pick(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) const {
  // Height of the drawn surfaces (soils, water) under (x, y); the plane z = 0 elsewhere.
  auto surface = [&](double x, double y) {
    for (const auto& s : soils_) {
      const terrain::Terrain& soil = *s->contents.soil;
      const std::int64_t i = soil.column_i(x), j = soil.column_j(y);
      const shore::GridRect& r = s->region;
      if (i >= r.i0 && j >= r.j0 && i < r.i0 + r.nx && j < r.j0 + r.ny) return soil.height(i, j);
    }
    for (const auto& w : waters_)
      if (w->contents.surface->contains(x, y)) return w->contents.surface->height_at(x, y);
    return 0.0;
  };
  auto below = [&](double t) {
    const Eigen::Vector3d p = origin + t * dir;
    return p.z() <= surface(p.x(), p.y());
  };
  if (below(0.0)) return std::nullopt;
  double t0 = 0.0;
  for (double t = 0.01; t < 1000.0; t += std::max(0.005, 0.002 * t)) {
    if (below(t)) {
      double a = t0, b = t;
      for (int k = 0; k < 40; ++k) (below(0.5 * (a + b)) ? b : a) = 0.5 * (a + b);
      return origin + b * dir;
    }
    t0 = t;
  }
  return std::nullopt;
}

}  // namespace shore::render
