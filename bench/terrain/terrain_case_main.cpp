// shore_terrain_case: runs one terrain case once and prints its numbers, for quick
// before/after comparisons and for callgrind (one run, no benchmark repetitions).
//   shore_terrain_case towed_wheel [cell_m] [threads] [steps] [sinkage_m] [star 0|1]
//   shore_terrain_case footprint|wheel [threads] [steps]
//   shore_terrain_case material_map one|map [steps] [timed]
//     shore-bench's terrain.material_map_cost_ratio case, one of its two terrains: the
//     step-alone wheel on one material or on the four-entry map of sand copies painted in
//     half-metre stripes (timed: also the wall time of Terrain::step alone per step, after
//     20 steps' warm-up, as the bench times it); callgrind it with
//     --toggle-collect='shore::terrain::Terrain::step(std::span<shore::terrain::Imprint const,
//     18446744073709551615ul>)'
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "shore/scenes/terrain_step_cases.h"
#include "shore/terrain/terrain.h"

namespace tb = shore::scenes;

namespace {

void print(const tb::TerrainCaseResult& r, double cell) {
  std::printf(
      "%s cell %.3f m threads %d: %.4f ms/step (last %d steps), bearing %.4f ms, active columns %.0f, "
      "erosion passes %.2f, hash %016llx, volume error %.3e m^3, bearing sum %.17g\n",
      r.name.c_str(), cell, r.threads, r.ms_per_step, r.steps, r.bearing_ms_per_step, r.active_columns,
      r.erosion_passes, static_cast<unsigned long long>(r.state_hash), r.volume_error, r.bearing_sum);
}

// The bench's material_map_cost terrains (bench/harness/sweeps/terrain.cpp), stepped under
// its wheel; prints the state hash.
int material_map(bool painted, int steps, bool timed) {
  shore::terrain::TerrainSettings s;
  s.cell = 0.01;
  s.threads = 1;
  shore::terrain::Terrain t(s);
  if (painted) {
    std::vector<shore::terrain::Material> palette(4, shore::terrain::Material::sand());
    for (int k = 1; k < 4; ++k) palette[static_cast<std::size_t>(k)].name = "sand " + std::to_string(k);
    t.set_palette(palette);
    for (int k = 0; k < 8; ++k) {
      t.paint_rect({k * 50, -20, 50, 20}, k % 4);
      t.paint_rect({k * 50, 0, 50, 20}, (k + 1) % 4);
    }
  }
  double seconds = 0.0;
  constexpr int kWarmup = 20;
  for (int k = 0; k < steps; ++k) {
    const shore::EnvelopeRaster env = tb::wheel_envelope(t, k / 240.0, 0.4 - 0.03, 0.4, 0.2, 0.15);
    const shore::terrain::Imprint im{&env};
    (void)t.bearing_offset(env, 4000.0);
    const auto t0 = std::chrono::steady_clock::now();
    t.step({&im, 1});
    if (k >= kWarmup) seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  std::printf("material map (%s) %d steps: hash %016llx\n", painted ? "four entries" : "one material", steps,
              static_cast<unsigned long long>(t.state_hash()));
  if (timed && steps > kWarmup) std::printf("step %.5f ms\n", 1e3 * seconds / (steps - kWarmup));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string which = argc > 1 ? argv[1] : "towed_wheel";
  if (which == "material_map")
    return material_map(argc > 2 && std::string(argv[2]) == "map", argc > 3 ? std::atoi(argv[3]) : 220,
                        argc > 4 && std::string(argv[4]) == "timed");
  if (which == "towed_wheel") {
    tb::TowedWheelCase c;
    if (argc > 2) c.cell = std::atof(argv[2]);
    if (argc > 3) c.threads = std::atoi(argv[3]);
    if (argc > 4) c.steps = std::atoi(argv[4]);
    if (argc > 5) c.sinkage = std::atof(argv[5]);
    if (argc > 6) c.star = std::atoi(argv[6]) != 0;
    print(tb::run_towed_wheel(c), c.cell);
    return 0;
  }
  const tb::TerrainCase kind = which == "footprint" ? tb::TerrainCase::footprint : tb::TerrainCase::wheel;
  const int threads = argc > 2 ? std::atoi(argv[2]) : 1;
  const int steps = argc > 3 ? std::atoi(argv[3]) : 400;
  print(tb::run_terrain_case(kind, threads, steps), 0.01);
  return 0;
}
