// The pipeline's stages one at a time, on small hand-made regions (private headers of
// terrain/src): the contour map's distances, displacement's volume and landing ring, the
// amount one erosion pass moves, Bekker capacity and the bearing offset, and the tile runs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <set>
#include <utility>
#include <vector>

#include "bearing.h"
#include "layers.h"
#include "region.h"
#include "stage_contour.h"
#include "stage_displace.h"
#include "stage_erode.h"
#include "stage_imprint.h"
#include "tile_store.h"

using namespace shore::terrain;

namespace {

// A w x h region (halo included) at the origin, flat at height 0 over bedrock at -1.
Region flat_region(int w, int h) {
  Region r;
  r.prepare({0, 0, w, h}, nullptr);  // one thread
  r.ht.assign(r.size(), 0.0);
  r.sink.assign(r.size(), 0.0);
  r.bed.assign(r.size(), -1.0);
  return r;
}

// Collision flags: interior everywhere but the halo, plus `extra` on [x0, x1] x [y0, y1].
std::vector<unsigned char> flags_with(const Region& r, int x0, int y0, int x1, int y1, unsigned char extra) {
  std::vector<unsigned char> flags(r.size(), 0);
  for (int y = 1; y < r.h - 1; ++y)
    for (int x = 1; x < r.w - 1; ++x) flags[r.at(x, y)] = kInterior;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) flags[r.at(x, y)] |= extra;
  return flags;
}

// The contour map of a contact patch [x0, x1] x [y0, y1] of r.
ContourStage contour_of_patch(const Region& r, int x0, int y0, int x1, int y1) {
  ContourStage contour;
  contour.run(r, flags_with(r, x0, y0, x1, y1, kCovered | kContact));
  return contour;
}

int chessboard_to_outside(int x, int y, int x0, int y0, int x1, int y1) {
  return std::min({x - x0, x1 - x, y - y0, y1 - y}) + 1;
}

}  // namespace

TEST(ContourStage, ChessboardDistanceToTheEdgeOfAContactPatch) {
  const Region r = flat_region(11, 11);
  const ContourStage contour = contour_of_patch(r, 2, 3, 8, 7);  // 7 x 5 columns
  for (int y = 0; y < r.h; ++y)
    for (int x = 0; x < r.w; ++x) {
      const bool inside = x >= 2 && x <= 8 && y >= 3 && y <= 7;
      EXPECT_EQ(contour.levels()[r.at(x, y)], inside ? chessboard_to_outside(x, y, 2, 3, 8, 7) : 0)
          << "column " << x << ", " << y;
    }
}

TEST(ContourStage, AGapInThePatchCountsAsContactButAnOpenEdgeDoesNot) {
  const Region r = flat_region(9, 9);
  auto flags = flags_with(r, 2, 2, 6, 6, kCovered | kContact);
  flags[r.at(4, 4)] = kInterior | kCovered;  // under the body, cut off from the open
  flags[r.at(2, 4)] = kInterior | kCovered;  // under the body, next to the open
  ContourStage contour;
  contour.run(r, flags);
  EXPECT_EQ(contour.levels()[r.at(2, 4)], 0);  // soil may land there
  EXPECT_EQ(contour.levels()[r.at(3, 4)], 1);  // so its neighbour borders open soil
  EXPECT_EQ(contour.levels()[r.at(4, 4)], 2);  // as if in contact, two columns from (2, 4)
}

