// Spray's cheaper arithmetic gives what the plain formulas give (private headers of
// terrain/src): the column a point falls in (llround of the division), a body-frame cube's
// key (floor of the division), the slow-piece test (the root), the particles a piece owes
// (floor of the division plus a uniform number), the index of a body's pieces (bisection of
// the sorted list), the end of a flight whatever its number of samples, and a column's tile
// and place in it by shifts. The points are the hard ones: exact multiples of the cell and
// of half cells, a few ulps either side, and random ones.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include "shore/terrain/height_source.h"
#include "spray_cling.h"
#include "spray_flight.h"
#include "spray_ground.h"
#include "spray_motion.h"
#include "spray_tile_index.h"
#include "spray_tops.h"
#include "tile_store.h"

using namespace shore::terrain;
using shore::Vec3;

namespace {

/// Values around each multiple of `step` (k = -n..n): the multiple and 3 ulps either side.
std::vector<double> around_multiples(double step, int n) {
  std::vector<double> out;
  for (int k = -n; k <= n; ++k) {
    double x = static_cast<double>(k) * step, lo = x, hi = x;
    out.push_back(x);
    for (int u = 0; u < 3; ++u) {
      lo = std::nextafter(lo, -INFINITY), hi = std::nextafter(hi, INFINITY);
      out.push_back(lo), out.push_back(hi);
    }
  }
  return out;
}

/// Random values in [-span, span].
std::vector<double> random_values(double span, int n, unsigned seed) {
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> d(-span, span);
  std::vector<double> out;
  for (int k = 0; k < n; ++k) out.push_back(d(gen));
  return out;
}

}  // namespace

TEST(SprayArithmetic, ColumnsAreTheRoundedQuotients) {
  for (const double cell : {0.01, 0.02, 0.005, 0.1, 1.0 / 3.0, 0.0123}) {
    TerrainSettings s;
    s.cell = cell;
    s.origin_x = 0.37, s.origin_y = -2.0 * cell;
    TileStore store(s);
    const SprayGround ground(store, s);
    std::vector<double> xs = around_multiples(0.5 * cell, 400);
    for (const double x : random_values(1e3, 20000, 7)) xs.push_back(x);
    for (const double d : xs) {
      const double x = d + s.origin_x, y = d + s.origin_y;
      ASSERT_EQ(ground.column_i(x), std::llround((x - s.origin_x) / cell)) << "cell " << cell << ", x " << x;
      ASSERT_EQ(ground.column_j(y), std::llround((y - s.origin_y) / cell)) << "cell " << cell << ", y " << y;
    }
  }
}

TEST(SprayArithmetic, PieceKeysAreTheFlooredQuotients) {
  for (const double cell : {0.01, 0.02, 0.005, 0.1, 1.0 / 3.0, 0.0123}) {
    const ClingKeys keys(cell);
    std::vector<double> xs = around_multiples(cell, 300);
    for (const double x : random_values(5.0, 20000, 11)) xs.push_back(x);
    xs.push_back(1e9), xs.push_back(-1e9);  // far out: clamped
    for (std::size_t k = 0; k + 2 < xs.size(); ++k) {
      const Vec3 b{xs[k], xs[k + 1], xs[k + 2]};
      std::uint64_t expected = 0;
      for (int a = 0; a < 3; ++a) {
        const double f = std::clamp(std::floor(b[static_cast<std::size_t>(a)] / cell), -1048576.0, 1048575.0);
        expected |= static_cast<std::uint64_t>(static_cast<std::int64_t>(f) + 1048576) << (21 * a);
      }
      ASSERT_EQ(keys.of(b), expected) << "cell " << cell << ", " << b[0] << " " << b[1] << " " << b[2];
      ASSERT_EQ(cling_key(b, cell), expected);
    }
  }
}

TEST(SprayArithmetic, SlowPiecesAreThoseUnderMinSpeedByTheRoot) {
  for (const double min_speed : {0.3, 0.5, 1.0, 0.0, 2.5}) {
    const SpeedTest test(min_speed);
    std::vector<double> speeds = around_multiples(min_speed > 0 ? min_speed : 1e-3, 3);
    for (const double v : random_values(3.0, 5000, 3)) speeds.push_back(v);
    for (const double v : speeds)
      for (const Vec3& u : {Vec3{v, 0, 0}, Vec3{0.6 * v, 0.8 * v, 0}, Vec3{v / 3, v / 3, v / 3}}) {
        const double root = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
        ASSERT_EQ(test.slower(u), root < min_speed) << "min speed " << min_speed << ", speed " << root;
      }
  }
}

