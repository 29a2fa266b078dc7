// Soil deltas (shore/terrain/soil_delta.h). Before compression, a delta is
//   f64 compacted, edited (the server's volume bookkeeping); u32 rectangle count;
//   per rectangle: i64 i0, j0; u16 nx, ny; then its heights and its sinkages, row-major,
//   each as a coded sequence (below);
//   (version 3 only) the material map: u8 palette flag; if 1 (the palette was set after
//   the delta's start), u32 palette size and every entry as the state file writes it
//   (material_io.h, entry 0 too); u32 count of tiles repainted after the start, per tile
//   (in key order) i64 tx, ty; u8 painted; if 1 its n * n palette indices as one coded
//   sequence (0: the tile was painted back to all index 0); (version 4 on) then u8
//   layered; if 1 its layers: the n * n boundaries' bit patterns (exact, +infinity where a
//   column is not layered) and the n * n lower indices, each as one coded sequence (0: the
//   tile has no layer);
//   (version 2 on) u8 spray flag; if 1 (exact deltas), the spray state as the terrain's
//   state file writes it (spray_io.h), to the end; from version 5 on with each particle's
//   and clinging cell's palette index, as the state file's version 8 writes it; from
//   version 6 on also with each body's last clinging step, as the state file's version 9.
// A delta with no map block to send (no palette set, no tile repainted after its start:
// every terrain that never paints) and no spray of another material than entry 0 is
// written as version 2, byte for byte as before maps; one with a map block from a terrain
// that never had a layer and whose spray is all entry 0's as version 3, as before layers;
// an exact one whose spray holds a body between two clinging steps of its cadence
// (Imprint::cling_every) as version 6; any other as version 5 (the map block of 5 and 6
// empty when there is nothing to send).
// A value is an integer: quantised, round((height - base) / quantum) and
// round(sinkage / quantum); exact, the double's bit pattern. A sequence codes each value's
// difference from the one before (the first from 0), wrapping, zig-zag mapped and written
// as a LEB128 varint; a 0 token is followed by a varint count of further zero differences
// (flat or unchanged stretches cost two bytes).

#include "shore/terrain/soil_delta.h"

#include <zstd.h>

#include <cmath>
#include <cstring>
#include <string>

#include "material_io.h"
#include "shore/core/byte_io.h"
#include "shore/core/error.h"
#include "shore/core/hash.h"
#include "spray_io.h"
#include "terrain_impl.h"

namespace shore::terrain {

namespace {

constexpr char kMagic[8] = {'S', 'H', 'O', 'R', 'E', 'S', 'D', 'L'};
// 1: no spray flag, 2: no map, 3: no layers, 4: no spray indices, 5: no spray bodies' steps
constexpr std::uint32_t kVersion = 6;
constexpr std::uint32_t kSprayStepsVersion = 6;
constexpr std::uint32_t kSprayMaterialsVersion = 5;
constexpr std::uint32_t kNoLayerVersion = 3;
constexpr std::uint32_t kNoMapVersion = 2;
constexpr std::uint32_t kByteOrderMark = 0x01020304u;
constexpr std::size_t kHeaderBytes = 8 + 4 + 4 + 8 + 8 + 8 + 8 + 8;
constexpr std::size_t kMaxRawBytes = std::size_t{1} << 31;
constexpr double kMaxQuanta = 4503599627370496.0;  // 2^52: integers exact in a double

[[noreturn]] void refuse(const std::string& problem) { throw FileError("soil delta: " + problem); }

void put_varint(std::vector<unsigned char>& out, std::uint64_t v) {
  while (v >= 0x80) {
    out.push_back(static_cast<unsigned char>(v | 0x80));
    v >>= 7;
  }
  out.push_back(static_cast<unsigned char>(v));
}

std::uint64_t zigzag(std::uint64_t difference) {
  const auto d = static_cast<std::int64_t>(difference);
  return (static_cast<std::uint64_t>(d) << 1) ^ static_cast<std::uint64_t>(d >> 63);
}
std::uint64_t unzigzag(std::uint64_t z) { return (z >> 1) ^ (0 - (z & 1)); }

// Differences, zig-zag, varints, zero runs.
void put_sequence(std::vector<unsigned char>& out, const std::vector<std::uint64_t>& values) {
  std::uint64_t previous = 0;
  for (std::size_t k = 0; k < values.size();) {
    const std::uint64_t z = zigzag(values[k] - previous);
    previous = values[k++];
    put_varint(out, z);
    if (z != 0) continue;
    std::uint64_t run = 0;
    while (k < values.size() && values[k] == previous) ++run, ++k;
    put_varint(out, run);
  }
}

class RawReader : public ByteReader {
 public:
  explicit RawReader(std::span<const unsigned char> bytes) : ByteReader(bytes, "soil delta") {}
  std::uint64_t varint() {
    std::uint64_t v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      const auto b = get<unsigned char>("a coded column");
      v |= static_cast<std::uint64_t>(b & 0x7f) << shift;
      if ((b & 0x80) == 0) return v;
    }
    refuse("corrupt (a varint of more than 10 bytes)");
  }
  void sequence(std::vector<std::uint64_t>& values) {
    std::uint64_t previous = 0;
    for (std::size_t k = 0; k < values.size();) {
      const std::uint64_t z = varint();
      previous += unzigzag(z);
      values[k++] = previous;
      if (z != 0) continue;
      const std::uint64_t run = varint();
      if (run > values.size() - k) refuse("corrupt (a zero run overruns its rectangle)");
      for (std::uint64_t r = 0; r < run; ++r) values[k++] = previous;
    }
  }
  [[nodiscard]] bool done() const { return remaining() == 0; }
};

std::uint64_t quantise(double value, double quantum) {
  if (quantum == 0.0) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &value, sizeof bits);
    return bits;
  }
  const double q = std::nearbyint(value / quantum);
  if (!(std::fabs(q) <= kMaxQuanta))
    throw InvalidSetting("terrain.DeltaSettings.quantum", detail::to_text(quantum),
                         "too fine: a column lies " + detail::to_text(value) + " m from its reference");
  return static_cast<std::uint64_t>(static_cast<std::int64_t>(q));
}

