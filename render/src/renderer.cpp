#include "shore/render/renderer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <stdexcept>
#include <unordered_map>
#include <vector>

#include <Eigen/Geometry>

#include "gl_util.h"
#include "layers.h"
#include "shaders.h"
#include "shore/scenes/image.h"

namespace shore::render {

using Mat4 = Eigen::Matrix4f;

namespace {

constexpr int kShadowSize = 2048;

Mat4 ortho(double r, double n, double f) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m(0, 0) = 1.0 / r;
  m(1, 1) = 1.0 / r;
  m(2, 2) = -2.0 / (f - n);
  m(2, 3) = -(f + n) / (f - n);
  return m.cast<float>();
}

/// The sun: azimuth 315 degrees (north-west), 50 degrees up.
Eigen::Vector3d sun_direction() {
  const double az = 315.0 * std::numbers::pi / 180.0, alt = 50.0 * std::numbers::pi / 180.0;
  return {std::sin(az) * std::cos(alt), std::cos(az) * std::cos(alt), std::sin(alt)};
}

GLint loc(GLuint program, const char* name) { return glGetUniformLocation(program, name); }
void set(GLuint p, const char* n, const Mat4& m) { glUniformMatrix4fv(loc(p, n), 1, GL_FALSE, m.data()); }
void set(GLuint p, const char* n, float v) { glUniform1f(loc(p, n), v); }
void set(GLuint p, const char* n, int v) { glUniform1i(loc(p, n), v); }
void set(GLuint p, const char* n, const Eigen::Vector3d& v) {
  glUniform3f(loc(p, n), float(v.x()), float(v.y()), float(v.z()));
}

/// The pictures' colour maps (image.h; their colour bars use the same) as a 256 x 3 texture: rows diverging,
/// height, water.
gl::Texture colour_lut() {
  std::vector<std::uint8_t> rgb;
  for (int row = 0; row < 3; ++row)
    for (int k = 0; k < 256; ++k) {
      const double t = k / 255.0;
      const scenes::Rgb c = row == 0   ? scenes::diverging_colour(2.0 * t - 1.0)
                            : row == 1 ? scenes::height_colour(t)
                                       : scenes::water_colour(2.0 * t - 1.0);
      rgb.insert(rgb.end(), {c.r, c.g, c.b});
    }
  gl::Texture t = gl::make_texture();
  glBindTexture(GL_TEXTURE_2D, t.get());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, 256, 3, 0, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return t;
}

std::string lit_fragment(const char* body) { return std::string(shaders::kLighting) + body; }

}  // namespace

struct Renderer::Impl {
  GLuint terrain = 0, water = 0, mesh = 0, field_depth = 0, mesh_depth = 0, sky = 0, lines = 0;
  gl::Texture lut;
  gl::VertexArray empty_vao;
  Layers layers;
  // Framebuffers: multisampled colour + depth, the resolved colour, the shadow map.
  gl::Framebuffer msaa_fbo, resolve_fbo, shadow_fbo;
  gl::Renderbuffer msaa_colour, msaa_depth;
  gl::Texture resolve_colour, shadow_depth;
  int width = 0, height = 0, samples = 0;
  bool bodies_on = true;  // the frame's RenderSettings::bodies
  gl::VertexArray line_vao;
  gl::Buffer line_vbo;
  FrameStats stats;

  Impl();
  ~Impl();
  void ensure_targets(int w, int h, int want_samples);
  void shadow_pass(const Mat4& light);
  void colour_pass(const OrbitCamera& camera, double aspect, const Mat4& light, const RenderSettings& s,
                   const LineBatch* batch);
  void draw_lines(const Mat4& view_proj, const LineBatch& batch);
  void draw_edges(const Frustum& frustum, const RenderSettings& s);
};

