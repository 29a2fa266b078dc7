// Replays: a run recorded with a Recorder and replayed from the file alone (the
// replay restores the initial checkpoint and then only writes the recorded soil deltas and
// body states; it steps nothing) must end in the original run's state hash. The original
// run is the reference. Bad files are refused with a FileError naming the file and the cause.
// Water scenes too: their frames carry the water's state; multibody scenes (rover) their
// multibodies' states and colliders' world transforms, compared bit for bit with the live
// run's at every frame.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "shore/bullet/body_state.h"
#include "shore/bullet/recording_file.h"
#include "shore/core/error.h"
#include "shore/core/hash.h"
#include "shore/scenes/contents.h"
#include "shore/scenes/multibody_state.h"
#include "shore/scenes/recording.h"
#include "shore/scenes/runner.h"
#include "shore/scenes/world.h"

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

// Version 1 files (before water) are refused saying which version they are (and so are
// versions this build does not know).
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
  const std::uint32_t five = 5;
  std::memcpy(bytes.data() + 8, &five, sizeof five);
  sum = shore::StateHash();
  sum.add_bytes(bytes.data(), bytes.size() - 8);
  const std::uint64_t checksum4 = sum.value();
  std::memcpy(bytes.data() + bytes.size() - 8, &checksum4, sizeof checksum4);
  write(old, bytes);
  EXPECT_NE(replay_error(old).find("unsupported recording version 5 (this build reads 2 to 4)"), std::string::npos)
      << replay_error(old);
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

namespace {

using shore::bullet::Recording;

/// What the pictures and the viewer draw of a scene's multibodies (every collider's world
/// transform: basis rows, origin) and what its state hash covers of them (multibody_state.h),
/// as btScalars.
std::vector<btScalar> multibody_picture(Scene& scene) {
  std::vector<btScalar> v;
  for (btMultiBody* m : scene.contents().world->multibodies()) {
    const std::vector<btScalar> state = multibody_state(*m);
    v.insert(v.end(), state.begin(), state.end());
    for (int part = -1; part < m->getNumLinks(); ++part) {
      const btMultiBodyLinkCollider* c = part < 0 ? m->getBaseCollider() : m->getLinkCollider(part);
      if (c == nullptr) continue;
      const btTransform& t = c->getWorldTransform();
      for (int r = 0; r < 3; ++r)
        for (int a = 0; a < 3; ++a) v.push_back(t.getBasis()[r][a]);
      for (int a = 0; a < 3; ++a) v.push_back(t.getOrigin()[a]);
    }
  }
  return v;
}

bool same_bits(const std::vector<btScalar>& a, const std::vector<btScalar>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(btScalar)) == 0;
}

/// `rec` written to `name` in the temporary folder; the replay's error message.
std::string replay_error_of(const Recording& rec, const std::string& name) {
  const fs::path bad = temp(name);
  write(bad, shore::bullet::write_recording(rec));
  std::string m = replay_error(bad);
  EXPECT_NE(m.find(bad.string()), std::string::npos) << m;
  fs::remove(bad);
  return m;
}

/// Every raycast wheel's world transform (basis rows, origin), what the pictures draw.
std::vector<btScalar> wheel_picture(Scene& scene) {
  std::vector<btScalar> v;
  for (const VehicleContents& c : scene.contents().vehicles)
    for (int k = 0; k < c.vehicle->getNumWheels(); ++k) {
      const btTransform& t = c.vehicle->getWheelInfo(k).m_worldTransform;
      for (int r = 0; r < 3; ++r)
        for (int a = 0; a < 3; ++a) v.push_back(t.getBasis()[r][a]);
      for (int a = 0; a < 3; ++a) v.push_back(t.getOrigin()[a]);
    }
  return v;
}

/// The smoke run of a scene recorded to `file` as run_scene runs it (step, observe, record),
/// keeping the live `picture` after every substep.
struct LiveRun {
  std::map<int, std::vector<btScalar>> pictures;  ///< by substep; 0: as created
  std::uint64_t state_hash = 0;
  Recorder::Sizes sizes;
};
LiveRun record_live(const std::string& name, const fs::path& file,
                    const std::function<std::vector<btScalar>(Scene&)>& picture) {
  const SceneType& type = *find_scene(name);
  const SceneOptions o = smoke_options(name);
  const std::unique_ptr<Scene> scene = type.create(o);
  Recorder recorder(file);
  recorder.begin(type, o, *scene);
  LiveRun live;
  live.pictures[0] = picture(*scene);
  for (int k = 1; k <= o.substeps(); ++k) {
    scene->step();
    scene->observe();
    recorder.after_substep(*scene, k);
    live.pictures[k] = picture(*scene);
  }
  live.state_hash = state_hash(scene->state());
  recorder.finish(live.state_hash);
  live.sizes = recorder.sizes();
  return live;
}