// Pockets (under a body, out of contact) in many patterns: a column is open if it is not
// under a body or is a pocket connected to such a column through pockets (8-connected,
// whichever way a raster scan meets them), and every other column's level is its chessboard
// distance to the open, as a breadth-first search from the open finds it. (Checked to fail
// when the contour's scan opens pockets without its backward fill.)
TEST(ContourStage, PocketsOpenWhereverThePocketsLeadToTheOpen) {
  const Region r = flat_region(40, 30);
  const int w = r.w, h = r.h;
  std::uint64_t state = 12345;
  auto draw = [&state] {  // SplitMix64: the same patterns on every machine
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  };
  auto each_neighbour = [&](int x, int y, auto f) {
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if ((dx != 0 || dy != 0) && x + dx >= 0 && y + dy >= 0 && x + dx < w && y + dy < h) f(x + dx, y + dy);
  };
  int opened = 0, closed = 0;  // pockets over all patterns: both kinds must occur
  for (const double share : {0.3, 0.5, 0.6, 0.7}) {
    for (int pattern = 0; pattern < 25; ++pattern) {
      auto flags = flags_with(r, 3, 3, w - 4, h - 4, kCovered | kContact);
      for (int y = 3; y <= h - 4; ++y)
        for (int x = 3; x <= w - 4; ++x)
          if (draw() < share) flags[r.at(x, y)] = kInterior | kCovered;
      ContourStage contour;
      contour.run(r, flags);
      // The reference: the open by a flood fill through pockets from the columns not under a
      // body, then the levels ring by ring from the open.
      std::vector<int> level(r.size(), -1);
      std::vector<std::pair<int, int>> ring, next;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          if (!(flags[r.at(x, y)] & (kCovered | kContact))) level[r.at(x, y)] = 0, ring.emplace_back(x, y);
      for (std::vector<std::pair<int, int>> fill = ring; !fill.empty();) {
        const auto [x, y] = fill.back();
        fill.pop_back();
        each_neighbour(x, y, [&](int nx, int ny) {
          if (level[r.at(nx, ny)] >= 0 || (flags[r.at(nx, ny)] & (kCovered | kContact)) != kCovered) return;
          level[r.at(nx, ny)] = 0, ring.emplace_back(nx, ny), fill.emplace_back(nx, ny);
          ++opened;
        });
      }
      for (int d = 1; !ring.empty(); ++d, ring.swap(next)) {
        next.clear();
        for (const auto& [x, y] : ring)
          each_neighbour(x, y, [&](int nx, int ny) {
            if (level[r.at(nx, ny)] >= 0) return;
            level[r.at(nx, ny)] = d, next.emplace_back(nx, ny);
            closed += (flags[r.at(nx, ny)] & (kCovered | kContact)) == kCovered;
          });
      }
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          ASSERT_EQ(contour.levels()[r.at(x, y)], level[r.at(x, y)])
              << "column " << x << ", " << y << ", share " << share << ", pattern " << pattern;
    }
  }
  EXPECT_GT(opened, 0) << "no pocket led to the open: this tests less than it says";
  EXPECT_GT(closed, 0) << "every pocket led to the open: this tests less than it says";
}

TEST(DisplaceStage, OneColumnSpreadsItsShareEvenlyOnItsRing) {
  Region r = flat_region(5, 5);
  const ContourStage contour = contour_of_patch(r, 2, 2, 2, 2);
  std::vector<double> displaced(r.size(), 0.0);
  displaced[r.at(2, 2)] = 1.0;
  DisplaceStage displace;
  const double compacted = displace.run(r, contour.levels(), contour.closed(), displaced, std::vector<double>{0.5});
  EXPECT_EQ(compacted, 0.5);
  for (int y = 0; y < r.h; ++y)
    for (int x = 0; x < r.w; ++x) {
      const bool ring = std::max(std::abs(x - 2), std::abs(y - 2)) == 1;
      EXPECT_EQ(r.ht[r.at(x, y)], ring ? 0.5 / 8 : 0.0) << "column " << x << ", " << y;
    }
}

