#pragma once
// Triangle-mesh export of a height grid: two triangles per cell, counter-clockwise seen
// from above (normals up), world coordinates in metres, Z up. NaN heights drop the
// triangles that touch them.

#include <filesystem>

#include "shore/scenes/height_grid.h"

namespace shore::scenes {

/// Wavefront OBJ (text). Returns the path; throws shore::FileError if it cannot write.
std::filesystem::path write_obj(const std::filesystem::path& path, const HeightGrid& grid);
/// PLY, binary little-endian, float vertices and int faces. Returns the path.
std::filesystem::path write_ply(const std::filesystem::path& path, const HeightGrid& grid);

}  // namespace shore::scenes