TEST(SprayArithmetic, ParticlesDueAreTheFlooredQuotientPlusTheDraw) {
  for (const double vp : {3.35e-8, 4.0 / 3.0 * M_PI * 8e-9, 9.05e-7, 1.0 / 7.0}) {
    const double inverse = 1.0 / vp;
    std::vector<double> owed = around_multiples(vp, 40);
    for (const double o : random_values(30 * vp, 5000, 5)) owed.push_back(std::abs(o));
    std::mt19937_64 gen(9);
    for (const double o : owed) {
      if (o < 0) continue;
      for (const double u : {0.0, 0.5, std::nextafter(1.0, 0.0), std::ldexp(static_cast<double>(gen() >> 11), -53)}) {
        // owed a hair under a whole number of particles, and the draw that makes it whole
        const double q = o / vp, tight = std::nextafter(std::ceil(q) - q, 1.0);
        for (const double draw : {u, tight < 1.0 ? tight : u})
          ASSERT_EQ(particles_due(o, vp, inverse, draw), std::floor(o / vp + draw)) << o << " " << vp << " " << draw;
      }
    }
  }
}

TEST(SprayArithmetic, ThePieceIndexFindsWhatBisectionFinds) {
  std::mt19937_64 gen(21);
  for (const int spread : {3, 20, 400}) {  // dense rows, sparse ones, too sparse for rows
    std::vector<ClingCell> cells;
    std::vector<std::uint64_t> keys;
    for (int k = 0; k < 300; ++k) {
      const std::uint64_t x = 1000 + gen() % 7, y = 2000 + gen() % static_cast<std::uint64_t>(spread),
                          z = 3000 + gen() % static_cast<std::uint64_t>(spread);
      keys.push_back(x | (y << 21) | (z << 42));
    }
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    for (const std::uint64_t key : keys) cells.push_back(ClingCell{.key = key});
    PieceIndex index;
    index.build(cells);
    for (const std::uint64_t key : keys) {
      const ClingCell* c = index.find(cells, key);
      ASSERT_NE(c, nullptr);
      EXPECT_EQ(c->key, key);
    }
    for (int k = 0; k < 3000; ++k) {  // misses: around the box and inside it
      const std::uint64_t x = 995 + gen() % 17, y = 1995 + gen() % static_cast<std::uint64_t>(spread + 10),
                          z = 2995 + gen() % static_cast<std::uint64_t>(spread + 10);
      const std::uint64_t key = x | (y << 21) | (z << 42);
      const bool there = std::binary_search(keys.begin(), keys.end(), key);
      const ClingCell* c = index.find(cells, key);
      EXPECT_EQ(c != nullptr, there) << x << " " << y << " " << z;
    }
  }
  PieceIndex empty;
  std::vector<ClingCell> none;
  empty.build(none);
  EXPECT_EQ(empty.find(none, 12345), nullptr);
}

// fly() times its last sample at duration * n / n for n samples; the clock says when that is
// the duration itself, without counting n.
TEST(SprayArithmetic, AFlightEndsAtTheDurationWhereTheClockSaysSo) {
  for (const double dt : {1.0 / 240, 0.005, 1.0 / 300, 0.01, 1.0 / 60})
    for (const double cell : {0.01, 0.02, 0.005}) {
      SampleClock clock;
      clock.reset(FlightRules{9.81, 0.6, 10.0}, dt, cell);
      int claimed = 0;
      for (double v = 0.0; v < 2000.0; v = v * 1.01 + 0.01)
        for (const double f : {1.0, std::nextafter(1.0, 0.0), std::nextafter(1.0, 2.0)}) {
          const double vx = 0.6 * v * f, vy = 0.8 * v;
          if (!clock.ends_at_end(vx, vy)) continue;
          ++claimed;
          const double travel = std::sqrt(vx * vx + vy * vy) * dt;
          const int n = static_cast<int>(std::min(4096.0, std::ceil(travel / (0.5 * cell)))) + 1;
          ASSERT_EQ(dt * static_cast<double>(n) / static_cast<double>(n), dt) << dt << " " << cell << " " << v;
        }
      EXPECT_GT(claimed, 0) << "the clock knows the end of slow flights, dt " << dt;
    }
}

// Spray's tile keys and local indices (shifts and masks for a power-of-two tile side) are
// the store's (floor divisions), on both sides of zero and for a side that is no power of two.
TEST(SprayArithmetic, TileKeysAndLocalIndicesAreTheStoresOwn) {
  for (const int side : {64, 16, 4, 48, 100}) {
    TerrainSettings s;
    s.tile_columns = side;
    const TileStore store(s);
    const TileIndex index(store);
    for (std::int64_t i = -3 * side - 5; i <= 3 * side + 5; i += 7)
      for (std::int64_t j = -2 * side - 3; j <= 2 * side + 3; j += 5) {
        ASSERT_EQ(index.key_of(i, j), store.key_of(i, j)) << side << " " << i << " " << j;
        ASSERT_EQ(index.local(i, j), store.local(i, j)) << side << " " << i << " " << j;
      }
    for (const std::int64_t far : {std::int64_t{1} << 40, -(std::int64_t{1} << 40) - 1}) {
      EXPECT_EQ(index.key_of(far, -far), store.key_of(far, -far)) << side;
      EXPECT_EQ(index.local(far, -far), store.local(far, -far)) << side;
    }
  }
}