double dequantise(std::uint64_t value, double quantum) {
  if (quantum == 0.0) {
    double v = 0.0;
    std::memcpy(&v, &value, sizeof v);
    return v;
  }
  return static_cast<double>(static_cast<std::int64_t>(value)) * quantum;
}

// One rectangle's decoded columns.
struct DecodedRect {
  GridRect rect;
  std::vector<double> height, sinkage;
};

/// One repainted tile: its indices (empty: painted back to all 0).
struct DecodedPaint {
  TileKey key;
  std::vector<std::uint8_t> material;
  bool layers_sent = false;      ///< version 4 on: the tile's layers below replace the replica's
  std::vector<double> boundary;  ///< empty: no layer
  std::vector<std::uint8_t> lower;
};

struct Decoded {
  double compacted = 0.0, edited = 0.0;
  std::vector<DecodedRect> rects;
  bool has_palette = false;
  std::vector<Material> palette;
  std::vector<DecodedPaint> painted;
  bool has_spray = false;
  SprayState spray;
};

std::uint64_t checksum(const unsigned char* data, std::size_t size) {
  StateHash h;
  h.add_bytes(data, size);
  return h.value();
}

}  // namespace

void DeltaSettings::validate() const {
  const Check c{"terrain.DeltaSettings"};
  c.non_negative("quantum", quantum);
  c.in_closed("compression_level", compression_level, 1, 19);
}

// ---- encoding ----------------------------------------------------------------------------

namespace {

/// The map block (version 3) into `raw` (im: the server's Terrain::Impl) if the palette was set or a tile repainted
/// after `since`; false (nothing written) otherwise.
/// With `layers` (a server that has painted a layer: version 4) each repainted tile's
/// layers follow its indices.
bool write_map(ByteWriter& raw, const auto& im, std::uint64_t since, bool layers, DeltaStats& st) {
  const bool palette = im.palette_at > since;
  const std::vector<TileKey> painted = im.tiles.painted_since(since);
  if (!palette && painted.empty()) return false;
  raw.put(static_cast<std::uint8_t>(palette ? 1 : 0));
  if (palette) {
    Writer entries;
    for (const Material& m : im.palette) write_material(entries, m);
    raw.put(static_cast<std::uint32_t>(im.palette.size()));
    raw.bytes.insert(raw.bytes.end(), entries.bytes.begin(), entries.bytes.end());
  }
  raw.put(static_cast<std::uint32_t>(painted.size()));
  std::vector<std::uint64_t> values;
  for (const TileKey& key : painted) {
    const Tile& t = *im.tiles.find(key);
    raw.put(key.tx), raw.put(key.ty);
    raw.put(static_cast<std::uint8_t>(t.material.empty() ? 0 : 1));
    if (!t.material.empty()) {
      values.assign(t.material.begin(), t.material.end());
      put_sequence(raw.bytes, values);
    }
    if (!layers) continue;
    raw.put(static_cast<std::uint8_t>(t.layered() ? 1 : 0));
    if (!t.layered()) continue;
    values.resize(t.layer_boundary.size());
    for (std::size_t c = 0; c < values.size(); ++c) std::memcpy(&values[c], &t.layer_boundary[c], sizeof(double));
    put_sequence(raw.bytes, values);
    values.assign(t.layer_lower.begin(), t.layer_lower.end());
    put_sequence(raw.bytes, values);
  }
  st.painted_tiles = painted.size();
  return true;
}

}  // namespace

