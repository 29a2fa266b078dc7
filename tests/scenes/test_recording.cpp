// Replays: a run recorded with a Recorder and replayed from the file alone (the
// replay restores the initial checkpoint and then only writes the recorded soil deltas and
// body states; it steps nothing) must end in the original run's state hash. The original
// run is the reference. Bad files are refused with a FileError naming the file and the cause.
// Water scenes too: their frames carry the water's state.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "shore/bullet/recording_file.h"
#include "shore/core/error.h"
#include "shore/core/hash.h"
#include "shore/scenes/recording.h"
#include "shore/scenes/runner.h"

using namespace shore::scenes;
namespace fs = std::filesystem;

namespace {

fs::path temp(const std::string& name) { return fs::path(testing::TempDir()) / ("shore_recording_" + name); }

SceneOptions smoke_options(const std::string& name) { return pinning_options(*find_scene(name)); }

/// Records the smoke run of `name` to `file`; returns the run's final state hash.
std::uint64_t record(const std::string& name, const fs::path& file) {
  Recorder recorder(file);
  return run_scene(*find_scene(name), smoke_options(name), ProgressMode::quiet, nullptr, &recorder).state_hash;
}

/// The state hash of the scene as created, before any substep (a replay that applied no
/// frame would end there).
std::uint64_t initial_hash(const std::string& name) {
  return state_hash(find_scene(name)->create(smoke_options(name))->state());
}

std::vector<unsigned char> bytes_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}
void write(const fs::path& file, const std::vector<unsigned char>& bytes) {
  std::ofstream(file, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), bytes.size());
}

/// The message of the FileError replaying `file` throws ("" if none).
std::string replay_error(const fs::path& file) {
  try {
    (void)replay(file, testing::TempDir(), false, nullptr, ProgressMode::quiet);
  } catch (const shore::FileError& e) {
    return e.what();
  }
  return "";
}

class SoilRecording : public testing::TestWithParam<const char*> {};

TEST_P(SoilRecording, ReplaysToTheSameFinalStateHash) {
  const std::string name = GetParam();
  const fs::path file = temp(name + ".rec");
  const std::uint64_t run = record(name, file);
  ASSERT_NE(run, initial_hash(name)) << "the smoke run changed nothing: the replay would test nothing";
  const ReplayResult r = replay(file, testing::TempDir(), false, nullptr, ProgressMode::quiet);
  EXPECT_EQ(r.scene, name);
  EXPECT_EQ(r.recorded_state_hash, run);
  EXPECT_EQ(r.state_hash, run) << "the recording does not carry the whole hashed state";
  EXPECT_GT(r.frames, 2);
  fs::remove(file);
}

// vehicle: one soil painted sand, mud and gravel (a material map) whose replay must end
// with the recorded map (the state hash covers it).
INSTANTIATE_TEST_SUITE_P(Scenes, SoilRecording, testing::Values("footprints", "tracks", "vehicle"));

TEST(Recording, CorruptTruncatedAndForeignFilesAreRefusedNamingTheFile) {
  const fs::path file = temp("bad_source.rec");
  record("footprints", file);
  const std::vector<unsigned char> good = bytes_of(file);
  ASSERT_GT(good.size(), 1000u);

  std::vector<unsigned char> corrupt = good;
  corrupt[corrupt.size() / 2] ^= 0x40;
  const fs::path bad = temp("corrupt.rec");
  write(bad, corrupt);
  std::string m = replay_error(bad);
  EXPECT_NE(m.find(bad.string()), std::string::npos) << m;
  EXPECT_NE(m.find("checksum mismatch"), std::string::npos) << m;

  const fs::path cut = temp("truncated.rec");
  write(cut, std::vector<unsigned char>(good.begin(), good.begin() + static_cast<long>(good.size() / 3)));
  m = replay_error(cut);
  EXPECT_NE(m.find(cut.string()), std::string::npos) << m;
  EXPECT_NE(m.find("truncated"), std::string::npos) << m;

  const fs::path foreign = temp("foreign.rec");
  write(foreign, std::vector<unsigned char>(good.size(), 'x'));
  m = replay_error(foreign);
  EXPECT_NE(m.find("not a Shore recording"), std::string::npos) << m;

  m = replay_error(temp("missing.rec"));
  EXPECT_NE(m.find("cannot open"), std::string::npos) << m;
  for (const fs::path& f : {file, bad, cut, foreign}) fs::remove(f);
}

