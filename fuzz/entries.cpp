#include "entries.h"

#include "coupled_world.h"
#include "delta_server.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

#include <zstd.h>

#include "shore/bullet/recording_file.h"
#include "shore/core/envelope.h"
#include "shore/core/error.h"
#include "shore/core/hash.h"
#include "shore/terrain/height_source.h"
#include "shore/terrain/material_image.h"
#include "shore/terrain/material_palette.h"
#include "shore/terrain/soil_delta.h"
#include "shore/terrain/terrain.h"

namespace shore::fuzz {

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw InvariantBroken(what);
}

void require_finite_volume(const terrain::Terrain& t, const char* when) {
  const terrain::VolumeTotals v = t.volume();
  require(std::isfinite(v.ground) && std::isfinite(v.compacted) && std::isfinite(v.edited),
          std::string("non-finite volume ") + when);
}

/// A small flat press just below the soil at columns (0..3, 0..3), in grid coordinates (the
/// file's origin and cell may be anything).
shore::EnvelopeRaster press_near_origin(const terrain::Terrain& t) {
  shore::EnvelopeRaster env;
  env.resize(0, 0, 4, 4, false);
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) env.lower[env.index(i, j)] = t.height(i, j) - 0.001;
  return env;
}

/// What a game does with a loaded state: steps it, reads it, saves it again.
void exercise(terrain::Terrain& t) {
  require_finite_volume(t, "after load");
  (void)t.take_changed();
  try {
    t.step({});  // the regions the file says are still eroding
    const shore::EnvelopeRaster env = press_near_origin(t);
    const terrain::Imprint im{&env};
    t.step({&im, 1});
  } catch (const InvalidSetting&) {
    // A refused step (a region too large to gather) changes nothing: allowed.
  }
  require_finite_volume(t, "after two steps");
  for (int j = -1; j <= 4; ++j)
    for (int i = -1; i <= 4; ++i) require(std::isfinite(t.height(i, j)), "non-finite height after a step");
  const std::vector<unsigned char> again = t.save_bytes();
  const terrain::Terrain reloaded = terrain::Terrain::load_bytes(again, "fuzz round trip");
  require(reloaded.state_hash() == t.state_hash(), "save and load changed the state");
}

std::uint32_t big_endian_32(const unsigned char* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | std::uint32_t{p[3]};
}

/// Rewrites the CRC of every chunk that lies inside the file, so that mutations reach the
/// decoder behind the loader's CRC check.
void fix_chunk_crcs(std::vector<unsigned char>& png) {
  for (std::size_t pos = 8; png.size() >= pos + 12;) {
    const std::uint32_t length = big_endian_32(png.data() + pos);
    if (png.size() - pos - 12 < length) return;
    std::uint32_t c = 0xffffffffu;
    for (std::size_t i = pos + 4; i < pos + 8 + length; ++i) {
      c ^= png[i];
      for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    c ^= 0xffffffffu;
    for (int b = 0; b < 4; ++b) png[pos + 8 + length + b] = static_cast<unsigned char>(c >> (24 - 8 * b));
    pos += 12 + length;
  }
}

/// Byte 0 odd: the rest with the file's checksum appended; even: the rest as it is.
std::vector<unsigned char> with_checksum_mode(std::span<const std::uint8_t> data) {
  std::vector<unsigned char> bytes(data.begin() + 1, data.end());
  if (data[0] & 1) {
    StateHash sum;
    sum.add_bytes(bytes.data(), bytes.size());
    const std::uint64_t checksum = sum.value();
    const auto* p = reinterpret_cast<const unsigned char*>(&checksum);
    bytes.insert(bytes.end(), p, p + sizeof checksum);
  }
  return bytes;
}

}  // namespace

bool terrain_state(std::span<const std::uint8_t> data) {
  if (data.empty()) return false;
  const std::vector<unsigned char> bytes = with_checksum_mode(data);
  try {
    terrain::Terrain t = terrain::Terrain::load_bytes(bytes, "fuzz input");
    exercise(t);
    return true;
  } catch (const FileError&) {
    return false;
  }
}

