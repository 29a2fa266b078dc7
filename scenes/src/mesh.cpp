#include "shore/scenes/mesh.h"

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <system_error>
#include <vector>

#include "shore/core/error.h"

namespace shore::scenes {
namespace {

struct Triangle {
  std::array<int, 3> v;  // vertex indices (0-based, j * nx + i)
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

std::filesystem::path write_obj(const std::filesystem::path& path, const HeightGrid& g) {
  AtomicFile file(path, std::ios::out);
  std::ofstream& o = file.stream();
  o.precision(9);
  o << "# Shore height grid " << g.nx << " x " << g.ny << ", cell " << g.cell << " m, Z up\n";
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const double z = g.at(i, j);
      o << "v " << g.x(i) << ' ' << g.y(j) << ' ' << (std::isfinite(z) ? z : 0.0) << '\n';
    }
  for (const Triangle& t : triangulate(g)) o << "f " << t.v[0] + 1 << ' ' << t.v[1] + 1 << ' ' << t.v[2] + 1 << '\n';
  return file.commit();
}

std::filesystem::path write_ply(const std::filesystem::path& path, const HeightGrid& g) {
  const std::vector<Triangle> tris = triangulate(g);
  AtomicFile file(path, std::ios::out | std::ios::binary);
  std::ofstream& o = file.stream();
  o << "ply\nformat binary_little_endian 1.0\ncomment Shore height grid, metres, Z up\n"
    << "element vertex " << static_cast<long long>(g.nx) * g.ny
    << "\nproperty float x\nproperty float y\nproperty float z\n"
    << "element face " << tris.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  static_assert(std::endian::native == std::endian::little, "PLY writer assumes a little-endian machine");
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const double z = g.at(i, j);
      const std::array<float, 3> v{static_cast<float>(g.x(i)), static_cast<float>(g.y(j)),
                                   static_cast<float>(std::isfinite(z) ? z : 0.0)};
      o.write(reinterpret_cast<const char*>(v.data()), sizeof v);
    }
  for (const Triangle& t : tris) {
    const std::uint8_t three = 3;
    o.write(reinterpret_cast<const char*>(&three), 1);
    const std::array<std::int32_t, 3> v{t.v[0], t.v[1], t.v[2]};
    o.write(reinterpret_cast<const char*>(v.data()), sizeof v);
  }
  return file.commit();
}

}  // namespace shore::scenes
