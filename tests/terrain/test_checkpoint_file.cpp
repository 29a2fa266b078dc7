// The checkpoint container (shore/core/checkpoint_file.h) with the terrain's own state as
// a section: a run restored mid-way from the file continues bit-identically; a corrupt,
// truncated, foreign, future or other-precision file is refused naming the problem.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "shore/core/checkpoint_file.h"
#include "shore/terrain/terrain.h"
#include "terrain_fixtures.h"

namespace shore::terrain {
namespace {

TerrainSettings sand() { return testing::coarse_sand(); }

// A sphere ploughing at 3 cm and a second pressing and lifting: erosion keeps working
// between steps (the unsettled boxes), so the saved state must carry more than heights.
void step(Terrain& t, int k) {
  const double x = 0.2 + 0.01 * k;
  const EnvelopeRaster a = testing::sphere_envelope(t, x, 0.3, 0.12, 0.15);
  const EnvelopeRaster b = testing::sphere_envelope(t, 0.8, 0.8, (k / 10) % 2 == 0 ? 0.09 : 0.5, 0.1);
  Imprint imprints[2];
  imprints[0].envelope = &a, imprints[0].velocity.x = 1.0;
  imprints[1].envelope = &b;
  t.step(imprints);
}

std::filesystem::path temp_file(const char* name) { return std::filesystem::temp_directory_path() / name; }

std::string error_of(const std::vector<unsigned char>& bytes, std::uint32_t scalar_bytes = 0) {
  try {
    CheckpointReader r(bytes, "test.ckp", scalar_bytes);
    (void)Terrain::load_bytes(r.section("TERRAIN"), r.describe("TERRAIN"));
  } catch (const FileError& e) {
    return e.what();
  }
  return "";
}

TEST(Checkpoint, SoilRunContinuesIdenticallyFromTheFile) {
  Terrain uninterrupted(sand());
  for (int k = 0; k < 45; ++k) step(uninterrupted, k);
  CheckpointWriter w(4);
  w.add("TERRAIN", uninterrupted.save_bytes());
  const auto file = temp_file("shore_checkpoint_soil.ckp");
  w.save(file);
  EXPECT_FALSE(std::filesystem::exists(file.string() + ".tmp"));
  const CheckpointReader r = CheckpointReader::open(file, 4);
  Terrain restored = Terrain::load_bytes(r.section("TERRAIN"), r.describe("TERRAIN"));
  EXPECT_EQ(restored.state_hash(), uninterrupted.state_hash());
  for (int k = 45; k < 100; ++k) step(uninterrupted, k), step(restored, k);
  EXPECT_EQ(restored.state_hash(), uninterrupted.state_hash());
  EXPECT_EQ(restored.volume().compacted, uninterrupted.volume().compacted);
  std::filesystem::remove(file);
}

// A sliding plate whose clinging soil is stepped every second step, saved after a step
// that skipped it: the restored body's next clinging step still covers two steps' time.
TEST(Checkpoint, ABodyBetweenTwoClingingStepsContinuesIdenticallyFromTheFile) {
  const auto slide = [](Terrain& t, int k) { testing::slide_clinging_plate(t, k, 10, 10, 4); };
  Terrain uninterrupted(sand());
  int k = 0;
  for (; k < 11; ++k) slide(uninterrupted, k);  // 10 clung, 11 will not
  slide(uninterrupted, k++);
  ASSERT_GT(uninterrupted.volume().clinging, 0.0) << "nothing clings to the plate: this tests nothing";
  CheckpointWriter w(4);
  w.add("TERRAIN", uninterrupted.save_bytes());
  const auto file = temp_file("shore_checkpoint_cadence.ckp");
  w.save(file);
  const CheckpointReader r = CheckpointReader::open(file, 4);
  Terrain restored = Terrain::load_bytes(r.section("TERRAIN"), r.describe("TERRAIN"));
  EXPECT_EQ(restored.state_hash(), uninterrupted.state_hash());
  for (; k < 40; ++k) slide(uninterrupted, k), slide(restored, k);
  EXPECT_EQ(restored.state_hash(), uninterrupted.state_hash());
  EXPECT_EQ(restored.volume().clinging, uninterrupted.volume().clinging);
  std::filesystem::remove(file);
}

TEST(Checkpoint, BadFilesAreRefusedNamingTheProblem) {
  Terrain t(sand());
  for (int k = 0; k < 10; ++k) step(t, k);
  CheckpointWriter w(4);
  w.add("TERRAIN", t.save_bytes());
  const std::vector<unsigned char> good = w.bytes();
  EXPECT_EQ(error_of(good), "");
  auto corrupt = good;
  corrupt[corrupt.size() / 2] ^= 1;
  EXPECT_NE(error_of(corrupt).find("checksum mismatch"), std::string::npos);
  EXPECT_NE(error_of({good.begin(), good.begin() + 40}).find("truncated"), std::string::npos);
  EXPECT_NE(error_of({good.begin(), good.begin() + 10}).find("truncated"), std::string::npos);
  auto foreign = good;
  foreign[0] = 'X';
  EXPECT_NE(error_of(foreign).find("not a Shore checkpoint"), std::string::npos);
  EXPECT_NE(error_of(good, 8).find("32-bit Bullet scalars, this one uses 64-bit"), std::string::npos);
  CheckpointWriter empty;
  EXPECT_NE(error_of(empty.bytes()).find("no section TERRAIN"), std::string::npos);
  EXPECT_THROW(w.add("TERRAIN", {}), InvalidSetting);
  EXPECT_THROW(w.add("TOO-LONG-TAG", {}), InvalidSetting);
}

TEST(Checkpoint, TerrainSectionErrorsNameTheSection) {
  CheckpointWriter w;
  w.add("TERRAIN", {1, 2, 3});
  EXPECT_NE(error_of(w.bytes()).find("checkpoint test.ckp, section TERRAIN"), std::string::npos);
}

TEST(Checkpoint, UnwritableTargetIsAFileError) {
  CheckpointWriter w;
  EXPECT_THROW(w.save("/nonexistent-dir/x.ckp"), FileError);
}

}  // namespace
}  // namespace shore::terrain
