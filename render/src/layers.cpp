#include "layers.h"

#include <algorithm>
#include <cmath>

#include <btBulletDynamicsCommon.h>

#include "shore/scenes/world.h"

namespace shore::render {
namespace {

constexpr int kMaxTexels = 4096;  // a side of a field texture
constexpr int kWaterTile = 64;    // cells per drawn water tile

Eigen::Vector3d material_tint(const std::string& name) {
  if (name == "mud") return {0.45, 0.36, 0.27};
  if (name == "snow") return {0.93, 0.94, 0.97};
  if (name == "rigid") return {0.60, 0.60, 0.60};
  return {0.80, 0.70, 0.52};
}

Eigen::Vector3d body_colour(const btCollisionObject& o, int k) {
  if (o.isStaticObject()) return {0.62, 0.60, 0.56};
  if (o.isKinematicObject()) return {0.85, 0.60, 0.35};
  static const Eigen::Vector3d palette[] = {{0.60, 0.66, 0.78}, {0.78, 0.42, 0.38}, {0.45, 0.65, 0.48},
                                            {0.82, 0.74, 0.42}, {0.62, 0.50, 0.74}, {0.40, 0.62, 0.70}};
  return palette[k % 6];
}

void uniform3(GLuint p, const char* n, const Eigen::Vector3d& v) {
  glUniform3f(glGetUniformLocation(p, n), float(v.x()), float(v.y()), float(v.z()));
}

}  // namespace

TileMesh tile_mesh(int cells) {
  TileMesh m;
  for (int b = 0; b <= cells; ++b)
    for (int a = 0; a <= cells; ++a) m.vertices.insert(m.vertices.end(), {a, b});
  const auto row = static_cast<std::uint32_t>(cells + 1);
  for (std::uint32_t b = 0; b < static_cast<std::uint32_t>(cells); ++b)
    for (std::uint32_t a = 0; a < static_cast<std::uint32_t>(cells); ++a) {
      const std::uint32_t v = b * row + a;
      m.indices.insert(m.indices.end(), {v, v + 1, v + row + 1, v, v + row + 1, v + row});
    }
  return m;
}

void FieldTexture::create(int columns_x, int columns_y, const std::vector<float>& base_heights) {
  nx = columns_x;
  ny = columns_y;
  auto make = [&](gl::Texture& t, GLint format, GLenum layout, const void* data) {
    t = gl::make_texture();
    glBindTexture(GL_TEXTURE_2D, t.get());
    glTexImage2D(GL_TEXTURE_2D, 0, format, nx, ny, 0, layout, GL_FLOAT, data);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  };
  make(field, GL_RG32F, GL_RG, nullptr);
  make(base, GL_R32F, GL_RED, base_heights.data());
}

std::int64_t FieldTexture::upload(int i0, int j0, int w, int h, const std::vector<float>& rg) {
  glBindTexture(GL_TEXTURE_2D, field.get());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTexSubImage2D(GL_TEXTURE_2D, 0, i0, j0, w, h, GL_RG, GL_FLOAT, rg.data());
  return static_cast<std::int64_t>(w) * h * 2 * static_cast<std::int64_t>(sizeof(float));
}

Layers::~Layers() { clear(); }

void Layers::set(const scenes::SceneContents& contents) {
  clear();
  contents_ = contents;
  for (const scenes::SoilContents& s : contents.soils) {
    const terrain::Terrain& soil = *s.soil;
    const double cell = soil.settings().cell, ox = soil.settings().origin_x, oy = soil.settings().origin_y;
    const double x0 = std::max(s.region.x0, contents.bounds.x0), x1 = std::min(s.region.x1, contents.bounds.x1);
    const double y0 = std::max(s.region.y0, contents.bounds.y0), y1 = std::min(s.region.y1, contents.bounds.y1);
    if (!(x1 > x0 && y1 > y0)) continue;
    auto layer = std::make_unique<SoilLayer>();
    layer->contents = s;
    layer->i0 = static_cast<std::int64_t>(std::ceil((x0 - ox) / cell - 1e-9));
    layer->j0 = static_cast<std::int64_t>(std::ceil((y0 - oy) / cell - 1e-9));
    const auto i1 = static_cast<std::int64_t>(std::floor((x1 - ox) / cell + 1e-9));
    const auto j1 = static_cast<std::int64_t>(std::floor((y1 - oy) / cell + 1e-9));
    const int nx = static_cast<int>(std::clamp<std::int64_t>(i1 - layer->i0 + 1, 2, kMaxTexels));
    const int ny = static_cast<int>(std::clamp<std::int64_t>(j1 - layer->j0 + 1, 2, kMaxTexels));
    std::vector<double> base(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny));
    soil.base_heights({layer->i0, layer->j0, nx, ny}, base);
    const std::vector<float> base_f(base.begin(), base.end());
    layer->tex.x0 = soil.column_x(layer->i0);
    layer->tex.y0 = soil.column_y(layer->j0);
    layer->tex.cell = cell;
    layer->tex.create(nx, ny, base_f);
    const auto [lo, hi] = std::minmax_element(base.begin(), base.end());
    layer->zmin = *lo;
    layer->zmax = *hi;
    if (s.coupling != nullptr) {
      SoilLayer* raw = layer.get();
      s.coupling->tiles().set_push_observer([raw](std::span<const terrain::ColumnRect> changed) {
        raw->pending.insert(raw->pending.end(), changed.begin(), changed.end());
      });
    }
    soils_.push_back(std::move(layer));
  }
  for (const scenes::WaterContents& w : contents.waters) {
    auto layer = std::make_unique<WaterLayer>();
    layer->contents = w;
    const water::Surface& s = *w.surface;
    layer->tex.x0 = s.node_x(0);
    layer->tex.y0 = s.node_y(0);
    layer->tex.cell = s.spacing();
    layer->tex.create(s.nx(), s.ny(), std::vector<float>(s.node_count(), float(s.settings().rest_height)));
    waters_.push_back(std::move(layer));
  }
}