namespace {

std::uint64_t world_hash(const CoupledWorld& w) {
  StateHash h;
  h.add(w.soil().state_hash());
  h.add(w.surface().state_hash());
  const btTransform& t = w.ball().getWorldTransform();
  for (int k = 0; k < 3; ++k)
    h.add(double(t.getOrigin()[k])), h.add(double(w.ball().getLinearVelocity()[k])),
        h.add(double(w.ball().getAngularVelocity()[k]));
  for (const double v : w.robot_state()) h.add(v);
  if (const btRigidBody* c = w.chassis())
    for (int k = 0; k < 3; ++k)
      h.add(double(c->getWorldTransform().getOrigin()[k])), h.add(double(c->getLinearVelocity()[k]));
  return h.value();
}

void require_finite_world(const CoupledWorld& w, const char* when) {
  const btTransform& t = w.ball().getWorldTransform();
  for (int k = 0; k < 3; ++k)
    require(std::isfinite(t.getOrigin()[k]) && std::isfinite(w.ball().getLinearVelocity()[k]) &&
                std::isfinite(w.ball().getAngularVelocity()[k]),
            std::string("non-finite ball ") + when);
  for (const double v : w.robot_state()) require(std::isfinite(v), std::string("non-finite multibody ") + when);
  if (const btRigidBody* c = w.chassis())
    for (int k = 0; k < 3; ++k)
      require(std::isfinite(c->getWorldTransform().getOrigin()[k]) && std::isfinite(c->getLinearVelocity()[k]),
              std::string("non-finite car ") + when);
  require_finite_volume(w.soil(), when);
  require(std::isfinite(w.surface().volume()), std::string("non-finite water volume ") + when);
}
}  // namespace

bool coupled_checkpoint(std::span<const std::uint8_t> data) {
  if (data.empty()) return false;
  // The container is read before any world is built: most mutations break it, and the
  // target's speed is the number of inputs that reach the sections' readers.
  std::optional<CheckpointReader> reader;
  try {
    reader.emplace(with_checksum_mode(data), "fuzz input", bullet::scalar_bytes());
  } catch (const FileError&) {
    return false;
  }
  // A checkpoint with the multibody's section restores into the world with links, one with
  // a vehicle's into the world with the car.
  auto world = std::make_unique<CoupledWorld>(reader->has("MBODY"), reader->has("VEHICLE"));
  try {
    world->restore(*reader);
  } catch (const FileError&) {
    return false;
  } catch (const InvalidSetting&) {
    return false;  // a soil state with settings this build refuses
  }
  require_finite_world(*world, "after restore");
  const std::vector<unsigned char> saved = world->checkpoint();
  try {
    for (int k = 0; k < 3; ++k) world->step();
  } catch (const InvalidSetting&) {
    return true;  // a step refused (an envelope window too large to gather): allowed
  }
  require_finite_world(*world, "after three steps");
  CoupledWorld again(world->links(), world->car());
  again.restore(CheckpointReader(saved, "fuzz round trip", bullet::scalar_bytes()));
  for (int k = 0; k < 3; ++k) again.step();
  require(world_hash(again) == world_hash(*world), "a saved checkpoint does not continue identically");
  return true;
}

bool checkpoint_seed_fits_build(std::span<const std::uint8_t> data) {
  constexpr std::size_t kPrecisionAt = 1 + 8 + 4 + 4;  // mode byte, magic, version, byte-order mark
  if (data.size() < kPrecisionAt + 4) return false;
  std::uint32_t scalar = 0;
  std::memcpy(&scalar, data.data() + kPrecisionAt, sizeof scalar);
  return scalar == bullet::scalar_bytes();
}

namespace {
/// A zstd container as Shore's soil deltas and recordings write it: 8 magic bytes, u32
/// version, u32 byte-order mark, the header fields as given, u64 raw size, u64 frame size,
/// the zstd frame of the payload, u64 checksum of every byte before it.
std::vector<unsigned char> zstd_container(const char (&magic)[9], std::uint32_t version,
                                          std::span<const std::uint8_t> header, std::span<const std::uint8_t> payload) {
  std::vector<unsigned char> out(magic, magic + 8);
  const auto put = [&out](const auto v) {
    const auto* p = reinterpret_cast<const unsigned char*>(&v);
    out.insert(out.end(), p, p + sizeof v);
  };
  put(version), put(std::uint32_t{0x01020304u});
  out.insert(out.end(), header.begin(), header.end());
  put(std::uint64_t{payload.size()});
  std::vector<unsigned char> frame(ZSTD_compressBound(payload.size()));
  const std::size_t n = ZSTD_compress(frame.data(), frame.size(), payload.data(), payload.size(), 1);
  require(ZSTD_isError(n) == 0, "zstd could not compress a payload");
  put(std::uint64_t{n});
  out.insert(out.end(), frame.begin(), frame.begin() + static_cast<std::ptrdiff_t>(n));
  StateHash sum;
  sum.add_bytes(out.data(), out.size());
  put(sum.value());
  return out;
}
}  // namespace

