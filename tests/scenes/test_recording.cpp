// Replays (issue 20): a run recorded with a Recorder and replayed from the file alone (the
// replay restores the initial checkpoint and then only writes the recorded soil deltas and
// body states; it steps nothing) must end in the original run's state hash. The original
// run is the reference. Bad files are refused with a FileError naming the file and the cause.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "shore/core/error.h"
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

INSTANTIATE_TEST_SUITE_P(Scenes, SoilRecording, testing::Values("footprints", "tracks"));

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

TEST(Recording, ScenesWithWaterAreRefused) {
  Recorder recorder(temp("pond.rec"));
  EXPECT_THROW(run_scene(*find_scene("pond"), smoke_options("pond"), ProgressMode::quiet, nullptr, &recorder),
               shore::InvalidSetting);
  EXPECT_FALSE(fs::exists(temp("pond.rec")));
}

}  // namespace
