#pragma once
// Soil deltas for network replicas: the columns a server's terrain changed since a
// generation (Terrain::generation), their heights and sinkage (what the bearing law and the
// contact read), quantised, delta and run-length coded rectangle by rectangle (at most one
// per tile), compressed with zstd, versioned and checksummed. Exact deltas (quantum 0)
// also carry the volume bookkeeping and the whole spray state (particles in flight, soil
// clinging to bodies), so a replica driven only by them has the server's state_hash;
// quantised ones carry columns and bookkeeping only. Both carry the material map: the
// palette if it was set after the delta's start, and every tile repainted after it.
//
// A replica is a Terrain built with the server's settings and base. It applies the deltas
// in order; each names the server generation it starts from and the one it brings, so a
// lost, repeated or reordered delta is refused. A delta from generation 0 (every column the
// server ever changed) is a full snapshot: a late joiner applies it first, whatever it
// holds. Applying reports the columns through the replica's take_changed / changed_since,
// so its Bullet tiles update as the server's did.
//
// Layout (docs/checkpoints.md): "SHORESDL", u32 version, u32 byte-order mark, f64 quantum,
// u64 from, u64 to, u64 raw size, u64 compressed size, zstd frame, u64 FNV-1a of every byte
// before it. Version 2 adds the spray block, version 3 the map block (written only when
// there is a palette or a repainted tile to send: a terrain that never paints sends
// version 2 deltas, byte for byte as before maps); versions 1 and 2 still apply.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "shore/terrain/terrain.h"

namespace shore::terrain {

struct DeltaSettings {
  /// m: heights and sinkage are sent as multiples of this, so a replica's columns lie within
  /// quantum / 2 of the server's (+ rounding of the sum). 0: exact (bit-identical, and the
  /// spray state travels too: the replica's Terrain::state_hash equals the server's). Finite, >= 0.
  double quantum = 1e-4;
  /// zstd level, in [1, 19]: higher is smaller and slower to encode (decoding is as fast).
  int compression_level = 3;

  /// Throws shore::InvalidSetting naming the field, the value and the allowed range.
  void validate() const;
};

/// What one encode() produced.
struct DeltaStats {
  std::size_t rectangles = 0;     ///< changed rectangles sent (at most one per tile)
  std::size_t columns = 0;        ///< columns in them
  std::size_t raw_bytes = 0;      ///< the coded columns before compression
  std::size_t bytes = 0;          ///< the whole delta
  std::size_t painted_tiles = 0;  ///< tiles whose material map was sent (repainted since)
};

class SoilDelta {
 public:
  /// The columns `server` changed after generation `since` (0: every changed column, a full
  /// snapshot), from `since` to server.generation(). Throws InvalidSetting on bad settings
  /// or a quantum too fine for the heights (more than 2^52 quanta from the base ground).
  static std::vector<unsigned char> encode(const Terrain& server, std::uint64_t since, const DeltaSettings& settings,
                                           DeltaStats* stats = nullptr);
  /// Applies a delta to a replica that mirrors server generation `at`; returns the
  /// generation it mirrors after. Throws shore::FileError (the replica untouched) if the
  /// delta is corrupt, truncated, of another version or byte order, or does not start at
  /// `at` (a snapshot, from 0, always applies); InvalidSetting (the replica untouched) if
  /// its rectangles do not fit the replica's tiles, its palette does not fit the replica
  /// (Terrain::set_palette's checks) or an index it paints, or one the replica keeps, lies
  /// beyond the palette then in force.
  static std::uint64_t apply(Terrain& replica, std::span<const unsigned char> delta, std::uint64_t at);
};

}  // namespace shore::terrain