LiveRun record_rover(const fs::path& file) {
  LiveRun live = record_live("rover", file, multibody_picture);
  EXPECT_GT(live.sizes.multibodies, 0u);
  return live;
}

/// Replays `file`; every frame's `picture` must be the live run's, bit for bit, and the
/// replay must end in the run's state hash.
void expect_replay_matches(const fs::path& file, const LiveRun& live,
                           const std::function<std::vector<btScalar>(Scene&)>& picture) {
  int compared = 0;
  const ReplayResult r =
      replay(file, testing::TempDir(), false, nullptr, ProgressMode::quiet, [&](Scene& scene, int substep) {
        ++compared;
        EXPECT_TRUE(same_bits(picture(scene), live.pictures.at(substep))) << "frame at substep " << substep;
      });
  EXPECT_EQ(compared, r.frames);
  EXPECT_GT(r.frames, 2);
  EXPECT_EQ(r.recorded_state_hash, live.state_hash);
  EXPECT_EQ(r.state_hash, live.state_hash) << "the recording does not carry the whole hashed state";
}

// rover: a six-wheeled btMultiBody. At every recorded frame the replay's multibody (its
// state and every collider's world transform, what the pictures draw) is the live run's,
// bit for bit, and the replay ends in the run's state hash. The rover must have moved
// (else a replay that wrote nothing would pass). With the replay's multibody frames left
// out, both fail (tried: the links stay where the initial checkpoint put them).
TEST(MultiBodyRecording, RoverReplaysItsLinksBitForBitAtEveryFrame) {
  const fs::path file = temp("rover.rec");
  const LiveRun live = record_rover(file);
  ASSERT_FALSE(live.pictures.at(0).empty());
  ASSERT_FALSE(same_bits(live.pictures.at(0), live.pictures.rbegin()->second)) << "the rover did not move";
  expect_replay_matches(file, live, multibody_picture);
  fs::remove(file);
}

// rally: a btRaycastVehicle. At every recorded frame the replay's wheels (their world
// transforms: where the suspension, the steering and the spin put them, what the pictures
// draw) are the live run's, bit for bit. Without the recorded wheels (a version 3 file) they are not: the replay draws
// them at the suspension length the replaying vehicle last had, unturned.
TEST(VehicleRecording, RallyReplaysItsWheelsBitForBitAtEveryFrame) {
  const fs::path file = temp("rally.rec");
  const LiveRun live = record_live("rally", file, wheel_picture);
  ASSERT_EQ(live.pictures.at(0).size(), 4u * 12u);
  ASSERT_FALSE(same_bits(live.pictures.at(0), live.pictures.rbegin()->second)) << "the wheels did not move";
  EXPECT_GT(live.sizes.wheels, 0u);
  expect_replay_matches(file, live, wheel_picture);

  Recording old = shore::bullet::read_recording(bytes_of(file), "test");
  ASSERT_EQ(old.vehicle_wheels, std::vector<std::uint32_t>{4});
  old.version = 3;
  EXPECT_THROW((void)shore::bullet::write_recording(old), shore::InvalidSetting);  // it would lose them
  old.vehicle_wheels.clear();
  for (Recording::Frame& f : old.frames) f.wheels = {};
  const fs::path v3 = temp("rally_v3.rec");
  write(v3, shore::bullet::write_recording(old));
  int differing = 0;
  const ReplayResult r =
      replay(v3, testing::TempDir(), false, nullptr, ProgressMode::quiet, [&](Scene& scene, int substep) {
        differing += same_bits(wheel_picture(scene), live.pictures.at(substep)) ? 0 : 1;
      });
  EXPECT_EQ(r.state_hash, live.state_hash) << "a version 3 file still replays the hashed state";
  EXPECT_GT(differing, r.frames / 2) << "without recorded wheels the replay cannot draw them as the run had them";
  for (const fs::path& f : {file, v3}) fs::remove(f);
}