std::vector<unsigned char> wrap_delta_payload(std::span<const std::uint8_t> fields, std::uint32_t version) {
  constexpr std::size_t kFields = 8 + 8 + 8;  // quantum, from, to
  if (fields.size() < kFields) return {};
  // The container's layout (shore/terrain/soil_delta.h): version 2, 3, 5 or 6 (the ones the
  // encoder writes, so mutations reach its spray, map and layer blocks too), the three fields.
  return zstd_container("SHORESDL", version, fields.first(kFields), fields.subspan(kFields));
}

namespace {
const DeltaServer& delta_server() {
  static const DeltaServer server;
  return server;
}

/// Heights and sinkage of every column the replica lists as changed are finite.
void require_finite_changes(const terrain::Terrain& t, std::uint64_t since) {
  std::vector<double> h;
  for (const shore::GridRect& r : t.changed_since(since)) {
    h.resize(static_cast<std::size_t>(r.nx) * static_cast<std::size_t>(r.ny));
    t.heights(r, h);
    for (const double z : h) require(std::isfinite(z), "non-finite height applied");
    for (std::int64_t j = r.j0; j < r.j0 + r.ny; ++j)
      for (std::int64_t i = r.i0; i < r.i0 + r.nx; ++i) require(std::isfinite(t.sinkage(i, j)), "non-finite sinkage");
  }
}
}  // namespace

bool soil_delta(std::span<const std::uint8_t> data) {
  if (data.empty()) return false;
  const std::vector<unsigned char> delta = (data[0] & 2) ? wrap_delta_payload(data.subspan(1), (data[0] & 16)  ? 6
                                                                                               : (data[0] & 8) ? 5
                                                                                               : (data[0] & 4) ? 3
                                                                                                               : 2)
                                                         : with_checksum_mode(data);
  terrain::Terrain replica(delta_soil());
  const DeltaServer& server = delta_server();
  const std::uint64_t at = terrain::SoilDelta::apply(replica, server.first_snapshot(), 0);
  require(at == server.first_generation(), "the first snapshot brought the wrong generation");
  const std::uint64_t hash = replica.state_hash(), generation = replica.generation();
  try {
    (void)terrain::SoilDelta::apply(replica, delta, at);
  } catch (const FileError&) {
    require(replica.state_hash() == hash && replica.generation() == generation, "a refused delta changed the replica");
    return false;
  } catch (const InvalidSetting&) {
    require(replica.state_hash() == hash && replica.generation() == generation, "a refused delta changed the replica");
    return false;
  }
  require_finite_changes(replica, generation);
  exercise(replica);
  return true;
}

bool heightmap_png(std::span<const std::uint8_t> data) {
  if (data.empty()) return false;
  std::vector<unsigned char> png(data.begin() + 1, data.end());
  if (data[0] & 1) fix_chunk_crcs(png);
  try {
    const terrain::Heightmap h = terrain::Heightmap::from_png_bytes(png, "fuzz input", {});
    require(h.width() >= 1 && h.rows() >= 1, "empty heightmap accepted");
    for (const double x : {-1.0, 0.0, 0.5 * h.width(), double(h.width())})
      for (const double y : {-1.0, 0.0, 0.5 * h.rows(), double(h.rows())}) {
        const double z = h.height(x, y);
        require(std::isfinite(z) && z >= -1e-9 && z <= 1.0 + 1e-9, "PNG heights must lie in [0, 1] m");
      }
    return true;
  } catch (const FileError&) {
    return false;
  }
}

bool heightmap_raw(std::span<const std::uint8_t> data) {
  if (data.size() < 2) return false;
  const int width = 1 + data[0] % 32;
  const std::span<const std::uint8_t> file = data.subspan(2);
  const int rows = data[1] >= 128 ? std::max<int>(1, int(file.size() / 4 / std::size_t(width))) : 1 + data[1] % 32;
  try {
    const terrain::Heightmap h = terrain::Heightmap::from_raw_float32_bytes(file, "fuzz input", width, rows, {});
    require(h.width() == width && h.rows() == rows, "raw heightmap of the wrong size accepted");
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < width; ++c) require(std::isfinite(h.height(c, r)), "non-finite raw height");
    return true;
  } catch (const FileError&) {
    return false;
  }
}