void Layers::clear() {
  for (auto& s : soils_)
    if (s->contents.coupling != nullptr) s->contents.coupling->tiles().set_push_observer({});
  soils_.clear();
  waters_.clear();
  meshes_.clear();
  contents_ = {};
}

void Layers::upload_soil(SoilLayer& layer, const terrain::ColumnRect& rect, FrameStats& stats) {
  const std::int64_t a0 = std::max(rect.i0, layer.i0), b0 = std::max(rect.j0, layer.j0);
  const std::int64_t a1 = std::min(rect.i0 + rect.nx, layer.i0 + layer.tex.nx);
  const std::int64_t b1 = std::min(rect.j0 + rect.ny, layer.j0 + layer.tex.ny);
  if (a1 <= a0 || b1 <= b0) return;
  const int w = static_cast<int>(a1 - a0), h = static_cast<int>(b1 - b0);
  const terrain::Terrain& soil = *layer.contents.soil;
  std::vector<double> heights(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  std::vector<double> base(heights.size());
  soil.heights({a0, b0, w, h}, heights);
  soil.base_heights({a0, b0, w, h}, base);
  std::vector<float> rg(2 * heights.size());
  for (int b = 0; b < h; ++b)
    for (int a = 0; a < w; ++a) {
      const std::size_t k = static_cast<std::size_t>(b) * static_cast<std::size_t>(w) + static_cast<std::size_t>(a);
      const double sink = soil.sinkage(a0 + a, b0 + b);
      rg[2 * k] = float(heights[k]);
      rg[2 * k + 1] = float(sink);
      layer.max_delta = std::max(layer.max_delta, std::abs(heights[k] - base[k]));
      layer.max_sinkage = std::max(layer.max_sinkage, std::abs(sink));
      layer.zmin = std::min(layer.zmin, heights[k]);
      layer.zmax = std::max(layer.zmax, heights[k]);
    }
  stats.soil_bytes += layer.tex.upload(static_cast<int>(a0 - layer.i0), static_cast<int>(b0 - layer.j0), w, h, rg);
}

void Layers::sync_water(WaterLayer& layer, FrameStats& stats) {
  const water::Surface& s = *layer.contents.surface;
  const double rest = s.settings().rest_height;
  std::vector<float> rg(2 * s.node_count());
  layer.scale_height = layer.scale_velocity = layer.steepest = 0.0;
  for (int j = 0; j < s.ny(); ++j)
    for (int i = 0; i < s.nx(); ++i) {
      const std::size_t k =
          static_cast<std::size_t>(j) * static_cast<std::size_t>(s.nx()) + static_cast<std::size_t>(i);
      const double h = s.height(i, j), v = s.vertical_velocity(i, j);
      rg[2 * k] = float(h);
      rg[2 * k + 1] = float(v);
      if (s.is_fixed(i, j)) continue;
      layer.scale_height = std::max(layer.scale_height, std::abs(h - rest));
      layer.scale_velocity = std::max(layer.scale_velocity, std::abs(v));
      if (i > 0) layer.steepest = std::max(layer.steepest, std::abs(h - s.height(i - 1, j)) / s.spacing());
      if (j > 0) layer.steepest = std::max(layer.steepest, std::abs(h - s.height(i, j - 1)) / s.spacing());
    }
  stats.water_bytes += layer.tex.upload(0, 0, s.nx(), s.ny(), rg);
}

void Layers::sync(FrameStats& stats) {
  stats.soil_bytes = stats.water_bytes = stats.whole_soil_bytes = stats.soil_columns = 0;
  for (auto& layer : soils_) {
    const std::int64_t columns = static_cast<std::int64_t>(layer->tex.nx) * layer->tex.ny;
    stats.soil_columns += columns;
    stats.whole_soil_bytes += columns * 2 * static_cast<std::int64_t>(sizeof(float));
    // Without a coupling nobody reports changes: upload the whole field every time.
    if (layer->whole || layer->contents.coupling == nullptr) {
      upload_soil(*layer, {layer->i0, layer->j0, layer->tex.nx, layer->tex.ny}, stats);
      layer->whole = false;
    } else {
      for (const terrain::ColumnRect& r : layer->pending) upload_soil(*layer, r, stats);
    }
    layer->pending.clear();
  }
  for (auto& w : waters_) sync_water(*w, stats);
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

GpuTile& Layers::tile(int cells) {
  auto it = tiles_.find(cells);
  if (it != tiles_.end()) return it->second;
  const TileMesh m = tile_mesh(cells);
  GpuTile t;
  t.cells = cells;
  t.vao = gl::make_vertex_array();
  t.vbo = gl::make_buffer();
  t.ibo = gl::make_buffer();
  glBindVertexArray(t.vao.get());
  glBindBuffer(GL_ARRAY_BUFFER, t.vbo.get());
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(m.vertices.size() * sizeof(std::int32_t)), m.vertices.data(),
               GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribIPointer(0, 2, GL_INT, 2 * sizeof(std::int32_t), nullptr);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, t.ibo.get());
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(m.indices.size() * sizeof(std::uint32_t)),
               m.indices.data(), GL_STATIC_DRAW);
  glBindVertexArray(0);
  t.index_count = static_cast<GLsizei>(m.indices.size());
  return tiles_.emplace(cells, std::move(t)).first->second;
}

