#include "shore/scenes/mesh.h"

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "shore/core/error.h"
#include "shore/mesh/chunked_mesh.h"
#include "shore/scenes/grid_field.h"

namespace shore::scenes {

void HeightGridField::positions(const shore::GridRect& r, std::span<double> out) const {
  std::size_t k = 0;
  for (std::int64_t j = r.j0; j < r.j0 + r.ny; ++j)
    for (std::int64_t i = r.i0; i < r.i0 + r.nx; ++i) {
      out[k++] = grid_->x(static_cast<int>(i));
      out[k++] = grid_->y(static_cast<int>(j));
      out[k++] = grid_->at(static_cast<int>(i), static_cast<int>(j));
    }
}

void HeightGridField::take_changes(std::vector<shore::GridRect>& out) {
  out.clear();
  if (first_) out.push_back({0, 0, grid_->nx, grid_->ny});
  first_ = false;
}

void MeshExport::validate() const { Check{"scenes.MeshExport"}.non_negative("max_error", max_error); }

namespace {

struct Triangle {
  std::array<int, 3> v;  // vertex indices (0-based)
};

/// What a file holds: vertices (with normals when simplified) and triangles.
struct Triangles {
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::array<float, 3>> normals;  ///< empty: none
  std::vector<Triangle> faces;
  std::string comment;
};

/// Two triangles per cell, counter-clockwise seen from +z; NaN vertices drop triangles.
std::vector<Triangle> triangulate(const HeightGrid& g) {
  std::vector<Triangle> tris;
  tris.reserve(2 * static_cast<std::size_t>(std::max(g.nx - 1, 0)) * static_cast<std::size_t>(std::max(g.ny - 1, 0)));
  auto ok = [&](int i, int j) { return std::isfinite(g.at(i, j)); };
  auto id = [&](int i, int j) { return static_cast<int>(g.index(i, j)); };
  for (int j = 0; j + 1 < g.ny; ++j)
    for (int i = 0; i + 1 < g.nx; ++i) {
      if (ok(i, j) && ok(i + 1, j) && ok(i + 1, j + 1)) tris.push_back({{id(i, j), id(i + 1, j), id(i + 1, j + 1)}});
      if (ok(i, j) && ok(i + 1, j + 1) && ok(i, j + 1)) tris.push_back({{id(i, j), id(i + 1, j + 1), id(i, j + 1)}});
    }
  return tris;
}

/// Every column a vertex (NaN written as 0), two triangles per cell.
Triangles full_mesh(const HeightGrid& g) {
  Triangles t;
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const double z = g.at(i, j);
      t.vertices.push_back({g.x(i), g.y(j), std::isfinite(z) ? z : 0.0});
    }
  t.faces = triangulate(g);
  std::ostringstream c;
  c.precision(9);
  c << "Shore height grid " << g.nx << " x " << g.ny << ", cell " << g.cell << " m, Z up";
  t.comment = c.str();
  return t;
}

/// The simplified mesh: every column within max_error (vertically) of it.
Triangles simplified_mesh(const HeightGrid& g, double max_error) {
  HeightGridField field(g);
  mesh::MeshSettings s;
  s.max_error = max_error;
  mesh::ChunkedMesh chunks(s);
  chunks.update(field);
  const mesh::TriangleMesh m = mesh::merge(chunks, field);
  Triangles t;
  for (std::size_t v = 0; v < m.nodes.size(); ++v) {
    t.vertices.push_back({m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]});
    t.normals.push_back({m.normals[3 * v], m.normals[3 * v + 1], m.normals[3 * v + 2]});
  }
  for (std::size_t f = 0; f < m.triangle_count(); ++f)
    t.faces.push_back({{static_cast<int>(m.indices[3 * f]), static_cast<int>(m.indices[3 * f + 1]),
                        static_cast<int>(m.indices[3 * f + 2])}});
  std::ostringstream c;
  c.precision(9);
  c << "Shore height grid " << g.nx << " x " << g.ny << ", cell " << g.cell << " m, Z up, simplified within "
    << max_error << " m: " << t.faces.size() << " of " << 2 * std::max(g.nx - 1, 0) * std::max(g.ny - 1, 0)
    << " triangles";
  t.comment = c.str();
  return t;
}

