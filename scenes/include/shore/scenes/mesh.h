#pragma once
// Triangle-mesh export of a height grid, counter-clockwise seen from above (normals up),
// world coordinates in metres, Z up. NaN heights drop the triangles that touch them. Either
// two triangles per cell (every column a vertex), or simplified (shore/mesh/chunked_mesh.h)
// so that every column lies within max_error of the mesh, with per-vertex normals.

#include <filesystem>

#include "shore/scenes/height_grid.h"

namespace shore::scenes {

struct MeshExport {
  bool simplified = false;   ///< false: every cell, two triangles; true: the simplified mesh
  double max_error = 0.001;  ///< m, simplified: largest vertical distance of a column from the mesh, >= 0
  /// Throws shore::InvalidSetting naming the field, the value and the allowed range.
  void validate() const;
};

/// Wavefront OBJ (text); simplified meshes carry vertex normals (vn). Returns the path;
/// throws shore::FileError if it cannot write.
std::filesystem::path write_obj(const std::filesystem::path& path, const HeightGrid& grid,
                                const MeshExport& options = {});
/// PLY, binary little-endian, float vertices (and normals when simplified) and int faces.
/// Returns the path.
std::filesystem::path write_ply(const std::filesystem::path& path, const HeightGrid& grid,
                                const MeshExport& options = {});

}  // namespace shore::scenes
