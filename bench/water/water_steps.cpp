// water_steps: steps one water surface a given number of times and prints its state hash,
// for counting the kernel's instructions (callgrind, perf stat) where timings are noisy:
// the cost per node-step is the difference of two runs with different step counts.
//
//   water_steps <3d|vertical> <nodes per side> <tile> <steps> [sleep|dense] [automatic|generic|avx2|unfused]
//
// The paper's lattice at dt 0.3 with a drop in the middle (the benchmark's kernel case);
// `sleep` turns sleeping tiles on (off by default, as in shore-bench's kernel cases); the
// last argument picks the kernel (SurfaceSettings::kernel; unfused: the row-pass kernel the
// fused one replaced, generic instruction set).
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "shore/scenes/water_kernel_cases.h"
#include "shore/water/disturbance.h"
#include "shore/water/surface.h"

using namespace shore;

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: %s <3d|vertical> <nodes per side> <tile> <steps> [sleep|dense] [kernel]\n", argv[0]);
    return 2;
  }
  const bool vertical = std::strcmp(argv[1], "vertical") == 0;
  const int n = std::atoi(argv[2]), tile = std::atoi(argv[3]), steps = std::atoi(argv[4]);
  const auto variant = vertical ? scenes::KernelVariant::vertical_only : scenes::KernelVariant::fast_3d;
  water::SurfaceSettings s = scenes::kernel_case_settings(variant, n, 1);
  s.sleep.tile = tile;
  s.sleep.enabled = argc > 5 && std::strcmp(argv[5], "sleep") == 0;
  if (argc > 6) {
    const char* k = argv[6];
    s.kernel = std::strcmp(k, "generic") == 0   ? water::KernelChoice::generic
               : std::strcmp(k, "avx2") == 0    ? water::KernelChoice::avx2
               : std::strcmp(k, "unfused") == 0 ? water::KernelChoice::unfused
                                                : water::KernelChoice::automatic;
  }
  water::Surface surf(s);
  surf.disturb(water::Disturbance::point_height(0.5 * (n - 1), 0.5 * (n - 1), 3.0, 1.0));
  for (int k = 0; k < steps; ++k) surf.step(0.3);
  std::printf("%016llx\n", static_cast<unsigned long long>(surf.state_hash()));
  return 0;
}