Renderer::Impl::Impl() {
  const std::string field_inputs = shaders::kFieldFragmentInputs;
  terrain =
      gl::program(shaders::kSurfaceVertex, lit_fragment((field_inputs + shaders::kTerrainFragment).c_str()), "terrain");
  water = gl::program(shaders::kSurfaceVertex, lit_fragment((field_inputs + shaders::kWaterFragment).c_str()), "water");
  mesh = gl::program(shaders::kMeshVertex, lit_fragment(shaders::kMeshFragment), "mesh");
  field_depth = gl::program(shaders::kSurfaceVertex, shaders::kDepthFragment, "surface depth");
  mesh_depth = gl::program(shaders::kMeshVertex, shaders::kDepthFragment, "mesh depth");
  sky = gl::program(shaders::kSkyVertex, lit_fragment(shaders::kSkyFragment), "sky");
  lines = gl::program(shaders::kLineVertex, shaders::kLineFragment, "lines");
  lut = colour_lut();
  empty_vao = gl::make_vertex_array();
  line_vao = gl::make_vertex_array();
  line_vbo = gl::make_buffer();
  glBindVertexArray(line_vao.get());
  glBindBuffer(GL_ARRAY_BUFFER, line_vbo.get());
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(LineBatch::End), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(LineBatch::End),
                        reinterpret_cast<const void*>(3 * sizeof(float)));
  glBindVertexArray(0);
  // The shadow map: a depth texture compared in the shader (sampler2DShadow).
  shadow_depth = gl::make_texture();
  glBindTexture(GL_TEXTURE_2D, shadow_depth.get());
  glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, kShadowSize, kShadowSize, 0, GL_DEPTH_COMPONENT, GL_FLOAT,
               nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  shadow_fbo = gl::make_framebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo.get());
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, shadow_depth.get(), 0);
  glDrawBuffer(GL_NONE);
  glReadBuffer(GL_NONE);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  gl::check("renderer setup");
}

Renderer::Impl::~Impl() {
  for (GLuint p : {terrain, water, mesh, field_depth, mesh_depth, sky, lines}) glDeleteProgram(p);
}

void Renderer::Impl::ensure_targets(int w, int h, int want_samples) {
  GLint max_samples = 1;
  glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
  const int s = std::clamp(want_samples, 1, std::max(1, max_samples));
  if (w == width && h == height && s == samples && msaa_fbo.get() != 0) return;
  width = w;
  height = h;
  samples = s;
  msaa_colour = gl::make_renderbuffer();
  glBindRenderbuffer(GL_RENDERBUFFER, msaa_colour.get());
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, s, GL_RGBA8, w, h);
  msaa_depth = gl::make_renderbuffer();
  glBindRenderbuffer(GL_RENDERBUFFER, msaa_depth.get());
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, s, GL_DEPTH_COMPONENT24, w, h);
  msaa_fbo = gl::make_framebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, msaa_fbo.get());
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, msaa_colour.get());
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, msaa_depth.get());
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("OpenGL: the multisampled framebuffer is incomplete");
  resolve_colour = gl::make_texture();
  glBindTexture(GL_TEXTURE_2D, resolve_colour.get());
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  resolve_fbo = gl::make_framebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, resolve_fbo.get());
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, resolve_colour.get(), 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  gl::check("framebuffers");
}

void Renderer::Impl::shadow_pass(const Mat4& light) {
  glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo.get());
  glViewport(0, 0, kShadowSize, kShadowSize);
  glClear(GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.5f, 2.0f);
  glUseProgram(field_depth);
  set(field_depth, "uViewProj", light);
  layers.draw_soils(field_depth, nullptr, /*depth_only=*/true);
  glUseProgram(mesh_depth);
  set(mesh_depth, "uViewProj", light);
  if (bodies_on) layers.draw_bodies(mesh_depth, /*depth_only=*/true);
  glDisable(GL_POLYGON_OFFSET_FILL);
}

void Renderer::Impl::draw_lines(const Mat4& view_proj, const LineBatch& batch) {
  if (batch.ends().empty()) return;
  glUseProgram(lines);
  set(lines, "uViewProj", view_proj);
  glBindVertexArray(line_vao.get());
  glBindBuffer(GL_ARRAY_BUFFER, line_vbo.get());
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(batch.ends().size() * sizeof(LineBatch::End)),
               batch.ends().data(), GL_STREAM_DRAW);
  glDrawArrays(GL_LINES, 0, static_cast<GLsizei>(batch.ends().size()));
  glBindVertexArray(0);
  stats.lines = static_cast<std::int64_t>(batch.line_count());
}

void Renderer::Impl::draw_edges(const Frustum& frustum, const RenderSettings& s) {
  // The meshes' triangles outlined over their filled surfaces (drawn at the same depth).
  glDepthFunc(GL_LEQUAL);
  glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
  glUseProgram(terrain);
  set(terrain, "uEdges", 1);
  layers.draw_soils(terrain, &frustum, false, s);
  glUseProgram(water);
  set(water, "uEdges", 1);
  layers.draw_waters(water, &frustum, s);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glDepthFunc(GL_LESS);
}