std::int64_t Layers::draw_field(GLuint p, const FieldTexture& tex, int tile_cells) {
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, tex.base.get());
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, tex.field.get());
  glUniform1i(glGetUniformLocation(p, "uField"), 0);
  glUniform1i(glGetUniformLocation(p, "uBase"), 1);
  glUniform2i(glGetUniformLocation(p, "uSize"), tex.nx, tex.ny);
  glUniform2f(glGetUniformLocation(p, "uOrigin"), float(tex.x0), float(tex.y0));
  glUniform1f(glGetUniformLocation(p, "uCell"), float(tex.cell));
  const GpuTile& t = tile(tile_cells);
  glBindVertexArray(t.vao.get());
  const GLint origin = glGetUniformLocation(p, "uTileOrigin");
  std::int64_t triangles = 0;
  for (int b = 0; b < tex.ny - 1; b += tile_cells)
    for (int a = 0; a < tex.nx - 1; a += tile_cells) {
      glUniform2i(origin, a, b);
      glDrawElements(GL_TRIANGLES, t.index_count, GL_UNSIGNED_INT, nullptr);
      triangles += t.index_count / 3;
    }
  glBindVertexArray(0);
  return triangles;
}

std::int64_t Layers::draw_soils(GLuint p, bool depth_only, const RenderSettings& s) {
  std::int64_t triangles = 0;
  for (const auto& layer : soils_) {
    const terrain::TerrainSettings& ts = layer->contents.soil->settings();
    glUniform1f(glGetUniformLocation(p, "uSlopeGain"), 1.0f);
    if (!depth_only) {
      glUniform1i(glGetUniformLocation(p, "uMode"), static_cast<int>(s.ground));
      glUniform1f(glGetUniformLocation(p, "uScale"), float(ground_scale_));
      glUniform2f(glGetUniformLocation(p, "uHeightRange"), float(layer->zmin), float(layer->zmax));
      uniform3(p, "uTint", material_tint(ts.material.name));
      glUniform1i(glGetUniformLocation(p, "uTileColumns"), s.soil_tile_borders ? ts.tile_columns : 0);
      // Storage tile edges sit at multiples of tile_columns; texel 0 is column i0.
      glUniform2i(glGetUniformLocation(p, "uFirstColumn"), static_cast<int>(layer->i0), static_cast<int>(layer->j0));
    }
    triangles += draw_field(p, layer->tex, std::clamp(ts.tile_columns, 16, 256));
  }
  return triangles;
}

