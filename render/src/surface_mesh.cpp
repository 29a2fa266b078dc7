#include "surface_mesh.h"

#include <algorithm>

namespace shore::render {

Frustum::Frustum(const Eigen::Matrix4f& m) {
  const Eigen::Vector4f r0 = m.row(0), r1 = m.row(1), r2 = m.row(2), r3 = m.row(3);
  planes = {r3 + r0, r3 - r0, r3 + r1, r3 - r1, r3 + r2, r3 - r2};
}

bool Frustum::may_see(const std::array<float, 3>& lo, const std::array<float, 3>& hi) const {
  for (const Eigen::Vector4f& p : planes) {
    // The box's corner farthest along the plane's normal: if even it is outside, all are.
    const float x = p.x() >= 0.0f ? hi[0] : lo[0], y = p.y() >= 0.0f ? hi[1] : lo[1], z = p.z() >= 0.0f ? hi[2] : lo[2];
    if (p.x() * x + p.y() * y + p.z() * z + p.w() < 0.0f) return false;
  }
  return true;
}

namespace {
mesh::MeshSettings settings_for(double max_error_pixels) {
  mesh::MeshSettings s;
  s.max_error_pixels = max_error_pixels;
  return s;
}
}  // namespace

SurfaceMesh::SurfaceMesh(std::unique_ptr<mesh::Field> field, VertexExtras extras, double max_error_pixels)
    : field_(std::move(field)), extras_(std::move(extras)), mesh_(settings_for(max_error_pixels)) {}

std::int64_t SurfaceMesh::update(const mesh::Camera& eye) {
  const mesh::MeshUpdate& u = mesh_.update(*field_, &eye);
  for (const mesh::ChunkKey& k : u.removed) gpu_.erase(k);
  std::int64_t bytes = 0;
  for (const mesh::ChunkKey& k : u.changed) bytes += upload(k, mesh_.chunks().at(k));
  return bytes;
}

std::int64_t SurfaceMesh::upload(const mesh::ChunkKey& key, const mesh::Chunk& chunk) {
  const std::size_t n = chunk.nodes.size();
  staging_.assign(n * kVertexFloats, 0.0f);
  const auto ni = static_cast<std::uint64_t>(field_->ni());
  for (std::size_t v = 0; v < n; ++v) {
    float* out = &staging_[v * kVertexFloats];
    std::copy_n(&chunk.positions[3 * v], 3, out);
    std::copy_n(&chunk.normals[3 * v], 3, out + 3);
    extras_(static_cast<std::int64_t>(chunk.nodes[v] % ni), static_cast<std::int64_t>(chunk.nodes[v] / ni), out[2],
            out + 6);
  }
  auto [it, fresh] = gpu_.try_emplace(key);
  GpuChunk& g = it->second;
  if (fresh) {
    g.vao = gl::make_vertex_array();
    g.vbo = gl::make_buffer();
    g.ibo = gl::make_buffer();
    glBindVertexArray(g.vao.get());
    glBindBuffer(GL_ARRAY_BUFFER, g.vbo.get());
    constexpr GLsizei stride = kVertexFloats * sizeof(float);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(3 * sizeof(float)));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(6 * sizeof(float)));
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.ibo.get());
  }
  glBindVertexArray(g.vao.get());
  glBindBuffer(GL_ARRAY_BUFFER, g.vbo.get());
  const auto vertex_bytes = static_cast<GLsizeiptr>(staging_.size() * sizeof(float));
  const auto index_bytes = static_cast<GLsizeiptr>(chunk.indices.size() * sizeof(std::uint32_t));
  glBufferData(GL_ARRAY_BUFFER, vertex_bytes, staging_.data(), GL_DYNAMIC_DRAW);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, index_bytes, chunk.indices.data(), GL_DYNAMIC_DRAW);
  glBindVertexArray(0);
  g.index_count = static_cast<GLsizei>(chunk.indices.size());
  g.lo = chunk.lo;
  g.hi = chunk.hi;
  return vertex_bytes + index_bytes;
}

ChunkDraw SurfaceMesh::draw(const Frustum* frustum) const {
  ChunkDraw d;
  for (const auto& [key, g] : gpu_) {
    if (g.index_count == 0) continue;
    if (frustum != nullptr && !frustum->may_see(g.lo, g.hi)) {
      ++d.culled;
      continue;
    }
    glBindVertexArray(g.vao.get());
    glDrawElements(GL_TRIANGLES, g.index_count, GL_UNSIGNED_INT, nullptr);
    d.triangles += g.index_count / 3;
    ++d.drawn;
  }
  glBindVertexArray(0);
  return d;
}

}  // namespace shore::render
