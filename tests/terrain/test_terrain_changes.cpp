// Non-consuming change tracking: Terrain::generation() and changed_since(g). Checked
// against snapshots of the heights (what really changed), for several observers that look
// at different times, and past the end of the history the store keeps.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "shore/terrain/terrain.h"
#include "terrain_fixtures.h"

using namespace shore::terrain;
using shore::terrain::testing::sphere_envelope;

namespace {

constexpr std::int64_t kLo = -40, kHi = 40;  // the window the snapshots cover

std::vector<double> snapshot(const Terrain& t) {
  std::vector<double> h;
  for (std::int64_t j = kLo; j <= kHi; ++j)
    for (std::int64_t i = kLo; i <= kHi; ++i) h.push_back(t.height(i, j));
  return h;
}

bool covered(const std::vector<shore::GridRect>& rects, std::int64_t i, std::int64_t j) {
  for (const shore::GridRect& r : rects)
    if (i >= r.i0 && i < r.i0 + r.nx && j >= r.j0 && j < r.j0 + r.ny) return true;
  return false;
}

/// Each rectangle holds a column that differs between the snapshot and now (no stale ones).
void expect_no_stale_rectangles(const std::vector<double>& before, const Terrain& t,
                                const std::vector<shore::GridRect>& rects) {
  const std::vector<double> now = snapshot(t);
  for (const shore::GridRect& r : rects) {
    bool holds_a_change = false;
    std::size_t k = 0;
    for (std::int64_t j = kLo; j <= kHi; ++j)
      for (std::int64_t i = kLo; i <= kHi; ++i, ++k)
        holds_a_change = holds_a_change || (now[k] != before[k] && covered({r}, i, j));
    EXPECT_TRUE(holds_a_change) << "rectangle at " << r.i0 << ", " << r.j0 << " holds no change";
  }
}

/// Every column that differs between the snapshots lies in a rectangle; returns how many did.
int expect_changes_covered(const std::vector<double>& before, const Terrain& t,
                           const std::vector<shore::GridRect>& rects) {
  const std::vector<double> now = snapshot(t);
  int changed = 0;
  std::size_t k = 0;
  for (std::int64_t j = kLo; j <= kHi; ++j)
    for (std::int64_t i = kLo; i <= kHi; ++i, ++k)
      if (now[k] != before[k]) {
        ++changed;
        EXPECT_TRUE(covered(rects, i, j)) << "column " << i << ", " << j << " changed but is not reported";
      }
  return changed;
}

void press(Terrain& t, double x, double depth) {
  const shore::EnvelopeRaster env = sphere_envelope(t, x, 0.0, 0.08 - depth, 0.08);
  const Imprint im{&env};
  t.step({&im, 1});
}

TerrainSettings small_tiles() {
  TerrainSettings s;
  s.tile_columns = 16;
  return s;
}

}  // namespace

TEST(ChangeGeneration, TwoObserversEachSeeWhatChangedSinceTheyLooked) {
  Terrain t(small_tiles());
  EXPECT_EQ(t.generation(), 1u);
  EXPECT_TRUE(t.changed_since(0).empty());  // nothing changed yet

  const std::uint64_t early = t.generation();
  const std::vector<double> at_early = snapshot(t);
  press(t, -0.15, 0.01);
  const std::uint64_t late = t.generation();
  EXPECT_GT(late, early);
  const std::vector<double> at_late = snapshot(t);
  press(t, 0.15, 0.01);

  // The early observer sees both prints, the late one only the second: each is complete...
  const std::vector<shore::GridRect> for_early = t.changed_since(early);
  const std::vector<shore::GridRect> for_late = t.changed_since(late);
  EXPECT_GT(expect_changes_covered(at_early, t, for_early), 0);
  EXPECT_GT(expect_changes_covered(at_late, t, for_late), 0);
  // ...and tight: every rectangle holds a change the observer has not seen.
  expect_no_stale_rectangles(at_early, t, for_early);
  expect_no_stale_rectangles(at_late, t, for_late);
  EXPECT_TRUE(covered(for_early, t.column_i(-0.15), 0));
  // Asking does not consume: the same question gives the same answer, and take_changed
  // still reports everything since it was last called (never).
  EXPECT_EQ(t.changed_since(early).size(), for_early.size());
  EXPECT_GE(t.take_changed().size(), for_late.size());
  EXPECT_EQ(t.changed_since(late).size(), for_late.size());
  EXPECT_TRUE(t.changed_since(t.generation()).empty());
}

TEST(ChangeGeneration, RectanglesArePerTileInKeyOrderAndInsideTheirTile) {
  Terrain t(small_tiles());
  press(t, 0.0, 0.02);
  const std::vector<shore::GridRect> rects = t.changed_since(0);
  ASSERT_GT(rects.size(), 1u);
  for (std::size_t k = 0; k < rects.size(); ++k) {
    const shore::GridRect& r = rects[k];
    const std::int64_t tx = (r.i0 >= 0 ? r.i0 : r.i0 - 15) / 16, ty = (r.j0 >= 0 ? r.j0 : r.j0 - 15) / 16;
    EXPECT_GE(r.i0, tx * 16);
    EXPECT_LE(r.i0 + r.nx, (tx + 1) * 16);
    EXPECT_GE(r.j0, ty * 16);
    EXPECT_LE(r.j0 + r.ny, (ty + 1) * 16);
    if (k > 0) {
      const shore::GridRect& p = rects[k - 1];
      const std::int64_t px = (p.i0 >= 0 ? p.i0 : p.i0 - 15) / 16, py = (p.j0 >= 0 ? p.j0 : p.j0 - 15) / 16;
      EXPECT_TRUE(px < tx || (px == tx && py < ty)) << "tile key order";
    }
  }
}

TEST(ChangeGeneration, AnObserverOlderThanTheHistoryGetsWholeTilesStillCoveringEverything) {
  Terrain t(small_tiles());
  const std::uint64_t start = t.generation();
  const std::vector<double> at_start = snapshot(t);
  // Many single-column edits: the history is trimmed long before the end.
  for (int k = 0; k < 3000; ++k) t.set_height(kLo + k % 81, kLo + (k * 7) % 81, 0.001 * (k % 13));
  const std::vector<shore::GridRect> rects = t.changed_since(start);
  EXPECT_GT(expect_changes_covered(at_start, t, rects), 0);
  for (const shore::GridRect& r : rects) {  // whole tiles now
    EXPECT_EQ(r.nx, 16);
    EXPECT_EQ(r.ny, 16);
  }
  // A recent observer still gets the tight box of the last edit.
  const std::uint64_t recent = t.generation();
  t.set_height(3, 4, 0.5);
  const std::vector<shore::GridRect> last = t.changed_since(recent);
  ASSERT_EQ(last.size(), 1u);
  EXPECT_EQ(last[0].i0, 3);
  EXPECT_EQ(last[0].j0, 4);
  EXPECT_EQ(last[0].nx, 1);
  EXPECT_EQ(last[0].ny, 1);
}

TEST(ChangeGeneration, LoadedTilesAreReportedSinceZero) {
  Terrain t(small_tiles());
  press(t, 0.0, 0.02);
  const std::filesystem::path file = std::filesystem::path(::testing::TempDir()) / "changes.soil";
  t.save(file);
  const Terrain back = Terrain::load(file);
  EXPECT_EQ(back.generation(), 1u);
  const std::vector<shore::GridRect> rects = back.changed_since(0);
  EXPECT_EQ(rects.size(), back.tile_count());
  EXPECT_TRUE(back.changed_since(back.generation()).empty());
  std::filesystem::remove(file);
}