TEST(SprayArithmetic, CounterNumbersAreTheHashChainWithOrWithoutTheTable) {
  // A candidate's draw is mix64(key ^ mix64(candidate * 16 + draw)), the counter's mix read
  // from a table for the first counters: the same numbers either side of the table's end.
  std::mt19937_64 gen(5);
  for (int trial = 0; trial < 20; ++trial) {
    const std::uint64_t seed = gen(), step = gen() % 1000, body = gen(), piece = gen();
    const CounterRandom rnd(seed, step, body, piece);
    const std::uint64_t key = mix64(mix64(mix64(mix64(seed) ^ step) ^ body) ^ piece);
    for (std::uint64_t candidate = 0; candidate < 80; ++candidate)
      for (std::uint64_t draw = 0; draw < 8; ++draw) {
        const std::uint64_t bits = mix64(key ^ mix64(candidate * 16u + draw));
        ASSERT_EQ(rnd.uniform(candidate, draw), static_cast<double>(bits >> 11) * 0x1.0p-53)
            << "candidate " << candidate << ", draw " << draw;
      }
  }
}

// The spray's landing bounds over blocks of columns, those of untiled blocks kept across
// steps (UntiledTops), are what reading every column of the blocks gives, and never below
// a column they cover: over untiled ground (a lattice-noise base), over tiles with raised
// columns, across windows of four block sides sharing one keep, for tile sides that are
// and are not multiples of the block side, and blocks wider than a tile (read tile by tile).
TEST(SprayArithmetic, KeptBlockBoundsAreTheColumnsHighest) {
  for (const int side : {64, 48, 20}) {
    TerrainSettings s;
    s.cell = 0.05;
    s.tile_columns = side;
    s.base = std::make_shared<LatticeNoise>(LatticeNoiseSettings{
        .seed = 3, .spacing = 1.0, .amplitude = 0.3, .mean = 0.0, .octaves = 2, .persistence = 0.5});
    TileStore store(s);
    for (const TileKey key : {TileKey{0, 0}, TileKey{1, 0}, TileKey{-1, -1}}) {
      Tile& t = store.tile(key);
      for (std::size_t k = 0; k < t.height.size(); k += 37) t.height[k] += 0.4;  // raised columns
    }
    UntiledTops kept;
    std::mt19937_64 gen(11);
    for (const std::int64_t width : {40, 300, 1000, 2500, 6000}) {  // block sides 8, 8, 16, 64, 128
      const std::int64_t i0 = -width / 2 - 13, j0 = -width / 3 - 5;
      SoilTops kept_too(store, &kept), by_columns(store, nullptr);
      kept_too.cover(i0, j0, i0 + width, j0 + width);
      by_columns.cover(i0, j0, i0 + width, j0 + width);
      for (int q = 0; q < 12; ++q) {  // the first over the raised tiles
        const std::int64_t a =
            q == 0 ? -8 : i0 + static_cast<std::int64_t>(gen() % static_cast<std::uint64_t>(width - 20));
        const std::int64_t b =
            q == 0 ? -8 : j0 + static_cast<std::int64_t>(gen() % static_cast<std::uint64_t>(width - 20));
        const std::int64_t c = a + static_cast<std::int64_t>(gen() % 20), d = b + static_cast<std::int64_t>(gen() % 20);
        const double bound = kept_too.bound(a, b, c, d);
        ASSERT_EQ(bound, by_columns.bound(a, b, c, d)) << side << " " << width << " " << a << " " << b;
        const shore::GridRect r{a, b, static_cast<int>(c - a + 1), static_cast<int>(d - b + 1)};
        std::vector<double> h(static_cast<std::size_t>(r.nx) * static_cast<std::size_t>(r.ny));
        store.read(r, h, false);
        ASSERT_GE(bound, *std::max_element(h.begin(), h.end())) << side << " " << width;
      }
    }
  }
}

