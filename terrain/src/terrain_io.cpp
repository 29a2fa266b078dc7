// Saved terrain state: a little binary format guarded by a checksum.
//
//   "SHORETRN" (8 bytes), u32 version, u32 byte-order mark 0x01020304
//   (version 4 on) u32 bytes per real number: 8 (every real is an IEEE-754 f64, whatever
//             precision Bullet was built with); any other value is refused by name
//   settings: f64 cell, origin_x, origin_y; i32 tile_columns; f64 base_height;
//             i32 max_erosion_passes, active_margin; f64 contact_tolerance; i32 threads,
//             parallel_min_columns; f64 active_reach (version 2 on; version 1 files
//             load with +infinity, the behaviour they were stepped with); i32
//             idle_tile_steps (version 4 on; older files load with the default)
//   material: u32 name length, name bytes; f64 theta_stop, sigma, theta_in, theta_out,
//             alpha, bekker_n, bekker_kc, bekker_kphi, friction, soil_depth; u8 rigid;
//             (version 3 on) f64 cohesion, friction_angle, shear_modulus, remould_ratio,
//             remould_shear_ratio, remould_length (older files load with the defaults of
//             Material{})
//   (version 4 on) spray settings: f64 adhesion, half_life, speed_scale, exponent,
//             particle_size, min_speed, jitter, drag (the material's); u8 enabled;
//             i32 max_particles; u64 seed; f64 gravity, x_min, x_max, y_min, y_max,
//             max_flight (older files load with spray off: they were stepped without it)
//   (version 5 on) f64 unload_modulus (older files load with 0: rigid-plastic columns)
//   f64 compacted, edited
//   (version 2 on) u64 count of regions still eroding; per region i64 i0, j0; i32 nx, ny
//   (version 4 on) spray state: i64 step; f64 lost; i64 created, landed, lost, clumps,
//             limited, set_down; f64 picked_volume; u64 particle count, per particle f64 x,
//             y, z, vx, vy, vz, volume, age; u64 body count, per body (by key) u64 key,
//             f64 c[3], q[4], u64 cell count, per cell (by key) u64 key, f64 rx, ry, rz,
//             volume, owed, pending, i64 i, j, touched
//   (version 6 on) material map: u32 palette size (in [1, 256]; entry 0 is the material
//             above), per further entry a material record (u32 name length, name bytes;
//             f64 theta_stop, sigma, theta_in, theta_out, alpha, bekker_n, bekker_kc,
//             bekker_kphi, friction, soil_depth; u8 rigid; f64 cohesion, friction_angle,
//             shear_modulus, remould_ratio, remould_shear_ratio, remould_length; f64 spray
//             adhesion, half_life, speed_scale, exponent, particle_size, min_speed, jitter,
//             drag; f64 unload_modulus); u64 painted tile count, per painted tile (in key
//             order, each one of the tiles below) i64 tx, ty; u8[n*n] palette index.
//             A terrain with one material and no painted tile is written as version 5,
//             byte for byte what it was before maps existed; older files load as one material
//   (version 7 on) layers in depth: u64 layered tile count, per layered tile (in key order,
//             each one of the tiles below) i64 tx, ty; f64[n*n] boundary (the sinkage at
//             which the crust ends, m; +infinity where the column is not layered);
//             u8[n*n] lower palette index (version 7 was written by a terrain with a
//             layer; version 8 by every terrain with a map, its count 0 if none)
//   (version 8 on, which every terrain with a map is written as) the spray state above
//             carries each particle's palette index (u8 after its age) and each clinging
//             cell's (u8 after its touched); earlier files load every one as entry 0
//   (version 9 on, which a terrain is written as while some body's clinging soil waits
//             between two steps of its cadence, Imprint::cling_every, its map block empty
//             if it has none; else as 8 or 5) each spray body carries i64 stepped, the spray
//             step its soil was last stepped on (after its q[4]), 1 to 2^20 steps before the
//             spray's step; earlier files load each body as stepped on the step before
//   u64 tile count
//   per tile (in key order): i64 tx, ty; f64[n*n] height, sinkage, base
//   u64 FNV-1a of every byte before it
// Numbers are stored in the writing machine's byte order; the mark rejects the other one.
// Every loader input is fuzzed (fuzz/README.md): a file, however corrupt, gives a FileError
// or a valid terrain, never a crash, a hang or a non-finite state.

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "material_io.h"
#include "region.h"
#include "shore/core/error.h"
#include "shore/core/file_bytes.h"
#include "shore/core/hash.h"
#include "spray_io.h"
#include "state_file.h"
#include "terrain_impl.h"

