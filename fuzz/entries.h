#pragma once
// The fuzzed loaders' entry points: one function per fuzz target, shared by the libFuzzer
// executables (fuzz_<name>, built with SHORE_FUZZ=ON) and by the ordinary test suite, which
// runs every seed and every kept crash input through them (tests/fuzz).
//
// Each takes arbitrary bytes and returns whether the loader accepted them. A loader may
// refuse them (shore::FileError: caught here); whatever it accepts must be a usable, finite
// state: otherwise, or on a crash or sanitizer report, the input is a bug. Broken
// invariants throw InvariantBroken (uncaught in a fuzzer: it aborts and keeps the input).

#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace shore::fuzz {

struct InvariantBroken : std::logic_error {
  using std::logic_error::logic_error;
};

/// A saved terrain state (Terrain::load_bytes). Byte 0 chooses the mode: odd, the rest is
/// a file without its checksum, which is appended (so mutations reach the parser behind
/// it); even, the rest is the whole file. An accepted state is stepped, saved and loaded
/// again: it must stay finite and round-trip to the same hash.
bool terrain_state(std::span<const std::uint8_t> data);
/// A checkpoint of a small coupled world (soil, water, both couplings, a Bullet ball:
/// coupled_world.h) restored into a fresh one. Byte 0 chooses the mode as for
/// terrain_state (odd: the container's checksum is appended). An accepted checkpoint is
/// stepped: the ball, soil and water must stay finite, and saving it again and restoring
/// that into another fresh world must continue to the same state.
bool coupled_checkpoint(std::span<const std::uint8_t> data);
/// A soil delta (SoilDelta::apply) applied to a replica that mirrors a small pressed server
/// (delta_server.h) at generation first_generation(). Byte 0 chooses the mode: bit 1 set,
/// the rest is f64 quantum, u64 from, u64 to and then the delta's payload before
/// compression, which is compressed and wrapped in a valid container (so mutations reach
/// the decoder behind zstd and the checksum) of version 6 (as 5, and each spray body's last
/// clinging step) if bit 4 is set, else of version 5 (a map block with layers, spray with
/// palette indices) if bit 3 is set, else of version 3 (a map block) if bit 2 is set,
/// else version 2; else bit 0 as for terrain_state (odd: the
/// checksum is appended). A refused delta must leave the replica unchanged; an accepted one
/// must leave it finite, and it is stepped, saved and loaded again (round trip).
bool soil_delta(std::span<const std::uint8_t> data);
/// A scene recording's file (bullet::read_recording: container, layout and sizes; what its
/// nested checkpoint, soil deltas and water states hold is read by their own loaders when a
/// replay applies them, fuzzed by the targets above). Byte 0 chooses the mode: bit 1 set,
/// the rest is u32 scalar bytes and then the raw layout before compression, which is
/// compressed and wrapped in a valid container (so mutations reach the layout behind zstd
/// and the checksum); else bit 0 as for terrain_state (odd: the checksum is appended). An
/// accepted recording's frames must be in order and of the stated sizes, its water states
/// must rebuild (StateChain), and written again it must read back to the same bytes.
bool recording(std::span<const std::uint8_t> data);
/// A PNG heightmap, 8 or 16 bits (Heightmap::from_png_bytes). Byte 0 chooses the mode: odd,
/// every chunk's CRC in the rest is rewritten to match (so mutations reach the decoder
/// behind the loader's CRC check); even, the rest is the file as it is.
bool heightmap_png(std::span<const std::uint8_t> data);
/// A raw float32 heightmap (Heightmap::from_raw_float32_bytes): byte 0 gives the width
/// (1 + b % 32), byte 1 the rows (b >= 128: as many as the rest holds; else 1 + b % 32); the
/// rest is the file.
bool heightmap_raw(std::span<const std::uint8_t> data);
/// A material map's sources: byte 0 % 4 chooses the loader. 0: the rest is a palette file's
/// text (parse_palette); 1 and 2: an 8-bit index PNG (MaterialImage::from_png_bytes), 1 with
/// every chunk's CRC rewritten as for heightmap_png; 3: raw indices
/// (MaterialImage::from_raw_bytes), byte 1 the width (1 + b % 32), byte 2 the rows (b >= 128:
/// as many as the rest holds; else 1 + b % 32), the rest the file. An accepted palette
/// becomes a small terrain's (unless the terrain refuses its soil depths or rigid flags),
/// each entry painted on a column; an accepted image of at most 64 x 64 pixels is painted
/// with a palette as long as its indices need and must read back pixel for pixel. The
/// painted terrain is stepped, saved (format 6) and loaded again.
bool material_map(std::span<const std::uint8_t> data);

/// A named entry point.
struct Target {
  const char* name;  ///< fuzz_<name> is the executable, fuzz/corpus/<name> its seeds
  bool (*run)(std::span<const std::uint8_t>);
  /// Whether a valid seed can load in this build (null: always). Checkpoint seeds carry
  /// the btScalar precision of the build that wrote them; the other precision refuses them.
  bool (*seed_fits_build)(std::span<const std::uint8_t>) = nullptr;
};
/// coupled_checkpoint's seed_fits_build: the container's precision field is this build's.
bool checkpoint_seed_fits_build(std::span<const std::uint8_t> data);
/// The soil delta container of `version` around a payload (soil_delta's modes 2, 6 and 10;
/// shore-fuzz-corpus writes such seeds): `fields` is f64 quantum, u64 from, u64 to, the
/// rest the payload.
std::vector<unsigned char> wrap_delta_payload(std::span<const std::uint8_t> fields, std::uint32_t version);
/// recording's seed_fits_build: the precision field (mode 2: the scalar bytes field) is this build's.
bool recording_seed_fits_build(std::span<const std::uint8_t> data);
/// The recording container of `version` around a raw layout (recording's modes 2 and 6;
/// shore-fuzz-corpus writes such seeds): `fields` is u32 scalar bytes, the rest the raw layout.
std::vector<unsigned char> wrap_recording_payload(std::span<const std::uint8_t> fields, std::uint32_t version);
/// Every target, in name order. A new loader adds its function here, in
/// fuzz/CMakeLists.txt and in scripts/fuzz.sh (fuzz/README.md).
const std::vector<Target>& targets();

}  // namespace shore::fuzz
