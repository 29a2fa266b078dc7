// Surface::save_state / restore_state through a checkpoint: a wave field restored mid-run
// (some tiles asleep, some awake, 3-D and vertical modes, open and fixed edges) continues
// bit-identically; bytes of another grid or version, or cut short, are refused and leave
// the surface as it was.

#include <gtest/gtest.h>

#include "shore/core/checkpoint_file.h"
#include "shore/water/surface.h"

namespace shore::water {
namespace {

SurfaceSettings pool(SurfaceMode mode, Boundary boundary) {
  SurfaceSettings s = SurfaceSettings::paper();
  s.nx = 96, s.ny = 80;
  s.mode = mode;
  s.boundary = boundary;
  s.threads = 1;
  s.sleep.tile = 16;
  return s;
}

void drive(Surface& s, int from, int to) {
  for (int k = from; k < to; ++k) {
    if (k % 25 == 0) {
      Disturbance d;
      d.x = 10.0 + k % 40, d.y = 12.0, d.radius = 2.0, d.amplitude = 0.3;
      s.disturb(d);
    }
    s.step(0.4);
  }
}

// Returns the tiles at the checkpoint.
TileStats continues_identically(SurfaceMode mode, Boundary boundary) {
  Surface uninterrupted(pool(mode, boundary));
  drive(uninterrupted, 0, 60);
  CheckpointWriter w;
  w.add("WATER", uninterrupted.save_state());
  const CheckpointReader r(w.bytes(), "test.ckp");
  Surface restored(pool(mode, boundary));
  restored.restore_state(r.section("WATER"), r.describe("WATER"));
  EXPECT_EQ(restored.state_hash(), uninterrupted.state_hash());
  EXPECT_EQ(restored.time(), uninterrupted.time());
  const TileStats before = uninterrupted.tile_stats();
  drive(uninterrupted, 60, 160), drive(restored, 60, 160);
  EXPECT_EQ(restored.state_hash(), uninterrupted.state_hash());
  EXPECT_EQ(restored.volume(), uninterrupted.volume());
  EXPECT_EQ(restored.tile_stats().awake, uninterrupted.tile_stats().awake);
  return before;
}

TEST(SurfaceCheckpoint, ThreeDimensionalFixedEdgesContinueIdentically) {
  const TileStats at = continues_identically(SurfaceMode::full_3d, Boundary::fixed);
  EXPECT_LT(at.created, at.tiles);  // the far tiles not created yet
}
TEST(SurfaceCheckpoint, VerticalOpenEdgesContinueIdentically) {
  const TileStats at = continues_identically(SurfaceMode::vertical_only, Boundary::open);
  EXPECT_GT(at.created, at.awake);  // some tiles asleep
}

TEST(SurfaceCheckpoint, ForeignOrShortStateIsRefusedAndChangesNothing) {
  Surface a(pool(SurfaceMode::full_3d, Boundary::fixed));
  drive(a, 0, 30);
  const std::vector<unsigned char> state = a.save_state();
  SurfaceSettings other = pool(SurfaceMode::full_3d, Boundary::fixed);
  other.nx = 64;
  Surface b(other);
  drive(b, 0, 5);
  const std::uint64_t hash = b.state_hash();
  try {
    b.restore_state(state, "x.ckp");
    ADD_FAILURE();
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("96 x 80"), std::string::npos) << e.what();
  }
  EXPECT_EQ(b.state_hash(), hash);
  Surface c(pool(SurfaceMode::full_3d, Boundary::fixed));
  const std::uint64_t fresh = c.state_hash();
  EXPECT_THROW(c.restore_state({state.data(), state.size() - 3}, "x.ckp"), FileError);
  auto future = state;
  future[0] = 7;
  EXPECT_THROW(c.restore_state(future, "x.ckp"), FileError);
  EXPECT_EQ(c.state_hash(), fresh);
}

}  // namespace
}  // namespace shore::water