// Water scenes: each frame carries the water's state (XORed with the previous frame's), and
// the replay writes it, so the replayed water is the run's. The run's water must have
// changed (its hash differs from the scene's initial water hash), else this tests nothing.
TEST(WaterRecording, PondReplaysToTheSameFinalStateHash) {
  const fs::path file = temp("pond.rec");
  Recorder recorder(file);
  const SceneResult run =
      run_scene(*find_scene("pond"), smoke_options("pond"), ProgressMode::quiet, nullptr, &recorder);
  ASSERT_NE(run.state_hash, initial_hash("pond"));
  EXPECT_GT(recorder.sizes().water_states, 0u);
  const ReplayResult r = replay(file, testing::TempDir(), false, nullptr, ProgressMode::quiet);
  EXPECT_EQ(r.scene, "pond");
  EXPECT_EQ(r.recorded_state_hash, run.state_hash);
  EXPECT_EQ(r.state_hash, run.state_hash) << "the recording does not carry the whole hashed state";
  EXPECT_GT(r.frames, 2);
  fs::remove(file);
}

// A water frame that does not restore (cut short, or of another water state version) is
// refused naming the recording, the frame by its substep and the water surface. (A frame
// that restores to another valid state is caught by the final hash instead.)
TEST(WaterRecording, ACorruptWaterFrameIsRefusedNamingTheFrame) {
  const fs::path file = temp("pond_source.rec");
  {
    Recorder recorder(file);
    (void)run_scene(*find_scene("pond"), smoke_options("pond"), ProgressMode::quiet, nullptr, &recorder);
  }
  const std::vector<unsigned char> good = bytes_of(file);
  for (const bool cut : {true, false}) {
    shore::bullet::Recording rec = shore::bullet::read_recording(good, "test");
    ASSERT_GT(rec.frames.size(), 3u);
    ASSERT_EQ(rec.waters, 1u);
    shore::bullet::Recording::Frame& f = rec.frames[rec.frames.size() / 2];
    std::vector<unsigned char> water(f.water_diffs[0].begin(), f.water_diffs[0].end());
    ASSERT_GT(water.size(), 100u);
    if (cut)
      water.resize(water.size() - 8);  // a state of another length: its byte planes no longer fit
    else
      water[0] ^= 0x10;  // byte 0 of the state (plane 0 comes first): its version changes
    f.water_diffs[0] = water;
    const fs::path bad = temp(cut ? "pond_cut_water.rec" : "pond_water_version.rec");
    write(bad, shore::bullet::write_recording(rec));
    const std::string m = replay_error(bad);
    EXPECT_NE(m.find(bad.string()), std::string::npos) << m;
    EXPECT_NE(m.find("frame at substep " + std::to_string(f.substep) + ", water 0"), std::string::npos) << m;
    if (!cut) {
      EXPECT_NE(m.find("water state version"), std::string::npos) << m;
    }
    fs::remove(bad);
  }
  fs::remove(file);
}

// Version 1 files (before water) are refused saying which version they are.
TEST(Recording, AVersionOneFileIsRefusedSayingSo) {
  const fs::path file = temp("v1_source.rec");
  record("footprints", file);
  std::vector<unsigned char> bytes = bytes_of(file);
  const std::uint32_t one = 1;
  std::memcpy(bytes.data() + 8, &one, sizeof one);
  shore::StateHash sum;
  sum.add_bytes(bytes.data(), bytes.size() - 8);
  const std::uint64_t checksum = sum.value();
  std::memcpy(bytes.data() + bytes.size() - 8, &checksum, sizeof checksum);
  const fs::path old = temp("v1.rec");
  write(old, bytes);
  const std::string m = replay_error(old);
  EXPECT_NE(m.find(old.string()), std::string::npos) << m;
  EXPECT_NE(m.find("recording version 1"), std::string::npos) << m;
  EXPECT_NE(m.find("record the run again"), std::string::npos) << m;
  fs::remove(file), fs::remove(old);
}

}  // namespace

namespace {

// The water frames' coding (bullet::StateChain) gives back every state bit for bit: states
// that grow, shrink, change in a few words or in every byte, whatever their alignment.
TEST(WaterRecording, TheStateChainIsExact) {
  std::vector<std::vector<unsigned char>> states;
  std::uint64_t x = 0x9e3779b97f4a7c15ull;
  auto random_byte = [&x] {
    x ^= x << 13, x ^= x >> 7, x ^= x << 17;
    return static_cast<unsigned char>(x >> 24);
  };
  std::vector<unsigned char> s(1001);
  for (auto& b : s) b = random_byte();
  for (int k = 0; k < 12; ++k) {
    if (k % 4 == 1) s.resize(s.size() + 13, 0x7f);
    if (k % 4 == 3) s.resize(s.size() - 29);
    for (int c = 0; c < 5; ++c) s[(static_cast<std::size_t>(random_byte()) * 7 + c) % s.size()] ^= random_byte();
    if (k == 6)
      for (auto& b : s) b = random_byte();
    states.push_back(s);
  }
  shore::bullet::StateChain writer, reader;
  for (const auto& state : states) {
    const std::vector<unsigned char> frame = writer.encode(state);
    EXPECT_EQ(frame.size(), state.size());
    EXPECT_EQ(reader.next(frame), state);
  }
}

}  // namespace