void Renderer::Impl::colour_pass(const OrbitCamera& camera, double aspect, const Mat4& light, const RenderSettings& s,
                                 const LineBatch* batch) {
  const Mat4 view_proj = camera.projection(aspect) * camera.view();
  glBindFramebuffer(GL_FRAMEBUFFER, msaa_fbo.get());
  glViewport(0, 0, width, height);
  glClearColor(1.0f, 1.0f, 1.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  // Textures: 2 colour maps, 3 shadow map.
  glActiveTexture(GL_TEXTURE2);
  glBindTexture(GL_TEXTURE_2D, lut.get());
  glActiveTexture(GL_TEXTURE3);
  glBindTexture(GL_TEXTURE_2D, shadow_depth.get());
  glActiveTexture(GL_TEXTURE0);
  const Eigen::Vector3d sun = sun_direction();
  for (GLuint p : {terrain, water, mesh, sky}) {
    glUseProgram(p);
    set(p, "uViewProj", view_proj);
    set(p, "uLightViewProj", light);
    set(p, "uSunDir", sun);
    set(p, "uShadow", 3);
    set(p, "uShadowOn", s.shadows ? 1 : 0);
    set(p, "uShadowTexel", 1.0f / kShadowSize);
    set(p, "uLut", 2);
  }
  if (s.sky) {
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    glUseProgram(sky);
    set(sky, "uInvViewProj", Mat4(view_proj.inverse()));
    glBindVertexArray(empty_vao.get());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDepthMask(GL_TRUE);
  }
  glEnable(GL_DEPTH_TEST);
  const Frustum frustum(view_proj);
  glUseProgram(terrain);
  set(terrain, "uEdges", 0);
  const ChunkDraw soils = layers.draw_soils(terrain, &frustum, false, s);
  glUseProgram(mesh);
  stats.triangles = s.bodies ? layers.draw_bodies(mesh, false) : 0;
  stats.bodies = s.bodies ? layers.bodies_drawn : 0;
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glUseProgram(water);
  set(water, "uEye", camera.eye());
  set(water, "uEdges", 0);
  const ChunkDraw waters = layers.draw_waters(water, &frustum, s);
  glDisable(GL_BLEND);
  if (s.mesh_edges) draw_edges(frustum, s);
  stats.surface_triangles = soils.triangles + waters.triangles;
  stats.triangles += stats.surface_triangles;
  stats.chunks_drawn = soils.drawn + waters.drawn;
  stats.chunks_culled = soils.culled + waters.culled;
  stats.lines = 0;
  if (batch != nullptr) draw_lines(view_proj, *batch);
}

Renderer::Renderer() : impl_(std::make_unique<Impl>()) {}
Renderer::~Renderer() = default;

void Renderer::set_contents(const scenes::SceneContents& contents) { impl_->layers.set(contents); }
void Renderer::clear() { impl_->layers.clear(); }

void Renderer::draw(const OrbitCamera& camera, int width, int height, const RenderSettings& settings,
                    const LineBatch* lines) {
  Impl& m = *impl_;
  m.ensure_targets(std::max(width, 1), std::max(height, 1), settings.samples);
  m.layers.update(camera.eye(), camera.fov_deg, m.height, settings, m.stats);
  m.layers.prepare(settings, m.stats);
  const scenes::Bounds b = m.layers.bounds();
  const Eigen::Vector3d centre(0.5 * (b.x0 + b.x1), 0.5 * (b.y0 + b.y1), m.layers.mid_height());
  const double radius = 0.5 * std::hypot(b.x1 - b.x0, b.y1 - b.y0) + 1.0;
  const Mat4 light = ortho(radius, 0.1, 4.0 * radius) * look_at(centre + 2.0 * radius * sun_direction(), centre);
  glDisable(GL_CULL_FACE);
  m.bodies_on = settings.bodies;
  if (settings.shadows) m.shadow_pass(light);
  m.colour_pass(camera, double(m.width) / double(m.height), light, settings, lines);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, m.msaa_fbo.get());
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m.resolve_fbo.get());
  glBlitFramebuffer(0, 0, m.width, m.height, 0, 0, m.width, m.height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glFinish();  // frame times then include the rasterizer's work (llvmpipe renders on other threads)
  gl::check("draw");
}

void Renderer::present(int width, int height) const {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, impl_->resolve_fbo.get());
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  glBlitFramebuffer(0, 0, impl_->width, impl_->height, 0, 0, width, height, GL_COLOR_BUFFER_BIT, GL_LINEAR);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

scenes::Image Renderer::read_image() const {
  const int w = impl_->width, h = impl_->height;
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, impl_->resolve_fbo.get());
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  scenes::Image out(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::uint8_t* p = &rgba[(static_cast<std::size_t>(h - 1 - y) * static_cast<std::size_t>(w) + x) * 4];
      out.at(x, y) = {p[0], p[1], p[2]};
    }
  return out;
}

std::optional<Eigen::Vector3d> Renderer::pick(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) const {
  return impl_->layers.pick(origin, direction.normalized());
}

const FrameStats& Renderer::stats() const noexcept { return impl_->stats; }

}  // namespace shore::render
