#pragma once
// The server of the soil delta fuzz target and its seeds: soil with small tiles pressed
// twice, the same way every time, so a delta encoded from it by shore-fuzz-corpus applies
// to a replica built in the fuzzer (shore/terrain/soil_delta.h). The replica first applies
// first_snapshot() (server generation 0 to after the first press), then the input.

#include <cstdint>
#include <stdexcept>
#include <vector>

#include "shore/core/envelope.h"
#include "shore/terrain/soil_delta.h"
#include "shore/terrain/terrain.h"

namespace shore::fuzz {

inline terrain::TerrainSettings delta_soil() {
  terrain::TerrainSettings s;
  s.tile_columns = 4;
  s.cell = 0.05;
  s.max_erosion_passes = 1;
  s.threads = 1;
  return s;
}

/// A flat press 2 cm into the soil over columns [i0, i0 + 3) x [1, 4).
inline void press_at(terrain::Terrain& t, int i0) {
  shore::EnvelopeRaster env;
  env.resize(i0, 1, 3, 3, false);
  for (double& v : env.lower) v = -0.02;
  const terrain::Imprint im{&env};
  t.step({&im, 1});
}

class DeltaServer {
 public:
  DeltaServer() : soil_(delta_soil()) {
    press_at(soil_, 1);
    first_generation_ = soil_.generation();
    first_ = terrain::SoilDelta::encode(soil_, 0, {});
  }
  /// The second press, for the seeds: deltas from first_generation() (or 0) to after it.
  void press_again() { press_at(soil_, 3); }
  /// A palette and a painted map, for the seeds of deltas that carry the map (version 3).
  void paint() {
    terrain::Material gravel = terrain::Material::sand();
    gravel.name = "gravel";
    gravel.bekker_kphi *= 20.0;
    soil_.set_palette({soil_.settings().material, terrain::Material::mud(), gravel});
    soil_.paint_rect({0, 0, 6, 3}, 2);
    soil_.paint_disc(0.2, 0.2, 0.08, 1);
  }
  /// After paint(): lower layers under the gravel and the mud, for the seeds of deltas that
  /// carry layers (version 5).
  void layer() {
    soil_.paint_layer_rect({0, 0, 6, 3}, 1, 0.01);
    soil_.paint_layer_disc(0.2, 0.2, 0.08, 0, 0.005);
  }
  /// A 3 x 3 column plate slid 1 mm deep along x at 1 m/s, then lifted, its clinging soil
  /// stepped every second step (Imprint::cling_every 2): left after a step that skipped it
  /// (at most 9 steps),
  /// for the seeds of exact deltas that carry the bodies' last clinging steps (version 6).
  void slide() {
    // 4 steps on the soil, then lifted, until a step skipped its soil (the soil's step count
    // is not public: the format an exact delta chooses tells).
    for (int k = 0; k < 7 || terrain::SoilDelta::encode(soil_, 0, {.quantum = 0.0})[8] != 6; ++k) {
      if (k > 9) throw std::runtime_error("the delta server's plate never rested between two clinging steps");
      shore::EnvelopeRaster env;
      env.resize(k, 5, 3, 3, false);
      for (double& v : env.lower) v = k < 4 ? -0.001 : 0.05;
      terrain::Imprint im{&env};
      im.velocity.x = 1.0;
      im.centre.x = soil_.column_x(k + 1), im.centre.y = soil_.column_y(6), im.centre.z = k < 4 ? 0.05 : 0.1;
      im.key = 6;
      im.cling_every = 2;
      soil_.step({&im, 1}, 1.0 / 240);
    }
  }
  [[nodiscard]] const terrain::Terrain& soil() const { return soil_; }
  [[nodiscard]] std::uint64_t first_generation() const { return first_generation_; }
  /// Generation 0 to first_generation(), quantised by the default 1e-4 m.
  [[nodiscard]] const std::vector<unsigned char>& first_snapshot() const { return first_; }

 private:
  terrain::Terrain soil_;
  std::uint64_t first_generation_ = 0;
  std::vector<unsigned char> first_;
};

}  // namespace shore::fuzz