Triangles mesh_of(const HeightGrid& g, const MeshExport& options) {
  options.validate();
  return options.simplified ? simplified_mesh(g, options.max_error) : full_mesh(g);
}

/// Opens path.tmp for writing; commit() renames it into place.
class AtomicFile {
 public:
  AtomicFile(const std::filesystem::path& path, std::ios::openmode mode) : path_(path), tmp_(path) {
    tmp_ += ".tmp";
    out_.open(tmp_, mode | std::ios::trunc);
    if (!out_) throw FileError("cannot write " + tmp_.string());
  }
  std::ofstream& stream() { return out_; }
  std::filesystem::path commit() {
    out_.close();
    if (!out_) throw FileError("error while writing " + tmp_.string());
    std::error_code ec;
    std::filesystem::rename(tmp_, path_, ec);
    if (ec) throw FileError("cannot rename " + tmp_.string() + ": " + ec.message());
    return path_;
  }

 private:
  std::filesystem::path path_, tmp_;
  std::ofstream out_;
};

}  // namespace

std::filesystem::path write_obj(const std::filesystem::path& path, const HeightGrid& g, const MeshExport& options) {
  const Triangles t = mesh_of(g, options);
  AtomicFile file(path, std::ios::out);
  std::ofstream& o = file.stream();
  o.precision(9);
  o << "# " << t.comment << '\n';
  for (const auto& v : t.vertices) o << "v " << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
  for (const auto& n : t.normals) o << "vn " << n[0] << ' ' << n[1] << ' ' << n[2] << '\n';
  const bool normals = !t.normals.empty();
  for (const Triangle& f : t.faces) {
    o << 'f';
    for (const int v : f.v) {
      o << ' ' << v + 1;
      if (normals) o << "//" << v + 1;
    }
    o << '\n';
  }
  return file.commit();
}

std::filesystem::path write_ply(const std::filesystem::path& path, const HeightGrid& g, const MeshExport& options) {
  const Triangles t = mesh_of(g, options);
  const bool normals = !t.normals.empty();
  AtomicFile file(path, std::ios::out | std::ios::binary);
  std::ofstream& o = file.stream();
  o << "ply\nformat binary_little_endian 1.0\ncomment " << (normals ? t.comment : "Shore height grid, metres, Z up")
    << "\nelement vertex " << t.vertices.size() << "\nproperty float x\nproperty float y\nproperty float z\n"
    << (normals ? "property float nx\nproperty float ny\nproperty float nz\n" : "") << "element face " << t.faces.size()
    << "\nproperty list uchar int vertex_indices\nend_header\n";
  static_assert(std::endian::native == std::endian::little, "PLY writer assumes a little-endian machine");
  for (std::size_t k = 0; k < t.vertices.size(); ++k) {
    const std::array<float, 3> v{static_cast<float>(t.vertices[k][0]), static_cast<float>(t.vertices[k][1]),
                                 static_cast<float>(t.vertices[k][2])};
    o.write(reinterpret_cast<const char*>(v.data()), sizeof v);
    if (normals) o.write(reinterpret_cast<const char*>(t.normals[k].data()), sizeof t.normals[k]);
  }
  for (const Triangle& f : t.faces) {
    const std::uint8_t three = 3;
    o.write(reinterpret_cast<const char*>(&three), 1);
    const std::array<std::int32_t, 3> v{f.v[0], f.v[1], f.v[2]};
    o.write(reinterpret_cast<const char*>(v.data()), sizeof v);
  }
  return file.commit();
}

}  // namespace shore::scenes
