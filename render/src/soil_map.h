#pragma once
// A drawn soil's material map as a texture: the palette index of every column of the drawn
// region (GL_R8UI, one texel per column), which the terrain fragment shader looks up per
// fragment at the nearest column, and the palette's colours (material_colour). Kept up to
// date from the terrain's repainted tiles (Terrain::painted_since). A soil that never
// painted gets no texture: it is drawn in its one material's colour, as before maps.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "gl_util.h"
#include "shore/core/grid_rect.h"
#include "shore/render/renderer.h"
#include "shore/terrain/terrain.h"

namespace shore::render {

class SoilMapTexture {
 public:
  /// Uploads what was repainted since the last call (the whole region on the first paint).
  /// A region larger than the GL's largest texture gets none (drawn in entry 0's colour).
  void update(const terrain::Terrain& soil, const GridRect& region);
  /// Sets the terrain program's map uniforms (uMapOn, and with a map uMap on texture unit
  /// `unit`, uMapOrigin, uPalette) and binds the texture.
  void bind(GLuint program, int unit, const terrain::Terrain& soil, const RenderSettings& settings) const;
  [[nodiscard]] bool on() const noexcept { return texture_.get() != 0; }

 private:
  gl::Texture texture_;
  GridRect region_;
  std::uint64_t seen_ = 0;  ///< the terrain's generation the map was last read at
  bool too_large_ = false;
  std::vector<std::uint8_t> staging_;
};

}  // namespace shore::render