std::int64_t Layers::draw_waters(GLuint p, const RenderSettings& s) {
  std::int64_t triangles = 0;
  for (const auto& layer : waters_) {
    glUniform1f(glGetUniformLocation(p, "uSlopeGain"), float(wave_gain_));
    glUniform1i(glGetUniformLocation(p, "uMode"), static_cast<int>(s.water));
    glUniform1f(glGetUniformLocation(p, "uScale"), float(water_scale_));
    triangles += draw_field(p, layer->tex, kWaterTile);
  }
  return triangles;
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
  for (int k = 0; k < objects.size(); ++k) {
    const btCollisionObject* o = objects[k];
    if (o->getCollisionShape() == nullptr || is_soil_tile(o)) continue;
    const GpuMesh& m = mesh_of(o->getCollisionShape());
    btScalar gl_matrix[16];
    o->getWorldTransform().getOpenGLMatrix(gl_matrix);
    float f[16];
    for (int c = 0; c < 16; ++c) f[c] = float(gl_matrix[c]);
    glUniformMatrix4fv(model, 1, GL_FALSE, f);
    if (!depth_only) {
      const Eigen::Vector3d c = body_colour(*o, k);
      glUniform3f(colour, float(c.x()), float(c.y()), float(c.z()));
    }
    glBindVertexArray(m.vao.get());
    glDrawElements(GL_TRIANGLES, m.index_count, GL_UNSIGNED_INT, nullptr);
    triangles += m.index_count / 3;
    ++bodies_drawn;
  }
  glBindVertexArray(0);
  return triangles;
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
      const double fi = (x - s->tex.x0) / s->tex.cell, fj = (y - s->tex.y0) / s->tex.cell;
      if (fi >= 0 && fj >= 0 && fi <= s->tex.nx - 1 && fj <= s->tex.ny - 1) {
        const terrain::Terrain& soil = *s->contents.soil;
        return soil.height(soil.column_i(x), soil.column_j(y));
      }
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
