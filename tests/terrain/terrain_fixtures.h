#pragma once
// Analytic body envelopes and grid measurements shared by the terrain tests.

#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "shore/core/envelope.h"
#include "shore/core/hash.h"
#include "shore/terrain/terrain.h"

namespace shore::terrain::testing {

/// Sand on 2 cm columns in small tiles (16 x 16), one thread: rectangles and tiles stay
/// few for the checkpoint and delta tests.
inline TerrainSettings coarse_sand() {
  TerrainSettings s;
  s.cell = 0.02;
  s.tile_columns = 16;
  s.threads = 1;
  return s;
}

/// Lowest point of a sphere (centre cx, cy, cz, radius r) over every column it covers.
inline EnvelopeRaster sphere_envelope(const Terrain& t, double cx, double cy, double cz, double r) {
  EnvelopeRaster env;
  const std::int64_t i0 = t.column_i(cx - r) - 1, i1 = t.column_i(cx + r) + 1;
  const std::int64_t j0 = t.column_j(cy - r) - 1, j1 = t.column_j(cy + r) + 1;
  env.resize(i0, j0, static_cast<int>(i1 - i0 + 1), static_cast<int>(j1 - j0 + 1), false);
  for (std::int64_t j = j0; j <= j1; ++j)
    for (std::int64_t i = i0; i <= i1; ++i) {
      const double dx = t.column_x(i) - cx, dy = t.column_y(j) - cy;
      const double rr = dx * dx + dy * dy;
      if (rr < r * r) env.lower[env.index(i, j)] = cz - std::sqrt(r * r - rr);
    }
  return env;
}

/// Flat-bottomed box: columns i in [i0, i0 + nx), j in [j0, j0 + ny) at height bottom.
inline EnvelopeRaster box_envelope(std::int64_t i0, std::int64_t j0, int nx, int ny, double bottom) {
  EnvelopeRaster env;
  env.resize(i0 - 2, j0 - 2, nx + 4, ny + 4, false);  // a little uncovered border, as a rasterizer gives
  for (std::int64_t j = j0; j < j0 + ny; ++j)
    for (std::int64_t i = i0; i < i0 + nx; ++i) env.lower[env.index(i, j)] = bottom;
  return env;
}

/// A 3 x 3 column plate sliding 1 mm deep along x at 1 m/s from column (i0, j0), one column
/// a step, its clinging soil stepped every second step; from step 6 on it is lifted and
/// sheds what clings to it.
inline void slide_clinging_plate(Terrain& t, int step, std::int64_t i0, std::int64_t j0, std::uint64_t key) {
  const bool lifted = step >= 6;
  const EnvelopeRaster env = box_envelope(i0 + step, j0, 3, 3, lifted ? 0.05 : -0.001);
  Imprint im;
  im.envelope = &env;
  im.velocity.x = 1.0;
  im.centre.x = t.column_x(i0 + 1 + step), im.centre.y = t.column_y(j0 + 1), im.centre.z = lifted ? 0.1 : 0.05;
  im.key = key;
  im.cling_every = 2;
  t.step(std::span<const Imprint>(&im, 1), 1.0 / 240);
}

/// Volume (m^3) above and below the base over a rectangle of columns.
struct GroundChange {
  double raised = 0.0;   ///< sum of (h - base) where positive
  double lowered = 0.0;  ///< sum of (base - h) where positive
};

inline GroundChange ground_change(const Terrain& t, std::int64_t i0, std::int64_t j0, int nx, int ny) {
  GroundChange g;
  const double a = t.settings().cell * t.settings().cell;
  for (std::int64_t j = j0; j < j0 + ny; ++j)
    for (std::int64_t i = i0; i < i0 + nx; ++i) {
      const double d = t.height(i, j) - t.base_height(i, j);
      if (d > 0)
        g.raised += d * a;
      else
        g.lowered -= d * a;
    }
  return g;
}

/// Spherical cap of a sphere of radius r cut at depth z.
inline double cap_volume(double r, double z) { return std::numbers::pi * z * z * (r - z / 3.0); }

/// The message of the E a call throws, or "(no exception)".
template <class E>
std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return "(no exception)";
}

