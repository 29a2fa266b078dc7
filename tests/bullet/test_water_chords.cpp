// The vertical chords of a polyhedron along a row (bullet/src/water_chords.cpp, private):
// every vector path gives the bits of one point and one face at a time. Built twice: with
// the library (AVX where the CPU has it), and with water_chords.cpp compiled in without
// its AVX path (SHORE_CHORDS_NO_AVX: SSE2, or one by one), as suite WaterChordsWithoutAvx.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "water_shape.h"

#ifndef SHORE_CHORDS_SUITE
#define SHORE_CHORDS_SUITE WaterChords
#endif

namespace {

using namespace shore::bullet::water_detail;

/// chord_row one point and one face at a time, as its contract states it: what its vector
/// paths must give bit for bit.
void chord_row_one_by_one(const WorldPlanes& p, double x0, double dx, int n, double y, double* lo, double* hi) {
  for (std::size_t f = 0; f < p.n.size(); ++f) {
    const Vec3 nf = p.n[f];
    const double base = p.d[f] - nf.y * y - nf.x * x0, step = -nf.x * dx;
    for (int k = 0; k < n; ++k) {
      const double rest = base + k * step;
      if (std::abs(nf.z) < 1e-12) {
        if (rest < 0.0) lo[k] = std::numeric_limits<double>::infinity();
      } else if (nf.z > 0.0) {
        const double z = rest * (1.0 / nf.z);
        hi[k] = z < hi[k] ? z : hi[k];
      } else {
        const double z = rest * (1.0 / nf.z);
        lo[k] = z > lo[k] ? z : lo[k];
      }
    }
  }
}

/// Random faces of every kind (looking up, down, upright with n_z exactly 0 and below
/// 1e-12) in a random order, around the origin.
WorldPlanes random_planes(std::mt19937_64& rng, int faces) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  WorldPlanes planes;
  for (int f = 0; f < faces; ++f) {
    Vec3 n{u(rng), u(rng), u(rng)};
    if (f % 7 == 3) n.z = 0.0;
    if (f % 11 == 5) n.z = 1e-13;
    planes.n.push_back(n);
    planes.d.push_back(0.05 + 0.15 * (u(rng) + 1.0));  // the origin inside, points 0.2 m off it often not
  }
  return planes;
}

TEST(SHORE_CHORDS_SUITE, RowsGiveTheBitsOfOnePointAtATime) {
  // Random faces over rows of every length up to a few vector blocks, from ends that start
  // at +-inf or at random heights (so min and max pick both ways).
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const WorldPlanes planes = random_planes(rng, 1 + trial % 40);
    const int n = trial % 23;
    const double x0 = u(rng), dx = 0.01 + 0.05 * (u(rng) + 1.0), y = 0.5 * u(rng);
    std::vector<double> lo(std::size_t(n) + 1), hi(std::size_t(n) + 1);
    for (std::size_t k = 0; k < lo.size(); ++k) {
      lo[k] = trial % 2 ? -std::numeric_limits<double>::infinity() : u(rng);
      hi[k] = trial % 2 ? std::numeric_limits<double>::infinity() : u(rng);
    }
    std::vector<double> want_lo = lo, want_hi = hi;
    chord_row_one_by_one(planes, x0, dx, n, y, want_lo.data(), want_hi.data());
    chord_row(planes, x0, dx, n, y, lo.data(), hi.data());
    // Bit for bit, and the point past the row untouched.
    EXPECT_EQ(std::memcmp(lo.data(), want_lo.data(), lo.size() * sizeof(double)), 0) << "trial " << trial;
    EXPECT_EQ(std::memcmp(hi.data(), want_hi.data(), hi.size() * sizeof(double)), 0) << "trial " << trial;
  }
}

TEST(SHORE_CHORDS_SUITE, WideningGivesTheBitsOfChordsThenTheirMerge) {
  // A row's envelope so far (nothing yet, or random ends) widened where the faces' chord
  // is not empty: some points of each row are inside (small offsets: the planes pass near
  // the points), some outside.
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int inside = 0, points = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const WorldPlanes planes = random_planes(rng, 4 + trial % 40);
    const int n = trial % 23;
    const double x0 = 0.1 * u(rng), dx = 0.01, y = 0.1 * u(rng);
    points += n;
    std::vector<double> lower(std::size_t(n) + 1), upper(std::size_t(n) + 1);
    for (std::size_t k = 0; k < lower.size(); ++k) {
      lower[k] = trial % 2 ? std::numeric_limits<double>::infinity() : u(rng);
      upper[k] = trial % 2 ? -std::numeric_limits<double>::infinity() : u(rng);
    }
    std::vector<double> lo(std::size_t(n), -std::numeric_limits<double>::infinity());
    std::vector<double> hi(std::size_t(n), std::numeric_limits<double>::infinity());
    chord_row_one_by_one(planes, x0, dx, n, y, lo.data(), hi.data());
    std::vector<double> want_lower = lower, want_upper = upper;
    for (std::size_t k = 0; k < lo.size(); ++k)
      if (lo[k] < hi[k]) {
        ++inside;
        want_lower[k] = std::min(want_lower[k], lo[k]);
        want_upper[k] = std::max(want_upper[k], hi[k]);
      }
    widen_by_chords(planes, x0, dx, n, y, lower.data(), upper.data());
    EXPECT_EQ(std::memcmp(lower.data(), want_lower.data(), lower.size() * sizeof(double)), 0) << "trial " << trial;
    EXPECT_EQ(std::memcmp(upper.data(), want_upper.data(), upper.size() * sizeof(double)), 0) << "trial " << trial;
  }
  // Both kinds of point were met.
  EXPECT_GT(inside, points / 10);
  EXPECT_LT(inside, points - points / 10);
}

}  // namespace
