// water_steps: steps one water surface a given number of times and prints its state hash,
// for counting the kernel's instructions (callgrind, perf stat) where timings are noisy:
// the cost per node-step is the difference of two runs with different step counts.
//
//   water_steps <3d|vertical> <nodes per side> <tile> <steps> [sleep|dense] [automatic|generic|avx2|avx512|unfused]
//   water_steps lake <tile> <substeps>
//   water_steps asleep <tile> <substeps>
//   water_steps resting <nodes per side> <steps>
//   water_steps timed <3d|vertical> <nodes per side> <threads> <steps per round> <rounds>
//
// The paper's lattice at dt 0.3 with a drop in the middle (the benchmark's kernel case);
// `sleep` turns sleeping tiles on (off by default, as in shore-bench's kernel cases); the
// last argument picks the kernel (SurfaceSettings::kernel; unfused: the row-pass kernel the
// fused one replaced, generic instruction set). `lake`: the benchmark's 1 km lake at 10 cm
// (vertical-only, 2 m deep, open edges, 1/60 s substeps) with a source of waves moving at
// 2 m/s from the middle and the tiles around it kept awake, as a boat's coupling does.
// `asleep`: the same lake woken in 16 places (as shore-bench's asleep lake), stepped until
// every tile sleeps again, then stepped `substeps` more times with nothing awake: the
// difference of two such runs is what a fully asleep lake costs per substep.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <vector>

#include "shore/water/disturbance.h"
#include "shore/water/surface.h"

using namespace shore;

namespace {
water::SurfaceSettings lake_settings(int tile) {
  water::PhysicalParameters p;
  p.cell = 0.1;
  p.depth = 2.0;
  water::SurfaceSettings s = water::SurfaceSettings::physical(p, 10001, 10001);
  s.mode = water::SurfaceMode::vertical_only;
  s.boundary = water::Boundary::open;
  s.threads = 1;
  s.sleep.tile = tile;
  return s;
}

int lake(int tile, int substeps) {
  water::Surface surf(lake_settings(tile));
  const double dt = 1.0 / 60;
  long long node_substeps = 0;    // awake nodes summed over the substeps (tile_stats: a pass over the tiles)
  long long kernel_substeps = 0;  // the surface's own substeps (the guard may split a step)
  for (int k = 0; k < substeps; ++k) {
    const double x = 500.0 + 2.0 * dt * k, y = 500.0;
    surf.wake(x - 1.5, y - 1.0, x + 1.5, y + 1.0);
    surf.disturb(water::Disturbance::point_velocity(x, y, 0.3, -0.05));
    node_substeps += surf.tile_stats().awake_nodes;
    kernel_substeps += surf.step(dt).substeps;
  }
  const water::TileStats st = surf.tile_stats();
  std::printf("%016llx awake nodes %lld, awake node-substeps %lld, kernel substeps %lld\n",
              static_cast<unsigned long long>(surf.state_hash()), static_cast<long long>(st.awake_nodes), node_substeps,
              kernel_substeps);
  return 0;
}

int asleep(int tile, int substeps) {
  water::Surface surf(lake_settings(tile));
  const double dt = 1.0 / 60, side = 1000.0;
  for (int k = 0; k < 16; ++k) {
    const double x = (0.1 + 0.05 * k) * side, y = (0.9 - 0.05 * k) * side;
    surf.wake(x, y, x + 10.0, y + 10.0);
  }
  int settle = 0;
  for (; settle < 10000 && surf.tile_stats().awake > 0; ++settle) surf.step(dt);
  if (surf.tile_stats().awake > 0) {
    std::fprintf(stderr, "the lake did not settle in %d substeps\n", settle);
    return 1;
  }
  for (int k = 0; k < substeps; ++k) surf.step(dt);
  const water::TileStats st = surf.tile_stats();
  std::printf("%016llx settled in %d substeps, tiles created %lld\n",
              static_cast<unsigned long long>(surf.state_hash()), settle, static_cast<long long>(st.created));
  return 0;
}
}  // namespace

/// The benchmark's 3-D kernel case (256 x 256, drop in the middle, dt 0.3, sleeping off): the
/// fraction of nodes whose velocity is exactly 0 after a number of steps, i.e. whose
/// position the step leaves unchanged (a spring between two such nodes keeps its length).
int resting(int n, int steps) {
  water::SurfaceSettings s;
  s.nx = s.ny = n;
  s.lattice = water::LatticeParameters::paper();
  s.threads = 1;
  s.sleep.enabled = false;
  water::Surface surf(s);
  surf.disturb(water::Disturbance::point_height(0.5 * (n - 1), 0.5 * (n - 1), 3.0, 1.0));
  for (int k = 1; k <= steps; ++k) {
    surf.step(0.3);
    if (k % (steps / 10 > 0 ? steps / 10 : 1) != 0) continue;
    long still = 0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) still += surf.velocity(i, j).squaredNorm() == 0.0;
    std::printf("step %d: %.4f of the nodes did not move\n", k, double(still) / (double(n) * n));
  }
  return 0;
}