inline bool mentions(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// Lowest line of a wheel (axis along y, diameter D, width b) whose bottom is at `bottom`,
/// axle at x.
inline EnvelopeRaster wheel(const Terrain& t, double x, double bottom, double D, double b) {
  const double r = D / 2;
  EnvelopeRaster env;
  const std::int64_t i0 = t.column_i(x - r), i1 = t.column_i(x + r);
  const std::int64_t j0 = t.column_j(-b / 2), j1 = t.column_j(b / 2);
  env.resize(i0 - 1, j0 - 1, static_cast<int>(i1 - i0 + 3), static_cast<int>(j1 - j0 + 3), false);
  for (std::int64_t j = j0; j <= j1; ++j)
    for (std::int64_t i = i0; i <= i1; ++i) {
      const double dx = t.column_x(i) - x;
      if (std::abs(dx) < r && std::abs(t.column_y(j)) <= b / 2)
        env.lower[env.index(i, j)] = bottom + r - std::sqrt(r * r - dx * dx);
    }
  return env;
}

/// A wheel (axis along y, centred on y = 0) of radius r and width w, centre at (x, z):
/// its lowest point over each column it covers (the spray tests' wheel, set by its centre).
inline EnvelopeRaster wheel_by_centre(const Terrain& t, double x, double z, double r, double w) {
  EnvelopeRaster env;
  const std::int64_t i0 = t.column_i(x - r) - 1, i1 = t.column_i(x + r) + 1;
  const std::int64_t j0 = t.column_j(-w / 2), j1 = t.column_j(w / 2);
  env.resize(i0, j0, static_cast<int>(i1 - i0 + 1), static_cast<int>(j1 - j0 + 1), false);
  for (std::int64_t j = j0; j <= j1; ++j)
    for (std::int64_t i = i0; i <= i1; ++i) {
      const double dx = t.column_x(i) - x;
      if (std::abs(dx) < r) env.lower[env.index(i, j)] = z - std::sqrt(r * r - dx * dx);
    }
  return env;
}

/// A wheel carrying W towed at 1 m/s for 2 m (1/240 s steps): each step its bottom goes to
/// the depth below the untouched ground at which the soil carries W, and it presses there.
/// Returns the depth at each step.
inline std::vector<double> tow(Terrain& t, double W, double D, double b) {
  std::vector<double> depth;
  for (int k = 0; k < 480; ++k) {
    const double x = k / 240.0;
    const double d = t.bearing_offset(wheel(t, x, 0.0, D, b), W);
    const EnvelopeRaster env = wheel(t, x, -d, D, b);
    const Imprint im{&env};
    t.step({&im, 1});
    depth.push_back(d);
  }
  return depth;
}

/// Mean of the depths while the axle is in [x0, x1) m.
inline double mean_depth(const std::vector<double>& depth, double x0, double x1) {
  double sum = 0.0;
  int n = 0;
  for (std::size_t k = 0; k < depth.size(); ++k)
    if (k / 240.0 >= x0 && k / 240.0 < x1) sum += depth[k], ++n;
  return sum / n;
}

/// Ramps a square plate (`columns` wide, `width` m) whose lower-left column is (i0, j0) from 0
/// to pressure p over 20 steps, each lowering it by the bearing offset for the load and
/// pressing it in. Returns its depth.
inline double ramp_plate(Terrain& t, std::int64_t i0, std::int64_t j0, double p, int columns = 30, double width = 0.3) {
  constexpr int kSteps = 20;
  double depth = 0.0;
  for (int k = 1; k <= kSteps; ++k) {
    const double load = p * width * width * k / kSteps;
    const EnvelopeRaster here = box_envelope(i0, j0, columns, columns, -depth);
    depth += t.bearing_offset(here, load);
    const EnvelopeRaster env = box_envelope(i0, j0, columns, columns, -depth);
    const Imprint im{&env};
    t.step({&im, 1});
  }
  return depth;
}

/// Replaces a state file's trailing checksum with that of the bytes before it.
inline void reseal(std::vector<unsigned char>& bytes) {
  bytes.resize(bytes.size() - 8);
  StateHash sum;
  sum.add_bytes(bytes.data(), bytes.size());
  const std::uint64_t checksum = sum.value();
  bytes.insert(bytes.end(), reinterpret_cast<const unsigned char*>(&checksum),
               reinterpret_cast<const unsigned char*>(&checksum) + sizeof checksum);
}

}  // namespace shore::terrain::testing
