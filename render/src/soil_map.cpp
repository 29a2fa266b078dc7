#include "soil_map.h"

#include <algorithm>
#include <string>

namespace shore::render {
namespace {

/// The drawn shader's palette (kTerrainFragment's uPalette): every index a map can hold.
constexpr int kPaletteSize = terrain::Terrain::kMaxMaterials;

void upload(const terrain::Terrain& soil, const GridRect& region, const GridRect& rect,
            std::vector<std::uint8_t>& staging) {
  staging.resize(static_cast<std::size_t>(rect.nx) * static_cast<std::size_t>(rect.ny));
  soil.material_indices(rect, staging);
  glTexSubImage2D(GL_TEXTURE_2D, 0, static_cast<GLint>(rect.i0 - region.i0), static_cast<GLint>(rect.j0 - region.j0),
                  rect.nx, rect.ny, GL_RED_INTEGER, GL_UNSIGNED_BYTE, staging.data());
}

}  // namespace

Eigen::Vector3d material_colour(const std::string& name, const RenderSettings& settings) {
  if (const auto it = settings.material_colours.find(name); it != settings.material_colours.end()) return it->second;
  if (name == "mud") return {0.45, 0.36, 0.27};
  if (name == "dried mud") return {0.58, 0.49, 0.38};
  if (name == "snow") return {0.93, 0.94, 0.97};
  if (name == "rigid") return {0.60, 0.60, 0.60};
  if (name == "gravel") return {0.56, 0.55, 0.52};
  return {0.80, 0.70, 0.52};  // sand, and any other name
}

void SoilMapTexture::update(const terrain::Terrain& soil, const GridRect& region) {
  const std::vector<GridRect> painted = soil.painted_since(seen_);
  seen_ = soil.generation();
  if (painted.empty() || too_large_) return;
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  if (!on()) {
    GLint largest = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &largest);
    if (region.nx > largest || region.ny > largest) {
      too_large_ = true;
      return;
    }
    region_ = region;
    GLuint id = 0;
    glGenTextures(1, &id);
    texture_ = gl::Texture(id);
    glBindTexture(GL_TEXTURE_2D, id);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R8UI, region.nx, region.ny, 0, GL_RED_INTEGER, GL_UNSIGNED_BYTE, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    upload(soil, region_, region_, staging_);
  } else {
    glBindTexture(GL_TEXTURE_2D, texture_.get());
    for (const GridRect& tile : painted)
      if (const GridRect r = intersection(tile, region_); r.nx > 0 && r.ny > 0) upload(soil, region_, r, staging_);
  }
  glBindTexture(GL_TEXTURE_2D, 0);
  gl::check("soil material map");
}

void SoilMapTexture::bind(GLuint program, int unit, const terrain::Terrain& soil,
                          const RenderSettings& settings) const {
  glUniform1i(glGetUniformLocation(program, "uMapOn"), on() ? 1 : 0);
  // Its own unit even when off: no other sampler type may share uMap's unit.
  glUniform1i(glGetUniformLocation(program, "uMap"), unit);
  if (!on()) return;
  glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(unit));
  glBindTexture(GL_TEXTURE_2D, texture_.get());
  glActiveTexture(GL_TEXTURE0);
  glUniform2i(glGetUniformLocation(program, "uMapOrigin"), static_cast<GLint>(region_.i0),
              static_cast<GLint>(region_.j0));
  std::vector<float> colours(3 * static_cast<std::size_t>(kPaletteSize), 0.0f);
  const auto palette = soil.palette();
  for (std::size_t k = 0; k < palette.size() && k < static_cast<std::size_t>(kPaletteSize); ++k) {
    const Eigen::Vector3d c = material_colour(palette[k].name, settings);
    for (int a = 0; a < 3; ++a) colours[3 * k + static_cast<std::size_t>(a)] = static_cast<float>(c[a]);
  }
  glUniform3fv(glGetUniformLocation(program, "uPalette"), static_cast<GLsizei>(palette.size()), colours.data());
}

}  // namespace shore::render