/// The benchmark's 3-D (or vertical-only) kernel case on n x n nodes with `threads`
/// threads: prints the wall time per step of `steps` steps after two untimed ones (as
/// shore-bench times it), best and median of `rounds` rounds, without the creation's page
/// faults that dominate a whole run's time at 2048 x 2048.
int timed(bool vertical, int n, int threads, int steps, int rounds) {
  water::SurfaceSettings s;
  s.nx = s.ny = n;
  s.lattice = water::LatticeParameters::paper();
  s.threads = threads;
  s.mode = vertical ? water::SurfaceMode::vertical_only : water::SurfaceMode::full_3d;
  s.sleep.enabled = false;
  water::Surface surf(s);
  surf.disturb(water::Disturbance::point_height(0.5 * (n - 1), 0.5 * (n - 1), 3.0, 1.0));
  surf.step(0.3);
  surf.step(0.3);
  std::vector<double> ms, cpu;
  int substeps = 0;
  for (int r = 0; r < rounds; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    for (int k = 0; k < steps; ++k) substeps += surf.step(0.3).substeps;
    cpu.push_back(1e3 * double(std::clock() - c0) / CLOCKS_PER_SEC / steps);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / steps);
  }
  std::sort(ms.begin(), ms.end());
  std::sort(cpu.begin(), cpu.end());
  std::printf(
      "%016llx ms per step: wall best %.3f median %.3f, cpu (all threads) best %.3f median %.3f (%.2f substeps a "
      "step)\n",
      static_cast<unsigned long long>(surf.state_hash()), ms.front(), ms[ms.size() / 2], cpu.front(),
      cpu[cpu.size() / 2], double(substeps) / (steps * rounds));
  return 0;
}

int main(int argc, char** argv) {
  if (argc == 7 && std::strcmp(argv[1], "timed") == 0)
    return timed(std::strcmp(argv[2], "vertical") == 0, std::atoi(argv[3]), std::atoi(argv[4]), std::atoi(argv[5]),
                 std::atoi(argv[6]));
  if (argc == 4 && std::strcmp(argv[1], "resting") == 0) return resting(std::atoi(argv[2]), std::atoi(argv[3]));
  if (argc == 4 && std::strcmp(argv[1], "lake") == 0) return lake(std::atoi(argv[2]), std::atoi(argv[3]));
  if (argc == 4 && std::strcmp(argv[1], "asleep") == 0) return asleep(std::atoi(argv[2]), std::atoi(argv[3]));
  if (argc < 5) {
    std::fprintf(stderr, "usage: %s <3d|vertical> <nodes per side> <tile> <steps> [sleep|dense] [kernel]\n", argv[0]);
    return 2;
  }
  const bool vertical = std::strcmp(argv[1], "vertical") == 0;
  const int n = std::atoi(argv[2]), tile = std::atoi(argv[3]), steps = std::atoi(argv[4]);
  water::SurfaceSettings s;  // as scenes::kernel_case_settings: the paper's lattice, one thread
  s.nx = s.ny = n;
  s.lattice = water::LatticeParameters::paper();
  s.threads = 1;
  s.mode = vertical ? water::SurfaceMode::vertical_only : water::SurfaceMode::full_3d;
  s.sleep.tile = tile;
  s.sleep.enabled = argc > 5 && std::strcmp(argv[5], "sleep") == 0;
  if (argc > 6) {
    const char* k = argv[6];
    s.kernel = std::strcmp(k, "generic") == 0   ? water::KernelChoice::generic
               : std::strcmp(k, "avx2") == 0    ? water::KernelChoice::avx2
               : std::strcmp(k, "avx512") == 0  ? water::KernelChoice::avx512
               : std::strcmp(k, "unfused") == 0 ? water::KernelChoice::unfused
                                                : water::KernelChoice::automatic;
  }
  water::Surface surf(s);
  surf.disturb(water::Disturbance::point_height(0.5 * (n - 1), 0.5 * (n - 1), 3.0, 1.0));
  for (int k = 0; k < steps; ++k) surf.step(0.3);
  std::printf("%016llx\n", static_cast<unsigned long long>(surf.state_hash()));
  return 0;
}