std::vector<unsigned char> SoilDelta::encode(const Terrain& server, std::uint64_t since, const DeltaSettings& settings,
                                             DeltaStats* stats) {
  settings.validate();
  const Terrain::Impl& im = *server.impl_;
  const std::vector<GridRect> rects = im.tiles.changed_since(since);
  ByteWriter raw;
  raw.put(im.compacted), raw.put(im.edited);
  raw.put(static_cast<std::uint32_t>(rects.size()));
  std::vector<std::uint64_t> heights, sinkages;
  DeltaStats st;
  for (const GridRect& r : rects) {
    raw.put(r.i0), raw.put(r.j0);
    raw.put(static_cast<std::uint16_t>(r.nx)), raw.put(static_cast<std::uint16_t>(r.ny));
    heights.assign(static_cast<std::size_t>(r.nx) * r.ny, 0);
    sinkages.assign(heights.size(), 0);
    im.tiles.for_each_run(r, [&](const Tile* t, const TileRun& run) {
      for (int k = 0; k < run.count; ++k) {
        const std::size_t at = static_cast<std::size_t>(run.y) * r.nx + run.x + k, local = run.local + k;
        const double h = t->height[local];
        heights[at] = quantise(settings.quantum == 0.0 ? h : h - t->base[local], settings.quantum);
        sinkages[at] = quantise(t->sinkage[local], settings.quantum);
      }
    });
    put_sequence(raw.bytes, heights);
    put_sequence(raw.bytes, sinkages);
    st.columns += heights.size();
  }
  const bool exact = settings.quantum == 0.0;
  const bool spray_steps = exact && im.spray.state.has_bodies_between_steps();
  const bool spray_materials = spray_steps || (exact && im.spray.state.has_materials());  // 6 has 5's fields
  const bool layers = im.tiles.layered() || spray_materials;  // version 5 carries the layer flags as 4 did
  bool map = write_map(raw, im, since, layers, st);
  if (!map && spray_materials) {  // the spray's indices (5) or bodies' steps (6) need an empty map block
    raw.put(std::uint8_t{0}), raw.put(std::uint32_t{0});
    map = true;
  }
  const std::uint32_t version = !map          ? kNoMapVersion
                                : !layers     ? kNoLayerVersion
                                : spray_steps ? kSprayStepsVersion
                                              : kSprayMaterialsVersion;
  // Exact deltas carry the spray too: with it the replica's whole soil state, and so its
  // state_hash, is the server's. Quantised ones do not (bodies on a replica read heights
  // and sinkages only; the spray would cost more than the columns).
  raw.put(static_cast<std::uint8_t>(exact ? 1 : 0));
  if (exact) {
    Writer spray;
    write_spray_state(spray, im.spray.state,
                      {.materials = version >= kSprayMaterialsVersion, .steps = version >= kSprayStepsVersion});
    raw.bytes.insert(raw.bytes.end(), spray.bytes.begin(), spray.bytes.end());
  }
  ByteWriter w;
  for (char c : kMagic) w.put(c);
  w.put(version), w.put(kByteOrderMark), w.put(settings.quantum);
  w.put(since), w.put(im.tiles.generation()), w.put(static_cast<std::uint64_t>(raw.bytes.size()));
  std::vector<unsigned char>& out = w.bytes;
  const std::size_t frame_at = out.size() + sizeof(std::uint64_t);
  out.resize(frame_at + ZSTD_compressBound(raw.bytes.size()));
  const std::size_t frame = ZSTD_compress(out.data() + frame_at, out.size() - frame_at, raw.bytes.data(),
                                          raw.bytes.size(), settings.compression_level);
  if (ZSTD_isError(frame) != 0) refuse(std::string("zstd failed: ") + ZSTD_getErrorName(frame));
  out.resize(frame_at + frame);
  const auto frame_size = static_cast<std::uint64_t>(frame);
  std::memcpy(out.data() + frame_at - sizeof frame_size, &frame_size, sizeof frame_size);
  w.put(checksum(out.data(), out.size()));
  st.rectangles = rects.size(), st.raw_bytes = raw.bytes.size(), st.bytes = out.size();
  if (stats != nullptr) *stats = st;
  return std::move(w.bytes);
}