TEST(DisplaceStage, ConservesVolumeAndLandsOnTheFirstRingOnly) {
  Region r = flat_region(13, 13);
  const ContourStage contour = contour_of_patch(r, 3, 3, 9, 8);
  std::vector<double> displaced(r.size(), 0.0);
  double pressed = 0.0;
  for (int y = 3; y <= 8; ++y)
    for (int x = 3; x <= 9; ++x) {
      displaced[r.at(x, y)] = 0.001 * (1 + x + 2 * y);
      pressed += displaced[r.at(x, y)];
    }
  const double alpha = 0.3;
  DisplaceStage displace;
  const double compacted = displace.run(r, contour.levels(), contour.closed(), displaced, std::vector<double>{alpha});
  double landed = 0.0;
  for (int y = 0; y < r.h; ++y)
    for (int x = 0; x < r.w; ++x) {
      const double rise = r.ht[r.at(x, y)];
      const bool ring = x >= 2 && x <= 10 && y >= 2 && y <= 9 && !(x >= 3 && x <= 9 && y >= 3 && y <= 8);
      if (ring)
        EXPECT_GT(rise, 0.0) << "column " << x << ", " << y;
      else
        EXPECT_EQ(rise, 0.0) << "column " << x << ", " << y;
      landed += rise;
    }
  // To rounding: the shares split among 3 or 5 lower neighbours are not exact in binary.
  EXPECT_NEAR(compacted, (1 - alpha) * pressed, 1e-14);
  EXPECT_NEAR(landed, alpha * pressed, 1e-14);
  EXPECT_NEAR(landed + compacted, pressed, 1e-14);
}

TEST(ErodeStage, OneTooSteepPairMovesSigmaTimesItsExcess) {
  // 3 x 3: only the centre gives (the halo only receives), and only its +x neighbour lies
  // lower; the others are level with it.
  const double top = 0.05;
  Region r = flat_region(3, 3);
  r.ht.assign(r.size(), top);
  r.ht[r.at(2, 1)] = 0.0;
  ImprintStage no_body;
  no_body.no_bodies(r);
  TerrainSettings s;  // sand, 1 cm
  s.max_erosion_passes = 1;
  ErodeStage erode;
  EXPECT_EQ(erode.run(r, no_body.flags(), no_body.body(), s, {&s.material, 1}, false), 1);
  const double limit = s.cell * std::tan(s.material.theta_out);
  const double moved = s.material.sigma * (top - limit);
  EXPECT_DOUBLE_EQ(r.ht[r.at(1, 1)], top - moved);
  EXPECT_DOUBLE_EQ(r.ht[r.at(2, 1)], moved);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x)
      if ((x != 1 || y != 1) && (x != 2 || y != 1)) {
        EXPECT_EQ(r.ht[r.at(x, y)], top);
      }
  // Stopped by the cap while still steeper than theta_stop: the giver carries on next step.
  const shore::GridRect& left = erode.still_flowing();
  EXPECT_EQ(left.i0, 1);
  EXPECT_EQ(left.j0, 1);
  EXPECT_EQ(left.nx, 1);
  EXPECT_EQ(left.ny, 1);
}

TEST(ErodeStage, ARaisedColumnSharesEquallyAmongItsEightNeighbours) {
  const double top = 0.05;
  Region r = flat_region(5, 5);
  r.ht[r.at(2, 2)] = top;
  ImprintStage no_body;
  no_body.no_bodies(r);
  TerrainSettings s;
  s.max_erosion_passes = 1;
  ErodeStage erode;
  erode.run(r, no_body.flags(), no_body.body(), s, {&s.material, 1}, true);
  const double t = std::tan(s.material.theta_out);
  const double excess = 4 * (top - s.cell * t) + 4 * (top - std::sqrt(2.0) * s.cell * t);
  const double share = s.material.sigma * (excess / 8) / 8;
  EXPECT_NEAR(r.ht[r.at(2, 2)], top - 8 * share, 1e-15);
  for (int y = 1; y <= 3; ++y)
    for (int x = 1; x <= 3; ++x)
      if (x != 2 || y != 2) {
        EXPECT_NEAR(r.ht[r.at(x, y)], share, 1e-15);
      }
}

