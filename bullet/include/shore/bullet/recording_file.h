#pragma once
// The file of a scene recording (shore/scenes/recording.h records and replays it;
// docs/checkpoints.md, "Replays"): its container and layout, written and read without a
// scene, so that the loader can be fuzzed on its own (fuzz_recording). What the nested
// parts hold (the initial checkpoint, the terrains' deltas (terrain::SoilDelta), the water states) is read by their
// own loaders when a replay applies them.
//
// File: "SHOREREC", u32 version (4), u32 byte-order mark 0x01020304, u32 scalar bytes
// (sizeof(btScalar) of the writer), u64 raw size, u64 compressed size, zstd frame of the
// raw bytes, u64 FNV-1a of every byte before it. Raw bytes: u32 length + scene name; f64
// seconds, substep, cell; u32 length + material; u8 smoke; i32 substeps; u64 the run's final
// state hash; u64 size + initial checkpoint (SHORECKP); u32 terrains, per terrain u64 its
// generation at the start; u32 waters; u32 multibodies, per multibody u32 links, u32 state
// values and one u8 per part (its base, then its links in order): 1 if the part has a
// collider, else 0; u32 frames, per frame: i32 substep, per terrain u64 size + delta, u32
// bodies, per body 18 btScalars (basis rows, origin, linear, angular velocity), per
// multibody its state values (btScalars: the state a scene's state hash covers) and then per
// part with a collider that collider's world transform (12 btScalars: basis rows, origin),
// then (version 4) per raycast vehicle per wheel its world transform (12 btScalars: basis
// rows, origin; Bullet's btWheelInfo::m_worldTransform, what pictures draw), per water u64 size + that water's
// state (Surface::save_state) XOR the previous frame's (0 past the previous state's end; the
// first frame's previous state is empty), its bytes grouped by place in an 8-byte word (byte
// k into plane k % 8, the planes in order). The header holds, after the multibodies'
// layouts (version 4), u32 vehicles, per vehicle u32 wheels.
// Version 3 (no wheels) is read as a recording of no vehicles: a replay draws the wheels
// where the replaying vehicle last had them. Version 2 (no multibodies: no multibody count,
// no multibody section in the frames) is read as a recording of none (a replay refuses it
// for a scene that has some). Version 1 (no water) is refused with a message saying so.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <LinearMath/btScalar.h>

#include "shore/bullet/config.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

/// A recording's contents. When read, the spans point into `raw` (keep the object alive and
/// do not copy it: a copy's spans would point into the original).
struct Recording {
  /// Scalars per body and frame: basis rows, origin, linear and angular velocity.
  static constexpr int kBodyScalars = 18;
  /// Scalars per multibody collider and frame: its world transform's basis rows and origin.
  static constexpr int kTransformScalars = 12;
  /// Scalars per raycast wheel and frame: its world transform's basis rows and origin.
  static constexpr int kWheelScalars = 12;
  /// The version write_recording writes by default, and the oldest read_recording reads.
  static constexpr std::uint32_t kVersion = 4, kOldestVersion = 2;

  /// What every frame holds of one multibody (the same in every frame).
  struct MultiBodyLayout {
    std::uint32_t links = 0;   ///< btMultiBody::getNumLinks()
    std::uint32_t values = 0;  ///< state values per frame
    /// Per part (base, then links; links + 1 entries): 1 if it has a collider, else 0.
    std::vector<std::uint8_t> colliders;
    [[nodiscard]] std::uint32_t collider_count() const;
    /// Scalars per frame: the values, then 12 per collider.
    [[nodiscard]] std::uint64_t scalars() const;
    /// Names scalar k of a frame's section ("state value 3", "link 2's world transform").
    [[nodiscard]] std::string describe(std::uint64_t k) const;
  };

