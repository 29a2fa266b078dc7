#include "shore/scenes/terrain_step_cases.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "shore/core/envelope.h"
#include "shore/terrain/terrain.h"

namespace shore::scenes {

using terrain::Bearing;
using terrain::Imprint;
using terrain::Material;
using terrain::StepReport;
using terrain::Terrain;
using terrain::TerrainSettings;

const char* terrain_case_name(TerrainCase c) {
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

namespace {

EnvelopeRaster sole(const Terrain& t, double x, double bottom) {
  EnvelopeRaster env;
  const std::int64_t i0 = t.column_i(x), j0 = t.column_j(-0.05);
  const int nx = 28, ny = 10;
  env.resize(i0 - 2, j0 - 2, nx + 4, ny + 4, false);
  for (std::int64_t j = j0; j < j0 + ny; ++j)
    for (std::int64_t i = i0; i < i0 + nx; ++i) env.lower[env.index(i, j)] = bottom;
  return env;
}

TerrainSettings sand_settings(double cell, int threads, bool forced_parallel) {
  TerrainSettings s;
  s.cell = cell;
  s.material = Material::sand();
  s.threads = threads;
  if (forced_parallel) s.parallel_min_columns = 0;
  return s;
}

using Clock = std::chrono::steady_clock;

/// What the measured steps add up to.
struct Totals {
  double step_s = 0.0, bearing_s = 0.0, active = 0.0, passes = 0.0;

  /// One measured step: bearing from t0 to t1, Terrain::step from t1 to t2.
  void add(Clock::time_point t0, Clock::time_point t1, Clock::time_point t2, const StepReport& rep) {
    bearing_s += std::chrono::duration<double>(t1 - t0).count();
    step_s += std::chrono::duration<double>(t2 - t1).count();
    active += rep.active_columns;
    passes += rep.erosion_passes;
  }

  void finish(TerrainCaseResult& r, const Terrain& t) const {
    const double steps = r.steps > 0 ? r.steps : 1;
    r.ms_per_step = 1e3 * step_s / steps;
    r.bearing_ms_per_step = 1e3 * bearing_s / steps;
    r.active_columns = active / steps;
    r.erosion_passes = passes / steps;
    r.columns_per_second = step_s > 0 ? active / step_s : 0.0;
    r.state_hash = t.state_hash();
    r.volume_error = t.volume().total();
  }
};

}  // namespace

EnvelopeRaster wheel_envelope(const Terrain& t, double x, double z, double r, double width, double half_window,
                              double y) {
  EnvelopeRaster env;
  const std::int64_t i0 = t.column_i(x - half_window), i1 = t.column_i(x + half_window);
  const std::int64_t j0 = t.column_j(y - width / 2), j1 = t.column_j(y + width / 2);
  env.resize(i0 - 1, j0 - 1, static_cast<int>(i1 - i0 + 3), static_cast<int>(j1 - j0 + 3), false);
  for (std::int64_t j = j0; j <= j1; ++j)
    for (std::int64_t i = i0; i <= i1; ++i) {
      const double dx = t.column_x(i) - x;
      if (std::abs(dx) < half_window && std::abs(t.column_y(j) - y) <= width / 2)
        env.lower[env.index(i, j)] = z - std::sqrt(r * r - dx * dx);
    }
  return env;
}

TerrainCaseResult run_towed_wheel(const TowedWheelCase& c, bool forced_parallel) {
  Terrain t(sand_settings(c.cell, c.threads, forced_parallel));
  TerrainCaseResult r;
  r.name = terrain_case_name(TerrainCase::towed_wheel);
  r.threads = c.threads;
  r.forced_parallel = forced_parallel;
  r.steps = std::min(c.measured, c.steps);
  Totals totals;
  const double axle_z = c.radius - c.sinkage;
  for (int k = 0; k < c.steps; ++k) {
    const double x = c.speed * c.substep * k;
    const EnvelopeRaster env = wheel_envelope(t, x, axle_z, c.radius, c.width, c.radius);
    const Imprint im{&env, 0.0, c.star, {c.speed, 0.0, 0.0}};
    const auto t0 = Clock::now();
    const Bearing b = t.bearing(env, 0.0);
    const auto t1 = Clock::now();
    const StepReport rep = t.step({&im, 1});
    const auto t2 = Clock::now();
    r.bearing_sum += b.capacity;
    if (k >= c.steps - r.steps) totals.add(t0, t1, t2, rep);
  }
  totals.finish(r, t);
  return r;
}

TerrainCaseResult run_terrain_case(TerrainCase c, int threads, int steps, bool forced_parallel, int warmup) {
  if (c == TerrainCase::towed_wheel) {
    TowedWheelCase towed;
    towed.threads = threads;
    towed.measured = std::min(steps, towed.steps);
    return run_towed_wheel(towed, forced_parallel);
  }
  Terrain t(sand_settings(0.01, threads, forced_parallel));
  TerrainCaseResult r;
  r.name = terrain_case_name(c);
  r.threads = threads;
  r.forced_parallel = forced_parallel;
  r.steps = steps;
  Totals totals;
  const double h = 1.0 / 240.0;
  for (int k = 0; k < warmup + steps; ++k) {
    EnvelopeRaster env;
    if (c == TerrainCase::footprint) {
      const int phase = k % 20, stride = k / 20;
      const double depth = phase < 10 ? 0.02 * (phase + 1) / 10.0 : 0.02 - 0.03 * (phase - 9) / 10.0;
      env = sole(t, 0.35 * stride, -depth);
    } else {
      const double x = 1.0 * h * k;
      env = wheel_envelope(t, x, 0.4 - 0.03, 0.4, 0.2, 0.15);
    }
    const Imprint im{&env};
    const auto t0 = Clock::now();
    if (c == TerrainCase::wheel) r.bearing_sum += t.bearing_offset(env, 4000.0);
    const auto t1 = Clock::now();
    const StepReport rep = t.step({&im, 1});
    const auto t2 = Clock::now();
    if (k >= warmup) totals.add(t0, t1, t2, rep);
  }
  totals.finish(r, t);
  return r;
}

}  // namespace shore::scenes