namespace shore::terrain {

namespace {

constexpr char kMagic[8] = {'S', 'H', 'O', 'R', 'E', 'T', 'R', 'N'};
constexpr std::uint32_t kVersion = 9;
/// The first version whose spray state carries each body's last clinging step.
constexpr std::uint32_t kSprayStepsVersion = 9;
/// The first version whose spray state carries palette indices.
constexpr std::uint32_t kSprayMaterialsVersion = 8;
/// The first version with a layers block.
constexpr std::uint32_t kLayersVersion = 7;
/// Written for terrains without a material map (one material, nothing painted).
constexpr std::uint32_t kOneMaterialVersion = 5;
constexpr std::uint32_t kOldestVersion = 1;
constexpr std::uint32_t kByteOrderMark = 0x01020304u;
constexpr std::uint32_t kRealBytes = sizeof(double);
/// Columns (and so tiles) beyond this index are refused: their world positions would no
/// longer be exact in a double, and index arithmetic stays far from overflow.
constexpr std::int64_t kMaxColumnIndex = std::int64_t{1} << 52;

std::uint64_t checksum(const unsigned char* data, std::size_t size) {
  StateHash h;
  h.add_bytes(data, size);
  return h.value();
}

void write_settings(Writer& w, const TerrainSettings& s) {
  const Material& m = s.material;
  w.put(s.cell), w.put(s.origin_x), w.put(s.origin_y);
  w.put(static_cast<std::int32_t>(s.tile_columns));
  w.put(s.base_height);
  w.put(static_cast<std::int32_t>(s.max_erosion_passes)), w.put(static_cast<std::int32_t>(s.active_margin));
  w.put(s.contact_tolerance);
  w.put(static_cast<std::int32_t>(s.threads));
  w.put(static_cast<std::int32_t>(s.parallel_min_columns));
  w.put(s.active_reach);
  w.put(static_cast<std::int32_t>(s.idle_tile_steps));
  write_material_fields(w, m);
  write_spray_settings(w, s);  // the material's spray, then the terrain's (the file's order)
  w.put(m.unload_modulus);
}

bool has_map(std::span<const Material> palette, const TileStore& tiles, const std::vector<TileKey>& keys) {
  if (palette.size() > 1) return true;
  for (const TileKey& key : keys)
    if (!tiles.find(key)->material.empty()) return true;
  return false;
}

void write_map(Writer& w, std::span<const Material> palette, const TileStore& tiles, const std::vector<TileKey>& keys) {
  w.put(static_cast<std::uint32_t>(palette.size()));
  for (std::size_t k = 1; k < palette.size(); ++k) write_material(w, palette[k]);
  std::uint64_t painted = 0;
  for (const TileKey& key : keys) painted += tiles.find(key)->material.empty() ? 0 : 1;
  w.put(painted);
  for (const TileKey& key : keys) {
    const Tile& t = *tiles.find(key);
    if (t.material.empty()) continue;
    w.put(key.tx), w.put(key.ty);
    for (const std::uint8_t m : t.material) w.put(m);
  }
}

bool has_layers(const TileStore& tiles, const std::vector<TileKey>& keys) {
  for (const TileKey& key : keys)
    if (tiles.find(key)->layered()) return true;
  return false;
}

void write_layers(Writer& w, const TileStore& tiles, const std::vector<TileKey>& keys) {
  std::uint64_t layered = 0;
  for (const TileKey& key : keys) layered += tiles.find(key)->layered() ? 1 : 0;
  w.put(layered);
  for (const TileKey& key : keys) {
    const Tile& t = *tiles.find(key);
    if (!t.layered()) continue;
    w.put(key.tx), w.put(key.ty);
    w.put_doubles(t.layer_boundary);
    for (const std::uint8_t m : t.layer_lower) w.put(m);
  }
}

/// Layers read from a file, applied once its tiles and palette are.
struct SavedLayers {
  struct Entry {
    TileKey key;
    std::vector<double> boundary;
    std::vector<std::uint8_t> lower;
  };
  std::vector<Entry> tiles;
};

SavedLayers read_layers(Reader& hr, int n) {
  SavedLayers layers;
  const auto count = hr.get<std::uint64_t>("layers");
  const std::size_t columns = static_cast<std::size_t>(n) * n;
  if (count > hr.remaining() / (16 + 9 * columns))
    hr.fail("layered tile count " + std::to_string(count) + " does not fit the file (corrupt)");
  for (std::uint64_t k = 0; k < count; ++k) {
    SavedLayers::Entry e;
    e.key.tx = hr.get<std::int64_t>("layers");
    e.key.ty = hr.get<std::int64_t>("layers");
    e.boundary.resize(columns);
    hr.get_doubles(e.boundary, "layers");
    e.lower.resize(columns);
    for (std::uint8_t& m : e.lower) m = hr.get<std::uint8_t>("layers");
    layers.tiles.push_back(std::move(e));
  }
  return layers;
}

/// A boundary beyond this (m of sinkage, either way) is corrupt: a painted depth is at most
/// 1e6 m. (Below 0: a top layer erosion laid on loose soil, whose sinkage is negative.)
constexpr double kMaxBoundary = 2e7;

/// Gives the saved tiles their layers (the palette already set), stamped as painted.
void apply_layers(const Reader& hr, SavedLayers& layers, std::size_t palette_size, TileStore& store) {
  for (SavedLayers::Entry& e : layers.tiles) {
    const std::string where = "layers of tile (" + std::to_string(e.key.tx) + ", " + std::to_string(e.key.ty) + ")";
    Tile* tile = store.find(e.key);
    if (tile == nullptr) hr.fail(where + ": no such tile in the file (corrupt)");
    if (tile->layered()) hr.fail(where + " appear twice (corrupt)");
    for (std::size_t c = 0; c < e.boundary.size(); ++c) {
      const double d = e.boundary[c];
      if (d == kNoLayer) continue;
      if (!(d >= -kMaxBoundary && d <= kMaxBoundary))
        hr.fail(where + ": column " + std::to_string(c) + " has boundary " + detail::to_text(d) +
                " m (allowed: -2e7 to 2e7, or +infinity; corrupt)");
      if (e.lower[c] >= palette_size)
        hr.fail(where + ": column " + std::to_string(c) + " holds lower index " + std::to_string(e.lower[c]) +
                ", beyond the palette (0 to " + std::to_string(palette_size - 1) + ")");
    }
    tile->layer_boundary = std::move(e.boundary);
    tile->layer_lower = std::move(e.lower);
    tile->normalize_layers();
    store.mark_painted(*tile);
  }
  if (!layers.tiles.empty()) store.mark_layered();
}

/// A map read from a file, applied once its tiles are.
struct SavedMap {
  std::vector<Material> palette;
  std::vector<std::pair<TileKey, std::vector<std::uint8_t>>> tiles;
};

SavedMap read_map(Reader& hr, int n) {
  SavedMap map;
  const auto size = hr.get<std::uint32_t>("palette");
  if (size < 1 || size > static_cast<std::uint32_t>(Terrain::kMaxMaterials))
    hr.fail("palette of " + std::to_string(size) + " materials (allowed: 1 to " +
            std::to_string(Terrain::kMaxMaterials) + "; corrupt)");
  for (std::uint32_t k = 1; k < size; ++k) map.palette.push_back(read_material(hr));
  const auto painted = hr.get<std::uint64_t>("material map");
  const std::size_t columns = static_cast<std::size_t>(n) * n;
  if (painted > hr.remaining() / (16 + columns))
    hr.fail("painted tile count " + std::to_string(painted) + " does not fit the file (corrupt)");
  for (std::uint64_t k = 0; k < painted; ++k) {
    TileKey key;
    key.tx = hr.get<std::int64_t>("material map");
    key.ty = hr.get<std::int64_t>("material map");
    std::vector<std::uint8_t> index(columns);
    for (std::uint8_t& m : index) m = hr.get<std::uint8_t>("material map");
    map.tiles.emplace_back(key, std::move(index));
  }
  return map;
}

/// Paints the saved tiles (the palette already set, `palette_size` entries), stamped as
/// painted in the loaded generation.
void apply_map(const Reader& hr, SavedMap& map, std::size_t palette_size, TileStore& store) {
  for (auto& [key, index] : map.tiles) {
    const std::string where = "material map of tile (" + std::to_string(key.tx) + ", " + std::to_string(key.ty) + ")";
    Tile* tile = store.find(key);
    if (tile == nullptr) hr.fail(where + ": no such tile in the file (corrupt)");
    if (!tile->material.empty()) hr.fail(where + " appears twice (corrupt)");
    for (std::size_t c = 0; c < index.size(); ++c)
      if (index[c] >= palette_size)
        hr.fail(where + ": column " + std::to_string(c) + " holds index " + std::to_string(index[c]) +
                ", beyond the palette (0 to " + std::to_string(palette_size - 1) + ")");
    tile->material = std::move(index);
    tile->normalize_material();
    store.mark_painted(*tile);
  }
}

std::string hex(std::uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%08x", v);
  return buf;
}

// Checks the magic, byte order, version, precision and checksum. Returns a reader of what
// lies between the header and the checksum, and sets version. The byte order comes first:
// a file from the other byte order reads every number swapped, its version too.
Reader open_body(std::span<const unsigned char> bytes, const std::string& name, std::uint32_t& version) {
  const Reader r(bytes, bytes.size(), name);
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    r.fail("not a Shore terrain state (magic \"SHORETRN\" missing)");
  if (bytes.size() < sizeof kMagic + 8 + 8) r.fail("truncated (file ends inside the header)");
  const std::size_t body = bytes.size() - sizeof(std::uint64_t);
  Reader hr(bytes, body, name);
  for (std::size_t k = 0; k < sizeof kMagic; ++k) hr.get<char>("magic");
  version = hr.get<std::uint32_t>("version");
  if (const auto mark = hr.get<std::uint32_t>("byte-order mark"); mark != kByteOrderMark)
    hr.fail(mark == __builtin_bswap32(kByteOrderMark)
                ? "written on a machine with the other byte order (byte-order mark " + hex(mark) +
                      "; this build reads files of its own byte order, " + hex(kByteOrderMark) + ")"
                : "byte-order mark " + hex(mark) + " is neither byte order's (corrupt)");
  if (version < kOldestVersion || version > kVersion)
    hr.fail("unsupported format version " + std::to_string(version) + " (this build reads versions " +
            std::to_string(kOldestVersion) + " to " + std::to_string(kVersion) + ")");
  if (version >= 4)
    if (const auto real = hr.get<std::uint32_t>("precision"); real != kRealBytes)
      hr.fail("stores " + std::to_string(real) + "-byte real numbers; this build reads " + std::to_string(kRealBytes) +
              "-byte (float64) ones only");
  std::uint64_t stored_sum = 0;
  std::memcpy(&stored_sum, bytes.data() + body, sizeof stored_sum);
  if (stored_sum != checksum(bytes.data(), body)) hr.fail("checksum mismatch (file truncated or corrupt)");
  return hr;
}

TerrainSettings read_settings(Reader& hr, std::uint32_t version, std::shared_ptr<const HeightSource> base) {
  TerrainSettings s;
  s.cell = hr.get<double>("settings");
  s.origin_x = hr.get<double>("settings");
  s.origin_y = hr.get<double>("settings");
  s.tile_columns = hr.get<std::int32_t>("settings");
  s.base_height = hr.get<double>("settings");
  s.max_erosion_passes = hr.get<std::int32_t>("settings");
  s.active_margin = hr.get<std::int32_t>("settings");
  s.contact_tolerance = hr.get<double>("settings");
  s.threads = hr.get<std::int32_t>("settings");
  s.parallel_min_columns = hr.get<std::int32_t>("settings");
  // Version 1 states were stepped with every covered column active and under the body.
  s.active_reach = version >= 2 ? hr.get<double>("settings") : std::numeric_limits<double>::infinity();
  if (version >= 4) s.idle_tile_steps = hr.get<std::int32_t>("settings");
  const auto name_size = hr.get<std::uint32_t>("material");
  if (name_size > 4096) hr.fail("material name of " + std::to_string(name_size) + " bytes (corrupt)");
  Material& m = s.material;
  m.name = hr.get_string(name_size, "material");
  for (double* v : {&m.theta_stop, &m.sigma, &m.theta_in, &m.theta_out, &m.alpha, &m.bekker_n, &m.bekker_kc,
                    &m.bekker_kphi, &m.friction, &m.soil_depth})
    *v = hr.get<double>("material");
  m.rigid = hr.get<std::uint8_t>("material") != 0;
  if (version >= 3)
    for (double* v : {&m.cohesion, &m.friction_angle, &m.shear_modulus, &m.remould_ratio, &m.remould_shear_ratio,
                      &m.remould_length})
      *v = hr.get<double>("material");
  if (version >= 4)
    read_spray_settings(hr, s);
  else
    s.spray.enabled = false;  // stepped without spray: it continues so
  // Version 5 on: the unloading modulus; older files were stepped with rigid-plastic columns.
  m.unload_modulus = version >= 5 ? hr.get<double>("material") : 0.0;
  s.base = std::move(base);
  try {
    s.validate();
  } catch (const InvalidSetting& e) {
    hr.fail(std::string("invalid settings: ") + e.what());
  }
  return s;
}

bool addressable(std::int64_t column) { return column >= -kMaxColumnIndex && column <= kMaxColumnIndex; }

std::string rect_text(const GridRect& r) {
  return "(" + std::to_string(r.i0) + ", " + std::to_string(r.j0) + ") + " + std::to_string(r.nx) + " x " +
         std::to_string(r.ny);
}

std::vector<GridRect> read_unsettled(Reader& hr) {
  std::vector<GridRect> boxes;
  const auto regions = hr.get<std::uint64_t>("eroding regions");
  if (regions > hr.remaining() / 24) hr.fail("eroding region count " + std::to_string(regions) + " (corrupt)");
  for (std::uint64_t k = 0; k < regions; ++k) {
    GridRect box;
    box.i0 = hr.get<std::int64_t>("eroding regions");
    box.j0 = hr.get<std::int64_t>("eroding regions");
    box.nx = hr.get<std::int32_t>("eroding regions");
    box.ny = hr.get<std::int32_t>("eroding regions");
    if (box.nx <= 0 || box.ny <= 0 || static_cast<std::int64_t>(box.nx) * box.ny > kMaxRegionColumns ||
        !addressable(box.i0) || !addressable(box.j0))
      hr.fail("eroding region " + rect_text(box) + " (corrupt)");
    boxes.push_back(box);
  }
  return boxes;
}

/// A saved state's eroding regions lie on saved tiles (a step creates the tiles of every
/// region it works on); a region elsewhere is corrupt, and could make the next step work
/// on far more columns than the file holds.
void check_unsettled_on_tiles(const Reader& hr, const std::vector<GridRect>& boxes, const TileStore& store) {
  for (const GridRect& box : boxes) {
    const std::int64_t n = store.n();
    const std::int64_t tx0 = floor_div(box.i0, n), tx1 = floor_div(box.i0 + box.nx - 1, n);
    const std::int64_t ty0 = floor_div(box.j0, n), ty1 = floor_div(box.j0 + box.ny - 1, n);
    if ((tx1 - tx0 + 1) * (ty1 - ty0 + 1) > static_cast<std::int64_t>(store.size()))
      hr.fail("eroding region " + rect_text(box) + " covers more tiles than the file holds (corrupt)");
    for (std::int64_t ty = ty0; ty <= ty1; ++ty)
      for (std::int64_t tx = tx0; tx <= tx1; ++tx)
        if (store.find({tx, ty}) == nullptr)
          hr.fail("eroding region " + rect_text(box) + " lies outside the saved tiles (corrupt)");
  }
}

/// Heights, sinkages and base heights beyond this (m) are corrupt: no ground is that far
/// from sea level, and sums of such values would overflow.
constexpr double kMaxLevel = 1e7;

void check_tile_values(const Reader& hr, const TileKey& key, const Tile& t) {
  const std::string where = "tile (" + std::to_string(key.tx) + ", " + std::to_string(key.ty) + ")";
  for (std::size_t c = 0; c < t.height.size(); ++c)
    for (const double v : {t.height[c], t.sinkage[c], t.base[c]}) {
      if (!std::isfinite(v)) hr.fail(where + " holds a non-finite value");
      if (std::abs(v) > kMaxLevel) hr.fail(where + " holds " + detail::to_text(v) + " m, beyond +-1e7 m (corrupt)");
    }
}

void read_tiles(Reader& hr, int n, TileStore& store) {
  const auto count = hr.get<std::uint64_t>("tile count");
  const std::size_t columns = static_cast<std::size_t>(n) * n;
  const std::size_t tile_bytes = 2 * sizeof(std::int64_t) + 3 * columns * sizeof(double);
  if (count > hr.remaining() / tile_bytes || count * tile_bytes != hr.remaining())
    hr.fail("tile count " + std::to_string(count) + " does not match the file size");
  for (std::uint64_t k = 0; k < count; ++k) {
    TileKey key;
    key.tx = hr.get<std::int64_t>("tile");
    key.ty = hr.get<std::int64_t>("tile");
    if (!addressable(key.tx) || !addressable(key.ty) || !addressable(key.tx * n) || !addressable(key.ty * n))
      hr.fail("tile (" + std::to_string(key.tx) + ", " + std::to_string(key.ty) +
              ") lies beyond column index 2^52 (corrupt)");
    auto tile = std::make_unique<Tile>(n);
    hr.get_doubles(tile->height, "tile");
    hr.get_doubles(tile->sinkage, "tile");
    hr.get_doubles(tile->base, "tile");
    check_tile_values(hr, key, *tile);
    if (!store.adopt(key, std::move(tile)))
      hr.fail("tile (" + std::to_string(key.tx) + ", " + std::to_string(key.ty) + ") appears twice");
  }
}

}  // namespace

std::vector<unsigned char> Terrain::save_bytes() const {
  const Impl& im = *impl_;
  Writer w;
  for (char c : kMagic) w.put(c);
  const std::vector<TileKey> keys = im.tiles.sorted_keys();
  // A body between two clinging steps needs version 9, and with it the blocks of 6 to 8.
  const bool steps = im.spray.state.has_bodies_between_steps();
  const bool map = steps || has_layers(im.tiles, keys) || has_map(im.palette, im.tiles, keys);
  w.put(steps ? kSprayStepsVersion : map ? kSprayMaterialsVersion : kOneMaterialVersion);
  w.put(kByteOrderMark);
  w.put(kRealBytes);
  write_settings(w, im.s);
  w.put(im.compacted), w.put(im.edited);
  w.put(static_cast<std::uint64_t>(im.unsettled.size()));
  for (const GridRect& r : im.unsettled)
    w.put(r.i0), w.put(r.j0), w.put(static_cast<std::int32_t>(r.nx)), w.put(static_cast<std::int32_t>(r.ny));
  write_spray_state(w, im.spray.state, {.materials = map, .steps = steps});
  if (map) write_map(w, im.palette, im.tiles, keys);
  if (map) write_layers(w, im.tiles, keys);
  w.put(static_cast<std::uint64_t>(keys.size()));
  for (const TileKey& key : keys) {
    const Tile& t = *im.tiles.find(key);
    w.put(key.tx), w.put(key.ty);
    w.put_doubles(t.height), w.put_doubles(t.sinkage), w.put_doubles(t.base);
  }
  w.put(checksum(w.bytes.data(), w.bytes.size()));
  return std::move(w.bytes);
}

void Terrain::save(const std::filesystem::path& file) const {
  write_file_atomically(file, save_bytes(), "terrain state");
}

Terrain Terrain::load(const std::filesystem::path& file, std::shared_ptr<const HeightSource> base) {
  return load_bytes(read_file_bytes(file, "terrain state"), file.string(), std::move(base));
}

Terrain Terrain::load_bytes(std::span<const unsigned char> bytes, const std::string& name,
                            std::shared_ptr<const HeightSource> base) {
  std::uint32_t version = 0;
  Reader hr = open_body(bytes, name, version);
  Terrain t(read_settings(hr, version, std::move(base)));
  Impl& im = *t.impl_;
  im.compacted = hr.get<double>("volume bookkeeping");
  im.edited = hr.get<double>("volume bookkeeping");
  if (!std::isfinite(im.compacted) || !std::isfinite(im.edited)) hr.fail("volume bookkeeping is not finite");
  if (version >= 2) im.unsettled = read_unsettled(hr);
  if (version >= 4)
    read_spray_state(hr, im.spray.state,
                     {.materials = version >= kSprayMaterialsVersion, .steps = version >= kSprayStepsVersion});
  SavedMap map;
  if (version >= 6) map = read_map(hr, im.s.tile_columns);
  SavedLayers layers;
  if (version >= kLayersVersion) layers = read_layers(hr, im.s.tile_columns);
  read_tiles(hr, im.s.tile_columns, im.tiles);
  if (version >= 6) {
    // Validated as Terrain::set_palette does, but without a new generation: a loaded
    // terrain is generation 1, palette, paint and tiles alike.
    std::vector<Material> palette{im.s.material};
    palette.insert(palette.end(), map.palette.begin(), map.palette.end());
    try {
      im.check_palette(palette, "terrain.Terrain.set_palette");
    } catch (const InvalidSetting& e) {
      hr.fail(std::string("invalid palette: ") + e.what());
    }
    im.adopt_palette(std::move(palette));
    apply_map(hr, map, im.palette.size(), im.tiles);
    apply_layers(hr, layers, im.palette.size(), im.tiles);
  }
  check_spray_materials(hr, im.spray.state, im.palette.size());
  check_unsettled_on_tiles(hr, im.unsettled, im.tiles);
  return t;
}

}  // namespace shore::terrain