namespace {

/// A small terrain for a material map: 8-column tiles, 5 cm columns, one thread.
terrain::TerrainSettings map_soil(const terrain::Material& material) {
  terrain::TerrainSettings s;
  s.material = material;
  s.tile_columns = 8;
  s.cell = 0.05;
  s.max_erosion_passes = 1;
  s.threads = 1;
  return s;
}

/// Palette entry k: sand, made different per index (bearing, shear, slope limits), so that
/// every stage reads a column's own material.
terrain::Material map_entry(int k) {
  terrain::Material m = terrain::Material::sand();
  m.bekker_kphi *= 1.0 + 0.5 * (k % 5);
  m.friction_angle = (20.0 + 2.0 * (k % 7)) * 0.017453292519943295;
  m.theta_out += 0.02 * (k % 3);
  return m;
}

/// Paints the image at columns (0, 0) on, with a palette as long as its largest index
/// needs; checks the map reads back pixel for pixel, then exercises the painted terrain
/// (steps, format 6 round trip).
void paint_and_exercise(const terrain::MaterialImage& image) {
  int largest = 0;
  for (int r = 0; r < image.rows(); ++r)
    for (int c = 0; c < image.width(); ++c) largest = std::max<int>(largest, image.at(c, r));
  std::vector<terrain::Material> palette;
  for (int k = 0; k <= largest; ++k) palette.push_back(map_entry(k));
  terrain::Terrain t(map_soil(palette[0]));
  t.set_palette(palette);
  t.paint_image(image, {0, 0, image.width(), image.rows()});
  for (int r = 0; r < image.rows(); ++r)
    for (int c = 0; c < image.width(); ++c)
      require(t.material_index(c, image.rows() - 1 - r) == image.at(c, r), "a painted column reads another index");
  exercise(t);
  const terrain::Terrain reloaded = terrain::Terrain::load_bytes(t.save_bytes(), "fuzz map round trip");
  for (int r = 0; r < image.rows(); ++r)
    for (int c = 0; c < image.width(); ++c)
      require(reloaded.material_index(c, image.rows() - 1 - r) == t.material_index(c, image.rows() - 1 - r),
              "save and load changed the map");
}

/// Most pixels an accepted image is painted with (larger ones are only checked): each input
/// stays cheap.
constexpr int kMaxPaintedPixels = 64 * 64;

bool material_image(const terrain::MaterialImage& image) {
  require(image.width() >= 1 && image.rows() >= 1, "empty material image accepted");
  if (image.width() * image.rows() <= kMaxPaintedPixels) paint_and_exercise(image);
  return true;
}

bool material_palette(std::span<const std::uint8_t> text) {
  std::vector<terrain::Material> palette;
  try {
    palette = terrain::parse_palette({reinterpret_cast<const char*>(text.data()), text.size()}, "fuzz input");
  } catch (const FileError&) {
    return false;
  }
  require(!palette.empty() && palette.size() <= static_cast<std::size_t>(terrain::Terrain::kMaxMaterials),
          "a palette of " + std::to_string(palette.size()) + " entries accepted");
  terrain::Terrain t(map_soil(palette[0]));  // every entry passed Material::validate
  try {
    t.set_palette(palette);
  } catch (const InvalidSetting&) {
    return true;  // entries of another soil depth or rigid flag than entry 0's: refused by the terrain
  }
  // Each entry on a column of its own, the press over the first 16.
  const int n = static_cast<int>(palette.size());
  for (int k = 0; k < n; ++k) t.paint_rect({k % 4, k / 4, 1, 1}, k);
  exercise(t);
  return true;
}

}  // namespace

bool material_map(std::span<const std::uint8_t> data) {
  if (data.empty()) return false;
  const std::span<const std::uint8_t> rest = data.subspan(1);
  switch (data[0] % 4) {
    case 0:
      return material_palette(rest);
    case 1:
    case 2: {
      std::vector<unsigned char> png(rest.begin(), rest.end());
      if (data[0] % 4 == 1) fix_chunk_crcs(png);
      try {
        return material_image(terrain::MaterialImage::from_png_bytes(png, "fuzz input"));
      } catch (const FileError&) {
        return false;
      }
    }
    default: {
      if (rest.size() < 2) return false;
      const int width = 1 + rest[0] % 32;
      const std::span<const std::uint8_t> file = rest.subspan(2);
      const int rows = rest[1] >= 128 ? std::max<int>(1, int(file.size() / std::size_t(width))) : 1 + rest[1] % 32;
      try {
        const terrain::MaterialImage image = terrain::MaterialImage::from_raw_bytes(file, "fuzz input", width, rows);
        require(image.width() == width && image.rows() == rows, "raw material image of the wrong size accepted");
        return material_image(image);
      } catch (const FileError&) {
        return false;
      }
    }
  }
}