TEST(Bearing, FlatPlateCapacityIsBekkersPressureTimesItsArea) {
  TerrainSettings s;  // sand, 1 cm
  const int nx = 20, ny = 12;
  const double sunk = 0.01, pressed = 0.02;
  std::vector<BearingColumn> plate;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) plate.push_back({i, j, 0.0, sunk, -1.0, -pressed});
  const Bearing b = capacity(plate, {}, {}, s, {&s.material, 1}, bearing_powers({&s.material, 1}), 0.0, true);
  const Material& m = s.material;
  const double width = ny * s.cell;
  const double p = (m.bekker_kc / width + m.bekker_kphi) * std::pow(sunk + pressed, m.bekker_n);
  EXPECT_EQ(b.contact_columns, nx * ny);
  EXPECT_DOUBLE_EQ(b.patch_width, width);
  EXPECT_NEAR(b.capacity, p * nx * ny * s.cell * s.cell, 1e-12 * b.capacity);
  ASSERT_EQ(b.columns.size(), plate.size());
  EXPECT_EQ(b.columns.front().i, 0);
  EXPECT_EQ(b.columns.back().j, ny - 1);
}

TEST(Bearing, OffsetForALoadInvertsBekkersLaw) {
  TerrainSettings s;
  const int n = 30;
  std::vector<BearingColumn> plate;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) plate.push_back({i, j, 0.0, 0.0, -1.0, 0.0});
  const Material& m = s.material;
  const double area = n * n * s.cell * s.cell, load = 50e3 * area;
  const double expected = std::pow(load / area / (m.bekker_kc / (n * s.cell) + m.bekker_kphi), 1.0 / m.bekker_n);
  const std::vector<shore::det::FixedPower> powers = bearing_powers({&s.material, 1});
  const double offset = offset_for_load(plate, {}, {}, s, {&s.material, 1}, powers, load);
  EXPECT_NEAR(offset, expected, 2e-7);  // the bracket is narrowed to 1e-7
  EXPECT_GE(capacity(plate, {}, {}, s, {&s.material, 1}, powers, offset, false).capacity, load);  // its upper end
}

TEST(Layers, LayeredBitsMarkEachLayeredBoundaryOfUpToAWord) {
  // Layered and unlayered boundaries mixed irregularly (a few-column pattern shifted by the
  // word's length), every count from 0 to 64, at every alignment of the first column.
  std::vector<double> boundary(80);
  for (std::size_t k = 0; k < boundary.size(); ++k)
    boundary[k] = (k * 7 + k / 5) % 3 == 0 ? kNoLayer : 0.01 * static_cast<double>(k);
  boundary[9] = -0.02;  // a crust whose sinkage passed it is still layered
  for (std::size_t first = 0; first < 2; ++first)
    for (std::size_t count = 0; count <= 64; ++count) {
      std::uint64_t expected = 0;
      for (std::size_t j = 0; j < count; ++j)
        if (ColumnLayer{boundary[first + j], 0}.layered()) expected |= std::uint64_t{1} << j;
      EXPECT_EQ(layered_bits(boundary.data() + first, count), expected) << first << ", " << count;
    }
}

TEST(TileStore, RunsCoverARectangleOnceWithoutCrossingATileEdge) {
  TerrainSettings s;
  s.tile_columns = 8;
  TileStore store(s);
  const shore::GridRect rect{-13, -5, 30, 17};
  std::set<std::pair<std::int64_t, std::int64_t>> seen;
  int runs = 0;
  store.for_each_run_creating(rect, [&](Tile& t, const TileRun& run) {
    ++runs;
    EXPECT_EQ(&t, store.find(run.key));
    EXPECT_LE(run.li + run.count, 8);
    EXPECT_EQ(run.local, static_cast<std::size_t>(run.lj) * 8 + run.li);
    for (int c = 0; c < run.count; ++c) {
      const std::int64_t i = rect.i0 + run.x + c, j = rect.j0 + run.y;
      EXPECT_EQ(store.key_of(i, j), run.key);
      EXPECT_EQ(store.local(i, j), run.local + c);
      EXPECT_TRUE(seen.insert({i, j}).second) << "column " << i << ", " << j << " twice";
    }
  });
  EXPECT_EQ(seen.size(), 30u * 17u);
  EXPECT_EQ(store.size(), 5u * 3u);  // tiles -2..2 along x, -1..1 along y
  EXPECT_EQ(runs, 17 * 5);           // each row crosses 5 tiles
}
