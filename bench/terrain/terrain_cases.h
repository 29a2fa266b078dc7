#pragma once
// Terrain step cases shared by shore_terrain_bench and the shore-bench harness: a boot
// footprint and a rolling wheel at 1 cm in dry sand. Header-only; link shore::terrain.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>

#include "shore/core/envelope.h"
#include "shore/terrain/terrain.h"

namespace shore::terrain::bench {

enum class TerrainCase {
  footprint,  ///< 0.28 m x 0.10 m sole pressed 2 cm over 10 substeps, lifted, 0.35 m stride
  wheel,      ///< D 0.8 m, b 0.2 m wheel rolling at 1 m/s, 3 cm deep; envelope clipped to 0.3 m x 0.2 m
};

struct TerrainCaseResult {
  std::string name;
  int threads = 1;
  bool forced_parallel = false;  ///< parallel_min_columns = 0 (split even small regions)
  int steps = 0;
  double ms_per_step = 0.0;          ///< Terrain::step wall time
  double bearing_ms_per_step = 0.0;  ///< Terrain::bearing_offset wall time (wheel load 4 kN)
  double active_columns = 0.0;       ///< mean per step
  double erosion_passes = 0.0;       ///< mean per step
  double columns_per_second = 0.0;   ///< active columns / step time
};

inline const char* case_name(TerrainCase c) { return c == TerrainCase::footprint ? "footprint" : "wheel"; }

namespace detail {

inline EnvelopeRaster sole(const Terrain& t, double x, double bottom) {
  EnvelopeRaster env;
  const std::int64_t i0 = t.column_i(x), j0 = t.column_j(-0.05);
  const int nx = 28, ny = 10;
  env.resize(i0 - 2, j0 - 2, nx + 4, ny + 4, false);
  for (std::int64_t j = j0; j < j0 + ny; ++j)
    for (std::int64_t i = i0; i < i0 + nx; ++i) env.lower[env.index(i, j)] = bottom;
  return env;
}

// Lowest point of a cylinder (axis along y, radius r, axle at (x, 0, z)) per column,
// clipped to |column x - axle x| < half_window.
inline EnvelopeRaster wheel(const Terrain& t, double x, double z, double r, double width, double half_window) {
  EnvelopeRaster env;
  const std::int64_t i0 = t.column_i(x - half_window), i1 = t.column_i(x + half_window);
  const std::int64_t j0 = t.column_j(-width / 2), j1 = t.column_j(width / 2);
  env.resize(i0 - 1, j0 - 1, static_cast<int>(i1 - i0 + 3), static_cast<int>(j1 - j0 + 3), false);
  for (std::int64_t j = j0; j <= j1; ++j)
    for (std::int64_t i = i0; i <= i1; ++i) {
      const double dx = t.column_x(i) - x;
      if (std::abs(dx) < half_window && std::abs(t.column_y(j)) <= width / 2)
        env.lower[env.index(i, j)] = z - std::sqrt(r * r - dx * dx);
    }
  return env;
}

}  // namespace detail

/// Runs `steps` substeps of a case (after `warmup` unmeasured ones) and reports speed.
inline TerrainCaseResult run_terrain_case(TerrainCase c, int threads, int steps, bool forced_parallel = false,
                                          int warmup = 50) {
  TerrainSettings s;
  s.material = Material::sand();
  s.threads = threads;
  if (forced_parallel) s.parallel_min_columns = 0;
  Terrain t(s);
  TerrainCaseResult r;
  r.name = case_name(c);
  r.threads = threads;
  r.forced_parallel = forced_parallel;
  r.steps = steps;
  using clock = std::chrono::steady_clock;
  double step_s = 0.0, bearing_s = 0.0, active = 0.0, passes = 0.0;
  const double h = 1.0 / 240.0;
  for (int k = 0; k < warmup + steps; ++k) {
    EnvelopeRaster env;
    if (c == TerrainCase::footprint) {
      const int phase = k % 20, stride = k / 20;
      const double depth = phase < 10 ? 0.02 * (phase + 1) / 10.0 : 0.02 - 0.03 * (phase - 9) / 10.0;
      env = detail::sole(t, 0.35 * stride, -depth);
    } else {
      const double x = 1.0 * h * k;
      env = detail::wheel(t, x, 0.4 - 0.03, 0.4, 0.2, 0.15);
    }
    const Imprint im{&env};
    const auto t0 = clock::now();
    if (c == TerrainCase::wheel) (void)t.bearing_offset(env, 4000.0);
    const auto t1 = clock::now();
    const StepReport rep = t.step({&im, 1});
    const auto t2 = clock::now();
    if (k < warmup) continue;
    bearing_s += std::chrono::duration<double>(t1 - t0).count();
    step_s += std::chrono::duration<double>(t2 - t1).count();
    active += rep.active_columns;
    passes += rep.erosion_passes;
  }
  r.ms_per_step = 1e3 * step_s / steps;
  r.bearing_ms_per_step = 1e3 * bearing_s / steps;
  r.active_columns = active / steps;
  r.erosion_passes = passes / steps;
  r.columns_per_second = step_s > 0 ? active / step_s : 0.0;
  return r;
}

}  // namespace shore::terrain::bench
