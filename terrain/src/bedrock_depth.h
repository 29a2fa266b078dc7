#pragma once
// Private: how deep each column's soil reaches, by its palette entry. A rigid entry on a
// deforming terrain (a road, a rock) has its bedrock at its untouched top: nothing presses
// it, carries it off or erodes it below that (loose soil laid on it can go again), and the
// bearing and the contact take a column at bedrock as carrying anything. Every other entry
// shares the terrain's soil_depth (Terrain::set_palette checks it).

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "shore/terrain/material.h"

namespace shore::terrain {

class BedrockDepth {
 public:
  /// soil_depth for every index but the rigid entries of a palette whose entry 0 deforms.
  BedrockDepth(std::span<const Material> palette, double soil_depth) : uniform_(soil_depth) {
    if (palette.empty() || palette[0].rigid) return;
    bool any = false;
    for (const Material& m : palette) any = any || m.rigid;
    if (!any) return;  // the common case: no table, one depth
    by_index_.reserve(palette.size());
    for (const Material& m : palette) by_index_.push_back(m.rigid ? 0.0 : soil_depth);
  }
  /// True if every column's depth is the same (no rigid entry): the index need not be read.
  [[nodiscard]] bool uniform() const noexcept { return by_index_.empty(); }
  /// The depth of a column with palette index `index` (one that is on the palette).
  [[nodiscard]] double at(std::uint8_t index) const noexcept { return uniform() ? uniform_ : by_index_[index]; }
  /// The depth of column k of a tile's material array (empty: index 0).
  [[nodiscard]] double at(const std::vector<std::uint8_t>& material, std::size_t k) const noexcept {
    return uniform() || material.empty() ? uniform_ : by_index_[material[k]];
  }

 private:
  double uniform_;
  std::vector<double> by_index_;  ///< per palette index; empty: uniform_
};

}  // namespace shore::terrain
