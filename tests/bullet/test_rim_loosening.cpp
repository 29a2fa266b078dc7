// The loosening's weights (raycast_wheels_loosening.h): laid out in runs of one strip, each
// covered column must still hold its own strip's weight, worked out column by column here.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "raycast_wheels_loosening.h"
#include "shore/terrain/shear.h"

namespace {

using shore::EnvelopeRaster;
using shore::bullet::coupling_detail::ColumnOffsets;
using shore::bullet::coupling_detail::rim_angle;
using shore::bullet::coupling_detail::RimLoosening;
using shore::bullet::coupling_detail::RimShear;
using shore::bullet::coupling_detail::round_half_away;

// A ragged disc of covered columns with a hole in it: runs must not take the hole's or the
// outside's columns for covered ones, nor skip a covered column past a gap.
EnvelopeRaster ragged_disc() {
  EnvelopeRaster env;
  env.i0 = -23, env.j0 = -17, env.nx = 47, env.ny = 35;
  env.lower.assign(static_cast<std::size_t>(env.nx * env.ny), EnvelopeRaster::kNoLower);
  for (int y = 0; y < env.ny; ++y)
    for (int x = 0; x < env.nx; ++x) {
      const double dx = x - 23.0, dy = y - 17.0, r2 = dx * dx + dy * dy;
      const bool hole = std::abs(dx - 5.0) <= 2.0 && std::abs(dy + 3.0) <= 1.0;
      if (r2 <= 16.5 * 16.5 + 9.0 * std::sin(0.7 * x) && !hole)
        env.lower[static_cast<std::size_t>(y * env.nx + x)] = 0.01 * (x + y);
    }
  return env;
}

TEST(RimLoosening, EveryCoveredColumnWeighsItsOwnStripAtAnyHeading) {
  shore::terrain::TerrainSettings s;
  s.cell = 0.02;
  const shore::terrain::Terrain terrain(s);
  const shore::terrain::Material m = s.material;
  const EnvelopeRaster env = ragged_disc();
  const double radius = 0.3, reach = 0.95 * radius, cell = s.cell, cx = 0.013, cy = -0.007;
  ColumnOffsets from_centre;
  from_centre.read(terrain, env, cx, cy);
  RimShear shear;
  shear.radius = radius, shear.entry = 0.6, shear.sin_entry = std::sin(0.6);
  shear.rim = 1.0, shear.ground = 0.55, shear.side = 0.1;
  // Every covered column bearing 1 N: apply() then gives each its weight.
  shore::terrain::Bearing ones;
  for (int y = 0; y < env.ny; ++y)
    for (int x = 0; x < env.nx; ++x)
      if (env.lower[static_cast<std::size_t>(y * env.nx + x)] != EnvelopeRaster::kNoLower)
        ones.columns.push_back({env.i0 + x, env.j0 + y, 1.0});
  ones.capacity = static_cast<double>(ones.columns.size());
  const int half = static_cast<int>(std::ceil(reach / cell));
  RimLoosening loosening;
  // Along the axes and near them (long strips, runs), across them (each column placed).
  for (const double degrees : {0.0, 2.0, 7.0, 15.0, 25.0, 45.0, 65.0, 83.0, 90.0, 120.0, 180.0, 181.0, 260.0, 300.0}) {
    const double a = degrees * M_PI / 180.0;
    const btVector3 forward(btScalar(std::cos(a)), btScalar(std::sin(a)), 0);
    loosening.build(cell, env, from_centre, forward, radius, shear, m);
    shore::terrain::Bearing out;
    loosening.apply(ones, out);
    ASSERT_EQ(out.columns.size(), ones.columns.size());
    std::set<double> distinct;
    for (std::size_t k = 0; k < ones.columns.size(); ++k) {
      const auto& c = ones.columns[k];
      const double along = from_centre.dx(c.i) * double(forward.x()) + from_centre.dy(c.j) * double(forward.y());
      const double at = std::clamp(along, -reach, reach);
      const int strip = std::clamp(static_cast<int>(round_half_away(at * (1.0 / cell))), -half, half);
      const double expected = shore::terrain::shear::remoulding(m, shear.at(rim_angle(strip * cell, radius)));
      ASSERT_EQ(out.columns[k].force, expected) << degrees << " degrees, column " << c.i << ", " << c.j;
      distinct.insert(expected);
    }
    EXPECT_GT(distinct.size(), 10u) << degrees << " degrees: the strips should weigh differently";
  }
}

}  // namespace