// A wheel section that does not fit the scene, or holds a non-finite value, is refused naming
// the recording, the vehicle and the wheel.
TEST(VehicleRecording, ACorruptWheelSectionIsRefusedNamingTheWheel) {
  const fs::path file = temp("rally_source.rec");
  (void)record_live("rally", file, wheel_picture);
  const std::vector<unsigned char> good = bytes_of(file);
  {  // a vehicle of three wheels: the scene's has four
    Recording rec = shore::bullet::read_recording(good, "test");
    rec.vehicle_wheels[0] = 3;
    std::vector<std::vector<unsigned char>> kept;
    for (Recording::Frame& f : rec.frames) {
      kept.emplace_back(f.wheels.begin(), f.wheels.end() - Recording::kWheelScalars * sizeof(btScalar));
      f.wheels = kept.back();
    }
    const std::string m = replay_error_of(rec, "rally_wheels.rec");
    EXPECT_NE(m.find("vehicle 0: holds 3 wheels, the scene's has 4"), std::string::npos) << m;
  }
  {  // a rotation that is not finite
    Recording rec = shore::bullet::read_recording(good, "test");
    std::vector<unsigned char> bad(rec.frames[1].wheels.begin(), rec.frames[1].wheels.end());
    const btScalar inf = std::numeric_limits<btScalar>::infinity();
    std::memcpy(bad.data() + (Recording::kWheelScalars * 2 + 11) * sizeof(btScalar), &inf, sizeof inf);  // wheel 2's z
    rec.frames[1].wheels = bad;
    const std::string m = replay_error_of(rec, "rally_inf.rec");
    EXPECT_NE(m.find("vehicle 0, wheel 2: corrupt (its world transform holds inf, not finite)"), std::string::npos)
        << m;
  }
  {  // the file layer: a frame's wheel section of the wrong size is not written
    Recording rec = shore::bullet::read_recording(good, "test");
    rec.frames[0].wheels = {};
    EXPECT_THROW((void)shore::bullet::write_recording(rec), shore::InvalidSetting);
  }
  fs::remove(file);
}

// A multibody section that does not fit the scene, or holds a non-finite value, is refused
// naming the recording, the multibody and the field (and the frame by its substep).
TEST(MultiBodyRecording, ACorruptMultibodySectionIsRefusedNamingTheField) {
  const fs::path file = temp("rover_source.rec");
  (void)record_rover(file);
  const std::vector<unsigned char> good = bytes_of(file);
  {  // one link more (no collider: the frames' sizes stay the same)
    Recording rec = shore::bullet::read_recording(good, "test");
    ASSERT_EQ(rec.multibodies.size(), 1u);
    ASSERT_EQ(rec.multibodies[0].links, 6u);
    rec.multibodies[0].links = 7;
    rec.multibodies[0].colliders.push_back(0);
    const std::string m = replay_error_of(rec, "rover_links.rec");
    EXPECT_NE(m.find("multibody 0: link count 7, the scene's has 6"), std::string::npos) << m;
  }
  {  // the collider moved from link 5 to the new link 6
    Recording rec = shore::bullet::read_recording(good, "test");
    rec.multibodies[0].links = 7;
    rec.multibodies[0].colliders.back() = 0;
    rec.multibodies[0].colliders.push_back(1);
    const std::string m = replay_error_of(rec, "rover_colliders.rec");
    EXPECT_NE(m.find("multibody 0: link count 7"), std::string::npos) << m;
  }
  {  // no multibody at all
    Recording rec = shore::bullet::read_recording(good, "test");
    rec.multibodies.clear();
    for (Recording::Frame& f : rec.frames) f.multibodies = {};
    const std::string m = replay_error_of(rec, "rover_none.rec");
    EXPECT_NE(m.find("holds 0 multibodies, the scene has 1"), std::string::npos) << m;
  }
  // Non-finite: the middle frame's first state value (the base's x), and link 2's collider
  // origin x.
  const std::uint32_t values = shore::bullet::read_recording(good, "test").multibodies[0].values;
  ASSERT_EQ(values, 13u + 6u * 2u);                             // base, then each revolute wheel's angle and rate
  const std::size_t base_x = 0, link2_x = values + 12 * 3 + 9;  // colliders: base, link 0, 1, 2
  for (const std::size_t at : {base_x, link2_x}) {
    Recording rec = shore::bullet::read_recording(good, "test");
    Recording::Frame& f = rec.frames[rec.frames.size() / 2];
    std::vector<btScalar> v(f.multibodies.size() / sizeof(btScalar));
    std::memcpy(v.data(), f.multibodies.data(), f.multibodies.size());
    v[at] = std::numeric_limits<btScalar>::infinity();
    const std::vector<unsigned char> bytes(reinterpret_cast<const unsigned char*>(v.data()),
                                           reinterpret_cast<const unsigned char*>(v.data() + v.size()));
    f.multibodies = bytes;
    const std::string m = replay_error_of(rec, "rover_inf.rec");
    EXPECT_NE(m.find("frame at substep " + std::to_string(f.substep) + ", multibody 0"), std::string::npos) << m;
    EXPECT_NE(m.find(at == base_x ? "state value 0 of 25 is inf" : "link 2's collider world transform is inf"),
              std::string::npos)
        << m;
  }
  fs::remove(file);
}