// Laying a grain calls TileStore::mark_changed only for a column outside the box its tile
// has marked this step: every column laid must still be reported changed, to take_changed
// and to changed_since, whatever the order (tiles sharing a slot take turns, columns land
// inside and outside the box).
TEST(SprayArithmetic, EveryColumnLaidIsReportedChanged) {
  TerrainSettings s;
  TileStore store(s);
  const std::int64_t n = store.n();
  const std::uint64_t before = store.generation();
  store.advance_generation();
  std::vector<std::pair<std::int64_t, std::int64_t>> laid;
  {
    SprayGround ground(store, s);
    std::mt19937_64 gen(5);
    // Tiles 0..5 across: tiles 0 and 4, 1 and 5 share a slot; a few rows of tiles down.
    std::uniform_int_distribution<std::int64_t> i_of(-n, 5 * n + n - 1), j_of(-n, 2 * n - 1);
    for (int k = 0; k < 3000; ++k) {
      const std::int64_t i = i_of(gen), j = j_of(gen);
      ASSERT_GT(ground.lay(i, j, 1e-6), 0.0);
      laid.emplace_back(i, j);
    }
  }
  const auto reported = [&](const std::vector<shore::GridRect>& rects, std::int64_t i, std::int64_t j) {
    return std::any_of(rects.begin(), rects.end(), [&](const shore::GridRect& r) { return r.contains(i, j); });
  };
  const std::vector<shore::GridRect> since = store.changed_since(before), taken = store.take_changed();
  for (const auto& [i, j] : laid) {
    ASSERT_TRUE(reported(since, i, j)) << "column " << i << ", " << j << " (changed_since)";
    ASSERT_TRUE(reported(taken, i, j)) << "column " << i << ", " << j << " (take_changed)";
  }
}

// Bounds of blocks in one tile are kept from step to step (TiledTops) while the tile does
// not change: after columns are raised or lowered between steps (as the pipeline does,
// marked changed) or during one (grains laid and soil taken by the spray, before the
// blocks are asked, or after, in the generation they were read in), each bound is still what reading every column
// gives, for blocks in a tile and blocks wider than a tile, with steps that change nothing in between.
TEST(SprayArithmetic, KeptTileBoundsFollowEveryChange) {
  TerrainSettings s;
  s.cell = 0.05;
  s.tile_columns = 64;
  s.base = std::make_shared<LatticeNoise>(
      LatticeNoiseSettings{.seed = 7, .spacing = 1.0, .amplitude = 0.3, .mean = 0.0, .octaves = 2, .persistence = 0.5});
  TileStore store(s);
  const std::int64_t n = store.n();
  for (std::int64_t tx = -2; tx <= 2; ++tx)
    for (std::int64_t ty = -2; ty <= 2; ++ty) store.tile(TileKey{tx, ty});
  UntiledTops untiled;
  TiledTops tiled;
  std::mt19937_64 gen(23);
  std::uniform_int_distribution<std::int64_t> column(-2 * n, 3 * n - 1);
  // Grains laid and soil taken by the spray at random columns, half each.
  const auto spray_changes = [&](int changes) {
    SprayGround ground(store, s, {}, &untiled, &tiled);
    for (int c = 0; c < changes; ++c) {
      const std::int64_t i = column(gen), j = column(gen);
      if (c % 2 == 0)
        ground.lay(i, j, 0.4 * s.cell * s.cell);
      else
        ground.take(i, j, 0.3);
    }
  };
  for (int step = 0; step < 24; ++step) {
    store.advance_generation();
    const int changes = step % 3 == 2 ? 0 : 40;  // every third step changes nothing
    for (int c = 0; c < changes; ++c) {          // between steps: marked writes, up and down
      const std::int64_t i = column(gen), j = column(gen);
      const TileKey key = store.key_of(i, j);
      Tile& t = store.tile(key);
      const std::size_t k = store.local(i, j);
      t.height[k] += c % 2 == 0 ? 0.5 : -0.5;
      store.mark_changed(key, t, {static_cast<int>(k % n), static_cast<int>(k / n), 1, 1});
    }
    spray_changes(changes);                                // during the step, before the blocks are asked
    for (const std::int64_t width : {1000, 2500, 6000}) {  // block sides 16, 64, 128
      const std::int64_t i0 = -width / 2 - 13, j0 = -width / 3 - 5;
      SoilTops kept(store, &untiled, &tiled), by_columns(store);
      kept.cover(i0, j0, i0 + width, j0 + width);
      by_columns.cover(i0, j0, i0 + width, j0 + width);
      for (std::int64_t i = -2 * n; i < 3 * n; i += 16)
        for (std::int64_t j = -2 * n; j < 3 * n; j += 16) {
          const double bound = kept.bound(i, j, i + 15, j + 15);
          ASSERT_EQ(bound, by_columns.bound(i, j, i + 15, j + 15))
              << "step " << step << ", width " << width << ", block at " << i << ", " << j;
          const shore::GridRect r{i, j, 16, 16};
          std::vector<double> h(r.size());
          store.read(r, h, false);
          ASSERT_GE(bound, *std::max_element(h.begin(), h.end())) << step << " " << width;
        }
    }
    spray_changes(changes);  // later in the same generation, after the blocks were asked
  }
}