  struct Frame {
    int substep = 0;
    std::vector<std::span<const unsigned char>> terrain_deltas;  ///< one per terrain
    std::span<const unsigned char> bodies;                       ///< count * kBodyScalars btScalars
    std::uint32_t body_count = 0;
    /// Per multibody, in order: its MultiBodyLayout::scalars() btScalars.
    std::span<const unsigned char> multibodies;
    /// Per vehicle, per wheel: kWheelScalars btScalars (none before version 4).
    std::span<const unsigned char> wheels;
    std::vector<std::span<const unsigned char>> water_diffs;  ///< one per water: its XOR (see above)
  };

  /// The file's version: read_recording sets it; write_recording writes it (kOldestVersion
  /// only for a recording without multibodies).
  std::uint32_t version = kVersion;

  std::string scene;
  double seconds = 0.0, substep = 0.0, cell = 0.0;
  std::string material;
  bool smoke = false;
  int substeps = 0;
  std::uint64_t state_hash = 0;  ///< the run's final one
  std::span<const unsigned char> initial;
  std::vector<std::uint64_t> terrain_generations;
  std::uint32_t waters = 0;
  std::vector<MultiBodyLayout> multibodies;   ///< none in version 2
  std::vector<std::uint32_t> vehicle_wheels;  ///< per raycast vehicle, its wheel count; none before version 4
  std::vector<Frame> frames;
  std::vector<unsigned char> raw;  ///< the decompressed bytes the spans point into

  Recording() = default;
  Recording(Recording&&) = default;
  Recording& operator=(Recording&&) = default;
  Recording(const Recording&) = delete;
  Recording& operator=(const Recording&) = delete;

  /// The body states of frame f, as btScalars (FileError naming `source` if any is not finite).
  [[nodiscard]] std::vector<btScalar> body_scalars(const Frame& f, const std::string& source) const;
  /// The multibody states of frame f, as btScalars, every multibody's in turn (FileError
  /// naming `source`, the frame, the multibody and the value or part if any is not finite).
  [[nodiscard]] std::vector<btScalar> multibody_scalars(const Frame& f, const std::string& source) const;
  /// The wheels of frame f, as btScalars, every vehicle's in turn (FileError naming `source`,
  /// the frame, the vehicle and the wheel if any value is not finite).
  [[nodiscard]] std::vector<btScalar> wheel_scalars(const Frame& f, const std::string& source) const;
  /// Bytes each frame holds of the wheels: kWheelScalars btScalars per wheel of every vehicle.
  [[nodiscard]] std::uint64_t wheel_bytes() const;
};

/// Writes the file's bytes: the header, one zstd frame of the raw layout (frames' spans
/// as given, water_diffs already XORed) and the checksum, in rec.version. FileError if zstd
/// fails; InvalidSetting for a version this build does not write (2 to 4), multibodies in
/// version 2, vehicles before version 4, or a frame's multibody or wheel section of another
/// size than the layouts give.
[[nodiscard]] std::vector<unsigned char> write_recording(const Recording& rec, int compression_level = 3);

/// Reads a recording file's bytes. FileError naming `source` and the cause for bytes that
/// are not a recording, truncated or padded, corrupt (checksum, zstd, sizes), of another
/// version, byte order or btScalar precision, frames out of order or past the substeps,
/// another number of terrains or waters in a frame, a multibody's collider flag other than
/// 0 or 1, or bytes after the last frame. Every
/// size read is checked against what is left, so memory stays within a bounded multiple
/// of the input's size (zstd's best ratio).
[[nodiscard]] Recording read_recording(std::span<const unsigned char> file, const std::string& source);

/// Rebuilds the water states of successive frames from their XOR (above), and makes those
/// bytes. Exact: next(encode(s)) is s, bit for bit, whatever the bytes and lengths.
class StateChain {
 public:
  /// The next state from the next frame's bytes (as long as they are).
  const std::vector<unsigned char>& next(std::span<const unsigned char> frame);
  /// This frame's bytes for `state`, and `state` becomes the previous one.
  std::vector<unsigned char> encode(const std::vector<unsigned char>& state);
  [[nodiscard]] const std::vector<unsigned char>& state() const noexcept { return prev_; }

 private:
  std::vector<unsigned char> prev_;
};

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
