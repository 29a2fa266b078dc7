// A cylinder towed through sand at full sinkage: the erosion passes that follow only the
// changed columns must still conserve volume exactly and give bit-identical results for
// any thread count, with a wide overhang (covered, not touching) behind the axle.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "shore/terrain/terrain.h"

using namespace shore::terrain;

namespace {

// Lowest line of a horizontal cylinder (axis along y, radius r, width b) whose bottom lies
// `depth` below the flat ground, axle at x; the window is the whole body seen from below.
shore::EnvelopeRaster cylinder(const Terrain& t, double x, double r, double b, double depth) {
  shore::EnvelopeRaster env;
  const std::int64_t i0 = t.column_i(x - r), i1 = t.column_i(x + r);
  const std::int64_t j0 = t.column_j(-b / 2), j1 = t.column_j(b / 2);
  env.resize(i0, j0, static_cast<int>(i1 - i0 + 1), static_cast<int>(j1 - j0 + 1), false);
  for (std::int64_t j = j0; j <= j1; ++j)
    for (std::int64_t i = i0; i <= i1; ++i) {
      const double dx = t.column_x(i) - x;
      if (std::abs(dx) < r) env.lower[env.index(i, j)] = (r - depth) - std::sqrt(r * r - dx * dx);
    }
  return env;
}

struct Towed {
  std::uint64_t hash = 0;
  double total = 0.0;      // ground + compacted, m^3
  double displaced = 0.0;  // m^3 pushed down over the run
  double raised = 0.0;     // m^3 above the untouched ground at the end
};

Towed tow(int threads) {
  TerrainSettings s;
  s.cell = 0.02;
  s.material = Material::sand();
  s.threads = threads;
  s.parallel_min_columns = 0;  // split even this small region between threads
  s.max_erosion_passes = 8;    // fewer fork-joins: this machine's cores are shared
  Terrain t(s);
  Towed out;
  const double r = 0.2, b = 0.16, depth = 0.05;
  for (int k = 0; k < 24; ++k) {
    const shore::EnvelopeRaster env = cylinder(t, 0.012 * k, r, b, depth);
    const Imprint im{&env, 0.0, true};
    out.displaced += t.step({&im, 1}).displaced_volume;
  }
  out.hash = t.state_hash();
  out.total = t.volume().total();
  const double a = s.cell * s.cell;
  for (std::int64_t j = -20; j <= 20; ++j)
    for (std::int64_t i = -20; i <= 40; ++i) out.raised += std::max(0.0, t.height(i, j) - t.base_height(i, j)) * a;
  return out;
}

}  // namespace

TEST(Towed, CylinderConservesVolumeAndIgnoresThreadCount) {
  const Towed one = tow(1);
  ASSERT_GT(one.displaced, 0.0);
  // Displacement pushed alpha of the displaced volume out into berms and a bow wave.
  EXPECT_GT(one.raised, 0.1 * Material::sand().alpha * one.displaced);
  EXPECT_LE(std::abs(one.total), 1e-9 * one.displaced);
  const Towed two = tow(2);
  EXPECT_EQ(two.hash, one.hash);
}
