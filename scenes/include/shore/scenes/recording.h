#pragma once
// Recordings of a scene run and their replay (docs/checkpoints.md, "Replays").
//
// What a recording carries, so that a replay's final state hash equal to the run's means
// something: the scene's name and options, its initial checkpoint (checkpoint.h: soils,
// water, couplings, bodies, clock), then per frame (30 per simulated second, every filmstrip
// substep and the last substep) each soil's exact delta since the previous frame
// (soil_delta.h with quantum 0: heights, sinkages, volume bookkeeping and the spray state),
// every body's world transform and linear and angular velocity, in the order the scene
// added them (World::bodies(); not bullet::save_bodies, whose collision-object order
// changes as the couplings add and remove heightfield tiles during a run), every
// multibody's state (World::multibodies(), multibody_state.h: base pose and velocities,
// joint positions and velocities) and each of its colliders' world transforms, every raycast
// vehicle's wheels (SceneContents::vehicles: suspension length, steering, rotation, so that a
// replay draws each wheel where the run had it), and each water
// surface's whole state (Surface::save_state) XORed with the previous frame's, so that what
// did not change is zeros for the file's zstd. A replay does NOT step the physics: it
// restores the initial checkpoint into a fresh scene and then only writes the recorded
// columns, spray, water, bodies and multibodies into it, frame by frame. So its state hash equals the
// run's only if the recording holds the whole hashed state (the test compares them, and a
// replay that misses any soil column, spray particle, water node, body or multibody would
// differ),
// and its pictures show exactly the recorded states. The water couplings' own state (not
// hashed, read only by the next step) is not recorded per frame.
//
// File layout: shore/bullet/recording_file.h (version 4). Version 3 files (without wheels)
// replay with the wheels where the replaying vehicle last had them. Version 2 files (without
// multibodies) replay as before for scenes without multibodies and are refused, saying so,
// for scenes with some; version 1 files (without water) are refused with a message saying so.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "shore/scenes/progress.h"
#include "shore/scenes/scene.h"

namespace shore::scenes {

/// Records one run of one scene (one recorder per run); run_scene calls begin,
/// after_substep and finish.
class Recorder {
 public:
  /// Frames per simulated second (besides the filmstrip substeps and the last).
  static constexpr double kFramesPerSecond = 30.0;

  explicit Recorder(std::filesystem::path file);
  ~Recorder();
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  /// Before the first substep: the initial checkpoint. InvalidSetting if the scene shows no
  /// world, or hashes water surfaces its contents do not give.
  void begin(const SceneType& type, const SceneOptions& options, Scene& scene);
  /// After substep k (1-based): a frame if k is a frame substep.
  void after_substep(Scene& scene, int k);
  /// After the run: writes the file atomically. FileError naming it if that fails.
  void finish(std::uint64_t state_hash);
  /// What the file holds, bytes: the whole file (written by finish; 0 before), and before
  /// the outer compression the initial checkpoint, the soil deltas, the body states, the
  /// multibody states and collider transforms, the raycast wheels, and the water states (XORed); water_compressed: how
  /// much larger the file is for its water frames (the file compressed without them, subtracted; written by finish).
  struct Sizes {
    std::size_t file = 0, initial = 0, terrain_deltas = 0, bodies = 0, multibodies = 0, wheels = 0, water_states = 0,
                water_compressed = 0;
  };
  [[nodiscard]] const Sizes& sizes() const noexcept { return sizes_; }
  [[nodiscard]] std::size_t file_bytes() const noexcept { return sizes_.file; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  Sizes sizes_;
};

/// What replay() produced.
struct ReplayResult {
  std::string scene;
  std::uint64_t state_hash = 0;           ///< of the replayed final state
  std::uint64_t recorded_state_hash = 0;  ///< the original run's
  int frames = 0;
  double sim_seconds = 0.0;
  double wall_seconds = 0.0;  ///< reading, restoring and applying the frames (pictures excluded)
  std::size_t file_bytes = 0;
  std::vector<std::filesystem::path> files;  ///< pictures written (with write_files), metrics.json last
};

/// Called after each frame is applied, with the replaying scene and the frame's substep.
using FrameHook = std::function<void(Scene& scene, int substep)>;

/// Replays a recording: with write_files, the pictures (filmstrip too; none without a
/// painter) and metrics.json go to out_root / <scene> (the recording's scene). FileError
/// naming the file and the cause for a file that is missing, not a recording, truncated,
/// corrupt (checksum, zstd, sizes), of another version, byte order or btScalar precision,
/// or whose contents do not fit the scene (a delta, body, multibody or water section
/// refused, naming the frame by its substep; multibodies of other links, state values or
/// colliders, naming the multibody and the field; a version 2 file of a scene with
/// multibodies). after_frame (if set) sees the scene after each frame.
ReplayResult replay(const std::filesystem::path& file, const std::filesystem::path& out_root, bool write_files,
                    Painter* painter, ProgressMode progress, const FrameHook& after_frame = {});

}  // namespace shore::scenes
