#pragma once
// A perspective picture of simplified meshes (shore/mesh/chunked_mesh.h): z-buffered
// triangles shaded with the meshes' per-vertex normals, their edges drawn to show the level
// of detail. The headless counterpart of a real-time viewer: it draws what a renderer would
// upload, chunk by chunk.

#include <array>
#include <string>
#include <vector>

#include "shore/mesh/chunked_mesh.h"
#include "shore/scenes/image.h"

namespace shore::scenes {

struct MeshLayer {
  const mesh::ChunkedMesh* mesh = nullptr;
  Rgb colour{196, 178, 140};
};

struct PerspectiveView {
  mesh::Camera eye;                ///< where from; its field of view and viewport_height (the picture's height)
  std::array<double, 3> target{};  ///< m, the point at the picture's centre (not straight above or below the eye)
  int width = 0;                   ///< pixels; 0: 16 / 9 of the height
  bool edges = true;               ///< draw the triangles' edges
  std::string title;               ///< printed above the picture (empty: none)
};

/// The layers seen from the view. Throws shore::InvalidSetting for a bad view.
Image render_meshes(const std::vector<MeshLayer>& layers, const PerspectiveView& view);

}  // namespace shore::scenes
