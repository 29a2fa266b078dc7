// Soil deltas: a replica driven only by deltas follows a server whose sphere ploughs a rut
// (exact: bit for bit; quantised: within the quantum), sees the same changed tiles, and
// refuses corrupt, truncated, reordered and foreign deltas without changing.

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <vector>

#include "shore/core/error.h"
#include "shore/core/hash.h"
#include "shore/terrain/soil_delta.h"
#include "terrain_fixtures.h"

namespace shore::terrain {
namespace {

using testing::sphere_envelope;

TerrainSettings sand() { return testing::coarse_sand(); }

// The sphere's path: x from 0.2 to 1.4 m over `steps` steps, 3 cm deep.
void plough(Terrain& t, int step, int steps) {
  const double x = 0.2 + 1.2 * step / steps;
  const EnvelopeRaster env = sphere_envelope(t, x, 0.3, 0.15 - 0.03, 0.15);
  Imprint imprint;
  imprint.envelope = &env;
  imprint.velocity.x = 1.2;
  t.step(std::span<const Imprint>(&imprint, 1));
}

const shore::GridRect kArea{-5, -5, 90, 40};  // beyond everything the sphere reaches

std::vector<double> heights_of(const Terrain& t) {
  std::vector<double> h(static_cast<std::size_t>(kArea.nx) * kArea.ny);
  t.heights(kArea, h);
  return h;
}

std::vector<double> sinkage_of(const Terrain& t) {
  std::vector<double> s;
  for (std::int64_t j = kArea.j0; j < kArea.j0 + kArea.ny; ++j)
    for (std::int64_t i = kArea.i0; i < kArea.i0 + kArea.nx; ++i) s.push_back(t.sinkage(i, j));
  return s;
}

bool same_rects(const std::vector<shore::GridRect>& a, const std::vector<shore::GridRect>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (a[k].i0 != b[k].i0 || a[k].j0 != b[k].j0 || a[k].nx != b[k].nx || a[k].ny != b[k].ny) return false;
  return true;
}

struct SyncRun {
  double max_height_error = 0.0, max_sinkage_error = 0.0;
  std::size_t bytes = 0, columns = 0;
  bool same_notifications = true;
};

// 120 steps, a delta every 5 (20 Hz at 100 steps/s).
SyncRun sync(double quantum) {
  Terrain server(sand()), replica(sand());
  (void)server.take_changed(), (void)replica.take_changed();
  DeltaSettings ds;
  ds.quantum = quantum;
  SyncRun out;
  std::uint64_t sent = server.generation(), mirrored = sent;
  for (int step = 0; step < 120; ++step) {
    plough(server, step, 120);
    if (step % 5 != 4) continue;
    DeltaStats st;
    const auto delta = SoilDelta::encode(server, sent, ds, &st);
    sent = server.generation();
    mirrored = SoilDelta::apply(replica, delta, mirrored);
    EXPECT_EQ(mirrored, sent);
    out.bytes += st.bytes, out.columns += st.columns;
    // The replica is told of the same columns as the server, tile by tile.
    out.same_notifications = out.same_notifications && same_rects(server.take_changed(), replica.take_changed());
  }
  const auto hs = heights_of(server), hr = heights_of(replica);
  const auto ss = sinkage_of(server), sr = sinkage_of(replica);
  for (std::size_t k = 0; k < hs.size(); ++k) {
    out.max_height_error = std::max(out.max_height_error, std::fabs(hs[k] - hr[k]));
    out.max_sinkage_error = std::max(out.max_sinkage_error, std::fabs(ss[k] - sr[k]));
  }
  return out;
}

TEST(SoilDelta, ExactReplicaIsBitIdentical) {
  const SyncRun r = sync(0.0);
  EXPECT_EQ(r.max_height_error, 0.0);
  EXPECT_EQ(r.max_sinkage_error, 0.0);
  EXPECT_TRUE(r.same_notifications);
  EXPECT_GT(r.columns, 0u);
  std::printf("exact: %.2f bytes per sent column (SynChrono: 16)\n", double(r.bytes) / double(r.columns));
}

TEST(SoilDelta, QuantisedReplicaIsWithinTheQuantumAndSmall) {
  const double q = 1e-4;
  const SyncRun r = sync(q);
  EXPECT_LE(r.max_height_error, q);
  EXPECT_LE(r.max_sinkage_error, q);
  EXPECT_GT(r.max_height_error, 0.0);  // it is quantised: the rut's heights are not multiples of 0.1 mm
  EXPECT_TRUE(r.same_notifications);
  const double per_column = double(r.bytes) / double(r.columns);
  std::printf("0.1 mm: %.2f bytes per sent column (SynChrono: 16, target <= 2)\n", per_column);
  EXPECT_LT(per_column, 16.0);
}

TEST(SoilDelta, SnapshotBringsALateJoinerUp) {
  Terrain server(sand());
  for (int step = 0; step < 40; ++step) plough(server, step, 40);
  Terrain late(sand());
  const std::uint64_t at = SoilDelta::apply(late, SoilDelta::encode(server, 0, DeltaSettings{0.0}), 12345);
  EXPECT_EQ(at, server.generation());
  EXPECT_EQ(heights_of(late), heights_of(server));
  EXPECT_EQ(sinkage_of(late), sinkage_of(server));
  EXPECT_EQ(late.volume().compacted, server.volume().compacted);
}

class SoilDeltaRefusal : public ::testing::Test {
 protected:
  void SetUp() override {
    for (int step = 0; step < 20; ++step) plough(server, step, 40);
    first = SoilDelta::encode(server, 1, DeltaSettings{0.0});
    g1 = server.generation();
    for (int step = 20; step < 40; ++step) plough(server, step, 40);
    second = SoilDelta::encode(server, g1, DeltaSettings{0.0});
    at = SoilDelta::apply(replica, first, 1);
    hash = replica.state_hash();
  }
  void expect_refused(const std::vector<unsigned char>& delta, const char* says) {
    try {
      (void)SoilDelta::apply(replica, delta, at);
      ADD_FAILURE() << "accepted";
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
    EXPECT_EQ(replica.state_hash(), hash);
  }
  Terrain server{sand()}, replica{sand()};
  std::vector<unsigned char> first, second;
  std::uint64_t g1 = 0, at = 0, hash = 0;
};

TEST_F(SoilDeltaRefusal, CorruptTruncatedReorderedForeign) {
  ASSERT_EQ(at, g1);
  auto corrupt = second;
  corrupt[corrupt.size() / 2] ^= 0x10;
  expect_refused(corrupt, "checksum");
  expect_refused(std::vector<unsigned char>(second.begin(), second.end() - 7), "truncated");
  expect_refused(std::vector<unsigned char>(second.begin(), second.begin() + 20), "truncated");
  expect_refused(first, "out of order");  // a repeat
  auto foreign = second;
  foreign[0] = 'X';
  expect_refused(foreign, "magic");
  auto future = second;
  future[8] = 9;
  expect_refused(future, "unsupported version 9");
  EXPECT_NO_THROW(at = SoilDelta::apply(replica, second, at));
  EXPECT_EQ(heights_of(replica), heights_of(server));
}

// A payload size the zstd frame cannot hold (here 2 GiB, the most the header allows), with a
// valid checksum: refused before its buffer is allocated (found by fuzz_soil_delta, where
// such sizes cost gigabytes of memory per input).
TEST_F(SoilDeltaRefusal, APayloadSizeTheFrameCannotHoldIsRefused) {
  constexpr std::size_t kRawSizeAt = 8 + 4 + 4 + 8 + 8 + 8;  // magic, version, mark, quantum, from, to
  for (const std::uint64_t raw_size : {std::uint64_t{1} << 31, std::uint64_t{1}}) {
    auto resized = second;
    std::memcpy(resized.data() + kRawSizeAt, &raw_size, sizeof raw_size);
    StateHash sum;
    sum.add_bytes(resized.data(), resized.size() - 8);
    const std::uint64_t checksum = sum.value();
    std::memcpy(resized.data() + resized.size() - 8, &checksum, sizeof checksum);
    expect_refused(resized, "that says otherwise");
  }
}

TEST(SoilDelta, BadSettingsAreNamed) {
  Terrain t(sand());
  try {
    (void)SoilDelta::encode(t, 0, DeltaSettings{-1.0});
    ADD_FAILURE();
  } catch (const InvalidSetting& e) {
    EXPECT_EQ(e.field(), "terrain.DeltaSettings.quantum");
  }
  t.set_height(3, 3, 1e6);
  EXPECT_THROW((void)SoilDelta::encode(t, 0, DeltaSettings{1e-12}), InvalidSetting);
}

// A checkpoint of the terrain alone: restore mid-run from its bytes and the continued run
// is bit-identical to the uninterrupted one.
TEST(SoilDelta, TerrainBytesContinueIdentically) {
  Terrain a(sand());
  for (int step = 0; step < 30; ++step) plough(a, step, 60);
  Terrain b = Terrain::load_bytes(a.save_bytes(), "mid-run");
  for (int step = 30; step < 60; ++step) plough(a, step, 60), plough(b, step, 60);
  EXPECT_EQ(a.state_hash(), b.state_hash());
}

// The plate of testing::slide_clinging_plate, from column (20, 10).
void slide(Terrain& t, int step) { testing::slide_clinging_plate(t, step, 20, 10, 2); }

// An exact delta sent between the two clinging steps of the plate's cadence carries when
// its soil was last stepped (version 6): the replica then continues as the server does.
TEST(SoilDelta, AnExactReplicaBetweenTwoClingingStepsContinuesIdentically) {
  Terrain server(sand()), replica(sand());
  const std::uint64_t start = server.generation();
  DeltaSettings exact;
  exact.quantum = 0.0;
  int step = 0;
  for (; step < 9; ++step) slide(server, step);  // the last (8) clung; then 9, odd, keeps it as it is
  const auto at_its_step = SoilDelta::encode(server, start, exact);
  slide(server, step++);
  ASSERT_GT(server.volume().clinging, 0.0) << "nothing clings to the plate: this tests nothing";
  const auto delta = SoilDelta::encode(server, start, exact);
  std::uint32_t version = 0, before = 0;
  std::memcpy(&version, delta.data() + 8, sizeof version);
  std::memcpy(&before, at_its_step.data() + 8, sizeof before);
  EXPECT_EQ(before, 2u) << "every body stepped on the last step: the bytes of before";
  EXPECT_EQ(version, 6u);
  (void)SoilDelta::apply(replica, delta, replica.generation());
  EXPECT_EQ(replica.state_hash(), server.state_hash());
  for (; step < 30; ++step) slide(server, step), slide(replica, step);
  EXPECT_EQ(replica.state_hash(), server.state_hash());
  EXPECT_EQ(replica.volume().clinging, server.volume().clinging);
}

}  // namespace
}  // namespace shore::terrain