// Version 2 files (before multibodies) still replay, to the run's hash, for scenes without
// multibodies (footprints: written by this build's version 2 writer; rigid_drop: a file
// the version 2 build wrote, committed), and are refused saying so for scenes with some.
TEST(MultiBodyRecording, AVersionTwoFileStillReplaysWithoutMultibodies) {
  const fs::path file = temp("v2_source.rec");
  const std::uint64_t run = record("footprints", file);
  Recording rec = shore::bullet::read_recording(bytes_of(file), "test");
  ASSERT_TRUE(rec.multibodies.empty());
  rec.version = 2;
  const fs::path old = temp("v2.rec");
  write(old, shore::bullet::write_recording(rec));
  const ReplayResult r = replay(old, testing::TempDir(), false, nullptr, ProgressMode::quiet);
  EXPECT_EQ(r.state_hash, run);
  EXPECT_EQ(r.recorded_state_hash, run);

  if (shore::bullet::scalar_bytes() == 4) {  // the committed file is a float build's
    const fs::path committed = fs::path(SHORE_RECORDING_DATA_DIR) / "rigid_drop_v2.rec";
    const std::vector<unsigned char> bytes = bytes_of(committed);
    ASSERT_GT(bytes.size(), 12u) << committed;
    std::uint32_t version = 0;
    std::memcpy(&version, bytes.data() + 8, sizeof version);
    ASSERT_EQ(version, 2u);
    const ReplayResult c = replay(committed, testing::TempDir(), false, nullptr, ProgressMode::quiet);
    EXPECT_EQ(c.scene, "rigid_drop");
    EXPECT_EQ(c.state_hash, c.recorded_state_hash);
    EXPECT_GT(c.frames, 2);
  }

  const fs::path rover = temp("rover_v2_source.rec");
  (void)record_rover(rover);
  Recording r2 = shore::bullet::read_recording(bytes_of(rover), "test");
  r2.version = 2;
  EXPECT_THROW((void)shore::bullet::write_recording(r2), shore::InvalidSetting);  // it would lose them
  r2.multibodies.clear();
  for (Recording::Frame& f : r2.frames) f.multibodies = {};
  const std::string m = replay_error_of(r2, "rover_v2.rec");
  EXPECT_NE(m.find("recording version 2 (written before recordings held multibodies)"), std::string::npos) << m;
  EXPECT_NE(m.find("record the run again"), std::string::npos) << m;
  for (const fs::path& f : {file, old, rover}) fs::remove(f);
}

// The file layer refuses a collider flag other than 0 or 1, naming the multibody and part.
TEST(MultiBodyRecording, ACorruptColliderFlagIsRefused) {
  const fs::path file = temp("rover_flag_source.rec");
  (void)record_rover(file);
  Recording rec = shore::bullet::read_recording(bytes_of(file), "test");
  rec.multibodies[0].colliders[3] = 2;  // link 2's
  try {
    (void)shore::bullet::read_recording(shore::bullet::write_recording(rec), "flagged");
    ADD_FAILURE() << "a collider flag of 2 was accepted";
  } catch (const shore::FileError& e) {
    EXPECT_NE(
        std::string(e.what()).find("flagged: multibody 0: corrupt (collider flag of link 2 is 2, allowed 0 or 1)"),
        std::string::npos)
        << e.what();
  }
  fs::remove(file);
}

}  // namespace