// ---- applying ----------------------------------------------------------------------------

namespace {

struct Header {
  std::uint32_t version = kVersion;
  double quantum = 0.0;
  std::uint64_t from = 0, to = 0, raw_size = 0, frame_size = 0;
};

Header read_header(std::span<const unsigned char> delta) {
  if (delta.size() < sizeof kMagic || std::memcmp(delta.data(), kMagic, sizeof kMagic) != 0)
    refuse("not a Shore soil delta (magic \"SHORESDL\" missing)");
  if (delta.size() < kHeaderBytes + 8) refuse("truncated (" + std::to_string(delta.size()) + " bytes)");
  RawReader r(delta.subspan(sizeof kMagic, kHeaderBytes - sizeof kMagic));
  const auto version = r.get<std::uint32_t>("version");
  if (version < 1 || version > kVersion)
    refuse("unsupported version " + std::to_string(version) + " (this build reads 1 to " + std::to_string(kVersion) +
           ")");
  if (r.get<std::uint32_t>("byte-order mark") != kByteOrderMark) refuse("written with the other byte order");
  Header h;
  h.version = version;
  h.quantum = r.get<double>("header"), h.from = r.get<std::uint64_t>("header"), h.to = r.get<std::uint64_t>("header");
  h.raw_size = r.get<std::uint64_t>("header"), h.frame_size = r.get<std::uint64_t>("header");
  if (h.frame_size != delta.size() - kHeaderBytes - 8)
    refuse("truncated or padded (frame of " + std::to_string(h.frame_size) + " bytes in a delta of " +
           std::to_string(delta.size()) + ")");
  std::uint64_t stored = 0;
  std::memcpy(&stored, delta.data() + delta.size() - 8, sizeof stored);
  if (stored != checksum(delta.data(), delta.size() - 8)) refuse("checksum mismatch (corrupt)");
  if (!(h.quantum >= 0.0) || !std::isfinite(h.quantum) || h.raw_size > kMaxRawBytes || h.to < h.from)
    refuse("corrupt header");
  return h;
}

std::vector<unsigned char> decompress(std::span<const unsigned char> delta, const Header& h) {
  // Checked before the payload's buffer is allocated, so a corrupt size cannot cost 2 GB
  // (found by fuzz_soil_delta): zstd's best ratio is a 128 KiB block from 4 bytes (an RLE
  // block), and the frame records its own content size.
  constexpr std::uint64_t kMaxRatio = 131072 / 4;
  if (h.raw_size > h.frame_size * kMaxRatio ||
      ZSTD_getFrameContentSize(delta.data() + kHeaderBytes, h.frame_size) != h.raw_size)
    refuse("corrupt (a payload of " + std::to_string(h.raw_size) + " bytes in a zstd frame of " +
           std::to_string(h.frame_size) + " that says otherwise)");
  std::vector<unsigned char> raw(h.raw_size);
  const std::size_t got = ZSTD_decompress(raw.data(), raw.size(), delta.data() + kHeaderBytes, h.frame_size);
  if (ZSTD_isError(got) != 0) refuse(std::string("zstd: ") + ZSTD_getErrorName(got));
  if (got != raw.size()) refuse("corrupt (decompressed size differs from the header's)");
  return raw;
}

DecodedRect read_rect(RawReader& r, const TileStore& tiles, double quantum) {
  DecodedRect d;
  d.rect.i0 = r.get<std::int64_t>("a rectangle"), d.rect.j0 = r.get<std::int64_t>("a rectangle");
  d.rect.nx = r.get<std::uint16_t>("a rectangle"), d.rect.ny = r.get<std::uint16_t>("a rectangle");
  const int n = tiles.n();
  const GridRect& c = d.rect;
  // Past column 2^52 the state file refuses a tile (terrain_io.cpp); a margin wider than
  // any tile keeps every column of the rectangle and its tile's origin inside (found by
  // fuzz_soil_delta: a replica that could not be saved).
  constexpr std::int64_t kMaxColumn = (std::int64_t{1} << 52) - 2048;
  if (c.i0 < -kMaxColumn || c.i0 > kMaxColumn || c.j0 < -kMaxColumn || c.j0 > kMaxColumn)
    refuse("corrupt (a rectangle at column (" + std::to_string(c.i0) + ", " + std::to_string(c.j0) +
           "), beyond column index 2^52)");
  if (c.nx < 1 || c.ny < 1 || tiles.key_of(c.i0, c.j0) != tiles.key_of(c.i0 + c.nx - 1, c.j0 + c.ny - 1))
    throw InvalidSetting("terrain.SoilDelta.rectangle",
                         std::to_string(c.nx) + " x " + std::to_string(c.ny) + " at (" + std::to_string(c.i0) + ", " +
                             std::to_string(c.j0) + ")",
                         "must lie in one tile of " + std::to_string(n) + " columns (the server's tile_columns)");
  std::vector<std::uint64_t> values(static_cast<std::size_t>(c.nx) * c.ny);
  d.height.resize(values.size()), d.sinkage.resize(values.size());
  r.sequence(values);
  for (int y = 0; y < c.ny; ++y)
    for (int x = 0; x < c.nx; ++x) {
      const std::size_t k = static_cast<std::size_t>(y) * c.nx + x;
      const double h = dequantise(values[k], quantum);
      d.height[k] = quantum == 0.0 ? h : tiles.base_at(c.i0 + x, c.j0 + y) + h;
    }
  r.sequence(values);
  for (std::size_t k = 0; k < values.size(); ++k) d.sinkage[k] = dequantise(values[k], quantum);
  // The state file's bound (terrain_io.cpp): no ground lies farther from sea level, and a
  // replica holding such a column could not be saved (found by fuzz_soil_delta).
  constexpr double kMaxLevel = 1e7;
  for (std::size_t k = 0; k < values.size(); ++k)
    if (!(std::fabs(d.height[k]) <= kMaxLevel) || !(std::fabs(d.sinkage[k]) <= kMaxLevel))
      refuse("corrupt (a column of height " + detail::to_text(d.height[k]) + " m, sinkage " +
             detail::to_text(d.sinkage[k]) + " m: non-finite or beyond +-1e7 m)");
  return d;
}

/// The spray block of a version 2 delta, from where `r` stands to the end.
void read_spray(RawReader& r, std::span<const unsigned char> raw, Decoded& d, SprayLayout layout) {
  const auto flag = r.get<std::uint8_t>("spray flag");
  if (flag > 1) refuse("corrupt (spray flag " + std::to_string(flag) + ")");
  d.has_spray = flag == 1;
  const std::span<const unsigned char> rest = raw.subspan(raw.size() - r.remaining());
  if (!d.has_spray) {
    if (!rest.empty()) refuse("corrupt (bytes after the last rectangle)");
    return;
  }
  Reader spray(rest, rest.size(), "in a soil delta");
  read_spray_state(spray, d.spray, layout);
  if (spray.remaining() != 0) refuse("corrupt (bytes after the spray state)");
}

/// The map block of a version 3 delta, from where `r` stands.
/// A repainted tile's layers (version 4 on), from where `r` stands.
void read_layers(RawReader& r, DecodedPaint& p, std::size_t columns) {
  p.layers_sent = true;
  const auto layered = r.get<std::uint8_t>("a painted tile's layers");
  if (layered > 1) refuse("corrupt (layered flag " + std::to_string(layered) + ")");
  if (layered == 0) return;
  std::vector<std::uint64_t> values(columns, 0);
  r.sequence(values);
  p.boundary.resize(columns);
  for (std::size_t c = 0; c < columns; ++c) std::memcpy(&p.boundary[c], &values[c], sizeof(double));
  values.assign(columns, 0);
  r.sequence(values);
  p.lower.resize(columns);
  for (std::size_t c = 0; c < columns; ++c) {
    const double d = p.boundary[c];
    // (Below 0: a top layer erosion laid on loose soil, whose sinkage is negative.)
    if (d != kNoLayer && !(d >= -2e7 && d <= 2e7))
      refuse("corrupt (tile (" + std::to_string(p.key.tx) + ", " + std::to_string(p.key.ty) + ") column " +
             std::to_string(c) + " has layer boundary " + detail::to_text(d) +
             " m; allowed: -2e7 to 2e7 or +infinity)");
    if (values[c] >= static_cast<std::uint64_t>(Terrain::kMaxMaterials))
      refuse("corrupt (tile (" + std::to_string(p.key.tx) + ", " + std::to_string(p.key.ty) + ") column " +
             std::to_string(c) + " holds lower index " + std::to_string(values[c]) + ")");
    p.lower[c] = static_cast<std::uint8_t>(values[c]);
  }
}

void read_map(RawReader& r, std::span<const unsigned char> raw, const TileStore& tiles, std::uint32_t version,
              Decoded& d) {
  const auto flag = r.get<std::uint8_t>("palette flag");
  if (flag > 1) refuse("corrupt (palette flag " + std::to_string(flag) + ")");
  d.has_palette = flag == 1;
  if (d.has_palette) {
    const auto size = r.get<std::uint32_t>("palette size");
    if (size < 1 || size > static_cast<std::uint32_t>(Terrain::kMaxMaterials))
      refuse("corrupt (a palette of " + std::to_string(size) + " materials; allowed: 1 to " +
             std::to_string(Terrain::kMaxMaterials) + ")");
    const std::span<const unsigned char> rest = raw.subspan(raw.size() - r.remaining());
    Reader entries(rest, rest.size(), "in a soil delta");
    for (std::uint32_t k = 0; k < size; ++k) d.palette.push_back(read_material(entries));
    r.skip(rest.size() - entries.remaining(), "the palette");
  }
  const auto count = r.get<std::uint32_t>("painted tile count");
  if (count > r.remaining() / 17) refuse("corrupt (painted tile count " + std::to_string(count) + ")");
  const std::int64_t n = tiles.n();
  // The rectangles' bound (read_rect), in tiles.
  const std::int64_t max_tile = ((std::int64_t{1} << 52) - 2048) / n;
  const std::size_t columns = static_cast<std::size_t>(n * n);
  std::vector<std::uint64_t> values;
  for (std::uint32_t k = 0; k < count; ++k) {
    DecodedPaint p;
    p.key.tx = r.get<std::int64_t>("a painted tile"), p.key.ty = r.get<std::int64_t>("a painted tile");
    if (p.key.tx < -max_tile || p.key.tx > max_tile || p.key.ty < -max_tile || p.key.ty > max_tile)
      refuse("corrupt (a painted tile at (" + std::to_string(p.key.tx) + ", " + std::to_string(p.key.ty) +
             "), beyond column index 2^52)");
    if (!d.painted.empty() && !(d.painted.back().key < p.key))
      refuse("corrupt (painted tiles out of key order or repeated)");
    const auto painted = r.get<std::uint8_t>("a painted tile");
    if (painted > 1) refuse("corrupt (painted flag " + std::to_string(painted) + ")");
    if (painted == 1) {
      values.assign(columns, 0);
      r.sequence(values);
      p.material.resize(columns);
      for (std::size_t c = 0; c < columns; ++c) {
        if (values[c] >= static_cast<std::uint64_t>(Terrain::kMaxMaterials))
          refuse("corrupt (tile (" + std::to_string(p.key.tx) + ", " + std::to_string(p.key.ty) + ") column " +
                 std::to_string(c) + " holds index " + std::to_string(values[c]) + ")");
        p.material[c] = static_cast<std::uint8_t>(values[c]);
      }
    }
    if (version >= 4) read_layers(r, p, columns);
    d.painted.push_back(std::move(p));
  }
}

Decoded decode(std::span<const unsigned char> raw, const TileStore& tiles, const Header& h) {
  const double quantum = h.quantum;
  RawReader r(raw);
  Decoded d;
  d.compacted = r.get<double>("bookkeeping"), d.edited = r.get<double>("bookkeeping");
  if (!std::isfinite(d.compacted) || !std::isfinite(d.edited)) refuse("corrupt (non-finite bookkeeping)");
  const auto count = r.get<std::uint32_t>("rectangle count");
  if (count > raw.size() / 20) refuse("corrupt (rectangle count " + std::to_string(count) + ")");
  for (std::uint32_t k = 0; k < count; ++k) d.rects.push_back(read_rect(r, tiles, quantum));
  if (h.version >= 3) read_map(r, raw, tiles, h.version, d);
  if (h.version >= 2) {
    read_spray(r, raw, d, {.materials = h.version >= kSprayMaterialsVersion, .steps = h.version >= kSprayStepsVersion});
    return d;
  }
  if (!r.done()) refuse("corrupt (bytes after the last rectangle)");
  return d;
}

}  // namespace

