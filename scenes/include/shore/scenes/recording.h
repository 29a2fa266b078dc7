#pragma once
// Recordings of a scene run and their replay (issue 20; docs/checkpoints.md, "Replays").
//
// What a recording carries, so that a replay's final state hash equal to the run's means
// something: the scene's name and options, its initial checkpoint (checkpoint.h: soils,
// couplings, bodies, clock), then per frame (30 per simulated second, every filmstrip
// substep and the last substep) each soil's exact delta since the previous frame
// (soil_delta.h with quantum 0: heights, sinkages, volume bookkeeping and the spray state)
// and every body's world transform and linear and angular velocity, in the order the scene
// added them (World::bodies(); not bullet::save_bodies, whose collision-object order
// changes as the couplings add and remove heightfield tiles during a run). A replay
// does NOT step the physics: it restores the initial checkpoint into a fresh scene and
// then only writes the recorded columns, spray and bodies into it, frame by frame. So its
// state hash equals the run's only if the recording holds the whole hashed state (the
// test compares them, and a replay that misses any soil column, spray particle or body
// would differ), and its pictures show exactly the recorded states.
//
// Scenes with water are refused: water gets no deltas (it is re-simulated from the same
// inputs, docs/checkpoints.md), and a replay re-simulates nothing.
//
// File layout: "SHOREREC", u32 version (1), u32 byte-order mark 0x01020304, u32 scalar bytes
// (sizeof(btScalar) of the writer), u64 raw size, u64 compressed size, zstd frame of the
// raw bytes, u64 FNV-1a of every byte before it. Raw bytes: u32 length + scene name; f64
// seconds, substep, cell; u32 length + material; u8 smoke; i32 substeps; u64 the run's final
// state hash; u64 size + initial checkpoint (SHORECKP); u32 soils, per soil u64 its
// generation at the start; u32 frames, per frame: i32 substep, per soil u64 size + delta,
// u32 bodies, per body 18 btScalars (basis rows, origin, linear, angular velocity).

#include <cstdint>
#include <filesystem>
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
  /// world or has water (see above).
  void begin(const SceneType& type, const SceneOptions& options, Scene& scene);
  /// After substep k (1-based): a frame if k is a frame substep.
  void after_substep(Scene& scene, int k);
  /// After the run: writes the file atomically. FileError naming it if that fails.
  void finish(std::uint64_t state_hash);
  /// What the file holds, bytes: the whole file (written by finish; 0 before), and before
  /// the outer compression the initial checkpoint, the soil deltas and the body states.
  struct Sizes {
    std::size_t file = 0, initial = 0, soil_deltas = 0, bodies = 0;
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

/// Replays a recording: with write_files, the pictures (filmstrip too; none without a
/// painter) and metrics.json go to out_root / <scene> (the recording's scene). FileError
/// naming the file and the cause for a file that is missing, not a recording, truncated,
/// corrupt (checksum, zstd, sizes), of another version, byte order or btScalar precision,
/// or whose contents do not fit the scene (a delta or body section refused).
ReplayResult replay(const std::filesystem::path& file, const std::filesystem::path& out_root, bool write_files,
                    Painter* painter, ProgressMode progress);

}  // namespace shore::scenes