std::vector<unsigned char> wrap_recording_payload(std::span<const std::uint8_t> fields, std::uint32_t version) {
  if (fields.size() < 4) return {};
  // The container's layout (shore/bullet/recording_file.h): version 2 (no multibodies), 3 (no
  // wheels) or 4, u32 scalar bytes (the field given).
  return zstd_container("SHOREREC", version, fields.first(4), fields.subspan(4));
}

bool recording_seed_fits_build(std::span<const std::uint8_t> data) {
  // mode 2: the scalar bytes field follows the mode byte; else the file's precision field
  const std::size_t at = (!data.empty() && (data[0] & 2)) ? 1 : 1 + 8 + 4 + 4;
  if (data.size() < at + 4) return false;
  std::uint32_t scalar = 0;
  std::memcpy(&scalar, data.data() + at, sizeof scalar);
  return scalar == bullet::scalar_bytes();
}

bool recording(std::span<const std::uint8_t> data) {
  if (data.empty()) return false;
  const std::vector<unsigned char> file = (data[0] & 2) ? wrap_recording_payload(data.subspan(1), (data[0] & 8)   ? 4
                                                                                                  : (data[0] & 4) ? 3
                                                                                                                  : 2)
                                                        : with_checksum_mode(data);
  try {
    const bullet::Recording rec = bullet::read_recording(file, "fuzz input");
    // What a replay reads besides the scene's own loaders (checkpoint, soil deltas, water
    // states: fuzzed by their targets): every frame's body and multibody states and water
    // state chain.
    std::uint64_t multibody_scalars = 0;
    for (const bullet::Recording::MultiBodyLayout& m : rec.multibodies) {
      require(m.colliders.size() == std::size_t{m.links} + 1, "a multibody's collider flags not one per part");
      for (const std::uint8_t c : m.colliders) require(c <= 1, "a collider flag other than 0 or 1 accepted");
      multibody_scalars += m.scalars();
    }
    require(rec.version >= 3 || rec.multibodies.empty(), "multibodies in a version 2 recording");
    require(rec.version >= 4 || rec.vehicle_wheels.empty(), "wheels in a recording before version 4");
    std::vector<bullet::StateChain> water(rec.waters);
    int last = 0;
    for (const bullet::Recording::Frame& f : rec.frames) {
      require(f.substep > last && f.substep <= rec.substeps, "a frame out of order accepted");
      last = f.substep;
      require(f.terrain_deltas.size() == rec.terrain_generations.size() && f.water_diffs.size() == rec.waters,
              "a frame with another number of soils or waters accepted");
      require(f.bodies.size() == std::size_t{f.body_count} * bullet::Recording::kBodyScalars * sizeof(btScalar),
              "a frame's body section of the wrong size accepted");
      for (std::uint32_t w = 0; w < rec.waters; ++w)
        require(water[w].next(f.water_diffs[w]).size() == f.water_diffs[w].size(), "a water state of the wrong size");
      require(f.multibodies.size() == multibody_scalars * sizeof(btScalar),
              "a frame's multibody section of the wrong size accepted");
      (void)rec.body_scalars(f, "fuzz input");
      require(f.wheels.size() == rec.wheel_bytes(), "a frame's wheel section of the wrong size accepted");
      (void)rec.multibody_scalars(f, "fuzz input");
      (void)rec.wheel_scalars(f, "fuzz input");
    }
    require(last == rec.substeps, "a recording without its last frame accepted");
    // Written again (in its own version), it reads back to the same bytes.
    const bullet::Recording again = bullet::read_recording(bullet::write_recording(rec, 1), "fuzz round trip");
    require(again.raw == rec.raw, "a recording written again reads back otherwise");
    return true;
  } catch (const FileError&) {
    return false;
  }
}

const std::vector<Target>& targets() {
  static const std::vector<Target> list = {
      {"coupled_checkpoint", coupled_checkpoint, checkpoint_seed_fits_build},
      {"heightmap_png", heightmap_png},
      {"heightmap_raw", heightmap_raw},
      {"material_map", material_map},
      {"recording", recording, recording_seed_fits_build},
      {"soil_delta", soil_delta},
      {"terrain_state", terrain_state},
  };
  return list;
}

}  // namespace shore::fuzz