namespace {

/// The palette a delta brings fits the replica (Terrain::set_palette's checks), and every
/// index on the map after applying it lies in the palette then in force.
void check_map(const auto& im, const Decoded& d) {
  if (d.has_palette) im.check_palette(d.palette, "terrain.SoilDelta.palette");
  const std::size_t size = d.has_palette ? d.palette.size() : im.palette.size();
  std::vector<TileKey> keys;
  for (const DecodedPaint& p : d.painted) {
    keys.push_back(p.key);
    for (std::size_t c = 0; c < p.material.size(); ++c)
      if (p.material[c] >= size)
        throw InvalidSetting("terrain.SoilDelta.tile(" + std::to_string(p.key.tx) + ", " + std::to_string(p.key.ty) +
                                 ").column(" + std::to_string(c) + ")",
                             std::to_string(p.material[c]),
                             "must be a palette entry, in [0, " + std::to_string(size - 1) + "]");
    for (std::size_t c = 0; c < p.lower.size(); ++c)
      if (p.boundary[c] != kNoLayer && p.lower[c] >= size)
        throw InvalidSetting("terrain.SoilDelta.tile(" + std::to_string(p.key.tx) + ", " + std::to_string(p.key.ty) +
                                 ").column(" + std::to_string(c) + ").lower_index",
                             std::to_string(p.lower[c]),
                             "must be a palette entry, in [0, " + std::to_string(size - 1) + "]");
  }
  if (const int largest = im.tiles.largest_material(keys); static_cast<std::size_t>(largest) >= size)
    throw InvalidSetting(
        "terrain.SoilDelta.palette.size()", std::to_string(size),
        "must be more than the largest index left painted on the replica (" + std::to_string(largest) + ")");
  if (const int largest = (d.has_spray ? d.spray : im.spray.state).largest_material();
      static_cast<std::size_t>(largest) >= size)
    throw InvalidSetting(
        "terrain.SoilDelta.spray", std::to_string(largest),
        "a particle's or clinging piece's palette index must be in [0, " + std::to_string(size - 1) + "]");
}

}  // namespace

