#pragma once
// Terrain step cases shared by shore_terrain_bench, shore_terrain_case and the shore-bench
// harness: a boot footprint, a rolling wheel and a towed wheel in dry sand.
// Header-only; link shore::terrain.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>

#include "shore/core/envelope.h"
#include "shore/terrain/terrain.h"

namespace shore::terrain::bench {

enum class TerrainCase {
  footprint,    ///< 0.28 m x 0.10 m sole pressed 2 cm over 10 substeps, lifted, 0.35 m stride
  wheel,        ///< D 0.8 m, b 0.2 m wheel rolling at 1 m/s, 3 cm deep; envelope clipped to 0.3 m x 0.2 m
  towed_wheel,  ///< D 0.8 m, b 0.3 m cylinder towed 2 m at 1 m/s, 7 cm deep, whole-body envelope window
};

struct TerrainCaseResult {
  std::string name;
  int threads = 1;
  bool forced_parallel = false;      ///< parallel_min_columns = 0 (split even small regions)
  int steps = 0;                     ///< measured steps
  double ms_per_step = 0.0;          ///< Terrain::step wall time
  double bearing_ms_per_step = 0.0;  ///< bearing wall time: bearing_offset (wheel) or bearing (towed wheel)
  double active_columns = 0.0;       ///< mean per step
  double erosion_passes = 0.0;       ///< mean per step
  double columns_per_second = 0.0;   ///< active columns / step time
  std::uint64_t state_hash = 0;      ///< Terrain::state_hash at the end (compare runs)
  double volume_error = 0.0;         ///< m^3, VolumeTotals::total() at the end (0 up to rounding)
  double bearing_sum = 0.0;          ///< N, sum of every bearing result (compare runs)
};

inline const char* case_name(TerrainCase c) {
  switch (c) {
    case TerrainCase::footprint:
      return "footprint";
    case TerrainCase::wheel:
      return "wheel";
    case TerrainCase::towed_wheel:
      return "towed_wheel";
  }
  return "?";
}

/// The towed wheel (the case the Bullet coupling runs): a horizontal cylinder, axis along
/// y, whose lowest line lies `sinkage` below the flat ground, moved `speed * substep` along
/// x each substep. The envelope window is the body's whole footprint seen from below
/// (2 radius x width), as the coupling rasterizes it, closed form, no Bullet.
struct TowedWheelCase {
  double cell = 0.01;            ///< m, column spacing
  double radius = 0.4;           ///< m
  double width = 0.3;            ///< m
  double sinkage = 0.07;         ///< m below the untouched ground (0)
  double speed = 1.0;            ///< m/s
  double substep = 1.0 / 240.0;  ///< s
  int steps = 480;               ///< substeps in all (2 m at the defaults)
  int measured = 100;            ///< the last `measured` substeps are timed
  int threads = 1;
  bool star = true;  ///< conservative collision surface, as the coupling uses
};

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

inline TerrainSettings sand_settings(double cell, int threads, bool forced_parallel) {
  TerrainSettings s;
  s.cell = cell;
  s.material = Material::sand();
  s.threads = threads;
  if (forced_parallel) s.parallel_min_columns = 0;
  return s;
}

inline void finish(TerrainCaseResult& r, const Terrain& t, double step_s, double bearing_s, double active,
                   double passes) {
  const double steps = r.steps > 0 ? r.steps : 1;
  r.ms_per_step = 1e3 * step_s / steps;
  r.bearing_ms_per_step = 1e3 * bearing_s / steps;
  r.active_columns = active / steps;
  r.erosion_passes = passes / steps;
  r.columns_per_second = step_s > 0 ? active / step_s : 0.0;
  r.state_hash = t.state_hash();
  r.volume_error = t.volume().total();
}

}  // namespace detail

/// Runs the towed wheel: Terrain::bearing on the envelope (as the coupling does once per
/// body per substep), then Terrain::step; times the last `measured` substeps.
inline TerrainCaseResult run_towed_wheel(const TowedWheelCase& c, bool forced_parallel = false) {
  Terrain t(detail::sand_settings(c.cell, c.threads, forced_parallel));
  TerrainCaseResult r;
  r.name = case_name(TerrainCase::towed_wheel);
  r.threads = c.threads;
  r.forced_parallel = forced_parallel;
  r.steps = std::min(c.measured, c.steps);
  using clock = std::chrono::steady_clock;
  double step_s = 0.0, bearing_s = 0.0, active = 0.0, passes = 0.0;
  const double axle_z = c.radius - c.sinkage;
  for (int k = 0; k < c.steps; ++k) {
    const double x = c.speed * c.substep * k;
    const EnvelopeRaster env = detail::wheel(t, x, axle_z, c.radius, c.width, c.radius);
    const Imprint im{&env, 0.0, c.star, c.speed, 0.0, 0.0};
    const auto t0 = clock::now();
    const Bearing b = t.bearing(env, 0.0);
    const auto t1 = clock::now();
    const StepReport rep = t.step({&im, 1});
    const auto t2 = clock::now();
    r.bearing_sum += b.capacity;
    if (k < c.steps - r.steps) continue;
    bearing_s += std::chrono::duration<double>(t1 - t0).count();
    step_s += std::chrono::duration<double>(t2 - t1).count();
    active += rep.active_columns;
    passes += rep.erosion_passes;
  }
  detail::finish(r, t, step_s, bearing_s, active, passes);
  return r;
}

/// Runs `steps` substeps of a case (after `warmup` unmeasured ones) and reports speed.
/// The towed wheel runs its default TowedWheelCase with `steps` measured at the end.
inline TerrainCaseResult run_terrain_case(TerrainCase c, int threads, int steps, bool forced_parallel = false,
                                          int warmup = 50) {
  if (c == TerrainCase::towed_wheel) {
    TowedWheelCase towed;
    towed.threads = threads;
    towed.measured = std::min(steps, towed.steps);
    return run_towed_wheel(towed, forced_parallel);
  }
  Terrain t(detail::sand_settings(0.01, threads, forced_parallel));
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
    if (c == TerrainCase::wheel) r.bearing_sum += t.bearing_offset(env, 4000.0);
    const auto t1 = clock::now();
    const StepReport rep = t.step({&im, 1});
    const auto t2 = clock::now();
    if (k < warmup) continue;
    bearing_s += std::chrono::duration<double>(t1 - t0).count();
    step_s += std::chrono::duration<double>(t2 - t1).count();
    active += rep.active_columns;
    passes += rep.erosion_passes;
  }
  detail::finish(r, t, step_s, bearing_s, active, passes);
  return r;
}

}  // namespace shore::terrain::bench