std::uint64_t SoilDelta::apply(Terrain& replica, std::span<const unsigned char> delta, std::uint64_t at) {
  const Header h = read_header(delta);
  if (h.from != 0 && h.from != at)
    refuse("out of order: it starts at server generation " + std::to_string(h.from) + ", the replica is at " +
           std::to_string(at));
  Terrain::Impl& im = *replica.impl_;
  // Everything is decoded and checked before the first column is written.
  Decoded d = decode(decompress(delta, h), im.tiles, h);
  check_map(im, d);
  TileStore& tiles = im.tiles;
  tiles.advance_generation();
  if (d.has_palette) im.adopt_palette(std::move(d.palette));
  for (DecodedPaint& p : d.painted) {
    Tile& t = tiles.tile(p.key);
    t.material = std::move(p.material);
    t.normalize_material();
    if (p.layers_sent) {
      t.layer_boundary = std::move(p.boundary);
      t.layer_lower = std::move(p.lower);
      t.normalize_layers();
      if (t.layered()) tiles.mark_layered();
    }
    tiles.mark_painted(t);
  }
  for (const DecodedRect& r : d.rects)
    tiles.for_each_run_creating(r.rect, [&](Tile& t, const TileRun& run) {
      const std::size_t from = static_cast<std::size_t>(run.y) * r.rect.nx + run.x;
      std::memcpy(t.height.data() + run.local, r.height.data() + from, run.count * sizeof(double));
      std::memcpy(t.sinkage.data() + run.local, r.sinkage.data() + from, run.count * sizeof(double));
      tiles.mark_changed(run.key, t, {run.li, run.lj, run.count, 1});
    });
  im.compacted = d.compacted, im.edited = d.edited;
  if (d.has_spray) im.spray.state = std::move(d.spray);
  return h.to;
}

}  // namespace shore::terrain
