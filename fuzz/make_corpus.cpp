// shore-fuzz-corpus <folder>: writes the fuzzers' seed corpus, <folder>/<target>/seed_*,
// from scratch (the committed fuzz/corpus was made by it; its seed_v4_* files by the
// version that wrote format 4, kept so the v4 reader stays fuzzed). Small valid inputs of every
// kind each loader reads: terrain states of format versions 3 and 5 (with and without the
// checksum the fuzz entry appends), PNG heightmaps of every colour type stb_image_write
// writes plus a 16-bit one, raw float32 maps, checkpoints of a small coupled world (a
// float build writes them: a double build refuses their precision), material maps (palette
// texts, index PNGs and raw indices; painted terrain states of format 6; painted, layered
// states with spray of a painted material, format 8), soil deltas of a small server
// (delta_server.h: a snapshot and increments, quantised and exact, painted (with the map,
// version 3), layered (version 5), whole and as payloads), recordings' layouts (whole, without the checksum, as a raw
// payload).
#include <stb_image_write.h>
#include <zstd.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "coupled_world.h"
#include "delta_server.h"
#include "png_writer.h"
#include "shore/bullet/body_state.h"
#include "shore/bullet/recording_file.h"
#include "shore/core/envelope.h"
#include "shore/terrain/terrain.h"

namespace fs = std::filesystem;
using Bytes = std::vector<unsigned char>;

namespace {

void stb_write_to(void* context, void* data, int size) {
  auto* out = static_cast<Bytes*>(context);
  out->insert(out->end(), static_cast<unsigned char*>(data), static_cast<unsigned char*>(data) + size);
}

void write(const fs::path& file, const Bytes& bytes) {
  fs::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

/// Small tiles, a press with its rim still eroding: every section of the format is used.
shore::terrain::Terrain pressed_state() {
  shore::terrain::TerrainSettings s;
  s.tile_columns = 4;
  s.cell = 0.05;
  s.max_erosion_passes = 1;
  s.threads = 1;
  shore::terrain::Terrain t(s);
  shore::EnvelopeRaster env;
  env.resize(1, 1, 3, 3, false);
  for (double& v : env.lower) v = -0.02;
  const shore::terrain::Imprint im{&env};
  t.step({&im, 1});
  return t;
}

/// A material map (format 6): three materials painted as a disc and a rectangle, pressed
/// across their border.
shore::terrain::Terrain painted_state() {
  shore::terrain::Terrain t = pressed_state();
  shore::terrain::Material mud = shore::terrain::Material::sand();
  mud.name = "soft";
  mud.bekker_kphi *= 0.3;
  mud.friction_angle *= 0.7;
  shore::terrain::Material gravel = shore::terrain::Material::sand();
  gravel.name = "gravel";
  gravel.bekker_kphi *= 4.0;
  t.set_palette({t.settings().material, mud, gravel});
  t.paint_disc(0.1, 0.1, 0.08, 1);
  t.paint_rect({2, -2, 3, 3}, 2);
  shore::EnvelopeRaster env;
  env.resize(0, 0, 4, 4, false);
  for (double& v : env.lower) v = -0.03;
  const shore::terrain::Imprint im{&env};
  t.step({&im, 1});
  return t;
}

/// A 3 x 3 column plate 1 mm into the soil over rows [j0, j0 + 3), moving at 1 m/s along x
/// from column i0 for `steps` steps of 1/240 s, then lifted: soil clings to it (spray).
inline void slide_plate(shore::terrain::Terrain& t, int i0, int j0, int steps) {
  for (int k = 0; k <= steps; ++k) {  // the last step lifts it 5 cm: the soil it loaded goes with it
    shore::EnvelopeRaster env;
    env.resize(i0 + k, j0, 3, 3, false);
    for (double& v : env.lower) v = k < steps ? -0.001 : 0.05;
    shore::terrain::Imprint im{&env};
    im.velocity.x = 1.0;
    im.centre.x = t.column_x(i0 + k + 1), im.centre.y = t.column_y(j0 + 1), im.centre.z = 0.05;
    im.key = 3;
    t.step({&im, 1}, 1.0 / 240);
  }
}

/// Format 8: the painted terrain with layers in depth (a crust of the soft entry over
/// gravel under its disc, gravel over entry 0 under its rectangle) and soil of the soft
/// entry clinging to a plate that slid over it (spray carrying palette indices).
shore::terrain::Terrain layered_state() {
  shore::terrain::Terrain t = painted_state();
  t.paint_layer_disc(0.1, 0.1, 0.08, 2, 0.004);
  t.paint_layer_rect({2, -2, 3, 3}, 0, 0.01);
  slide_plate(t, -1, 1, 4);
  // Soil of an entry other than 0 clings: a palette of entry 0 alone is refused.
  bool refused = false;
  try {
    shore::terrain::Terrain copy = shore::terrain::Terrain::load_bytes(t.save_bytes(), "the layered seed");
    copy.set_palette({copy.settings().material});
  } catch (const std::exception&) {
    refused = true;
  }
  if (!(t.volume().clinging > 0.0) || !refused)
    throw std::runtime_error("no soil of a painted entry clings to the layered seed's plate");
  return t;
}

/// Format 9: one material, soil clinging to a plate whose clinging soil is stepped every
/// second step (Imprint::cling_every 2), left after a step that skipped it.
shore::terrain::Terrain cadence_state() {
  shore::terrain::Terrain t = pressed_state();
  // 4 steps on the soil, then lifted 5 cm, until a step skipped its soil (the terrain's step
  // count is not public: the format the save chose tells).
  for (int k = 0; k < 7 || t.save_bytes()[8] != 9; ++k) {
    if (k > 9) throw std::runtime_error("the cadence seed's plate never rested between two clinging steps");
    shore::EnvelopeRaster env;
    env.resize(k - 2, 1, 3, 3, false);
    for (double& v : env.lower) v = k < 4 ? -0.001 : 0.05;
    shore::terrain::Imprint im{&env};
    im.velocity.x = 1.0;
    im.centre.x = t.column_x(k - 1), im.centre.y = t.column_y(2), im.centre.z = k < 4 ? 0.05 : 0.1;
    im.key = 3;
    im.cling_every = 2;
    t.step({&im, 1}, 1.0 / 240);
  }
  if (!(t.volume().clinging > 0.0)) throw std::runtime_error("no soil clings to the cadence seed's plate");
  return t;
}

/// A version 5 file as version 3 wrote it: no precision field (bytes 16-19), no
/// idle_tile_steps (the 4 bytes after active_reach), no spray settings and no
/// unload_modulus (after the material's shear fields) and no spray state (after the eroding
/// regions; only a soil that never sprayed can be converted). Layout at the top of
/// terrain/src/terrain_io.cpp.
Bytes as_version_3(Bytes v5) {
  v5.erase(v5.begin() + 88, v5.begin() + 92);
  v5.erase(v5.begin() + 16, v5.begin() + 20);
  auto read_u64 = [&](std::size_t at) {
    std::uint64_t v = 0;
    std::memcpy(&v, v5.data() + at, sizeof v);
    return v;
  };
  std::uint32_t name_length = 0;
  std::memcpy(&name_length, v5.data() + 84, sizeof name_length);  // after f64 active_reach at 76
  const std::size_t spray_at = 88 + name_length + 10 * 8 + 1 + 6 * 8;
  constexpr std::size_t kSpraySettings = 8 * 8 + 1 + 4 + 8 + 6 * 8 + 8;  // and unload_modulus (version 5)
  v5.erase(v5.begin() + static_cast<std::ptrdiff_t>(spray_at),
           v5.begin() + static_cast<std::ptrdiff_t>(spray_at + kSpraySettings));
  const std::size_t regions_at = spray_at + 2 * 8;  // after f64 compacted, edited
  const std::size_t state_at = regions_at + 8 + 24 * read_u64(regions_at);
  constexpr std::size_t kQuietState = 8 + 8 + 6 * 8 + 8 + 8 + 8;  // no particles, no bodies
  if (read_u64(state_at + kQuietState - 16) != 0 || read_u64(state_at + kQuietState - 8) != 0)
    throw std::runtime_error("the seed soil sprayed: cannot write it as version 3");
  v5.erase(v5.begin() + static_cast<std::ptrdiff_t>(state_at),
           v5.begin() + static_cast<std::ptrdiff_t>(state_at + kQuietState));
  v5[8] = 3;
  return v5;
}

/// The fuzz entry's input: mode byte (1: append the checksum) and the file.
Bytes entry_input(bool append_checksum, Bytes file) {
  if (append_checksum) {
    if (file.size() < 8) throw std::runtime_error("a seed file shorter than its checksum");
    file.resize(file.size() - 8);
  }
  file.insert(file.begin(), static_cast<unsigned char>(append_checksum ? 1 : 0));
  return file;
}

void terrain_seeds(const fs::path& dir) {
  const Bytes v5 = pressed_state().save_bytes();
  write(dir / "seed_v5_pressed", entry_input(true, v5));
  write(dir / "seed_v5_pressed_whole", entry_input(false, v5));
  Bytes v3 = as_version_3(v5);
  write(dir / "seed_v3_pressed", entry_input(true, v3));  // checksum recomputed by the entry
  shore::terrain::TerrainSettings s;
  s.tile_columns = 4;
  s.material = shore::terrain::Material::snow();
  shore::terrain::Terrain edited(s);
  edited.set_height(-3, 2, 0.25);
  write(dir / "seed_v5_edited_snow", entry_input(true, edited.save_bytes()));
  const Bytes v6 = painted_state().save_bytes();
  write(dir / "seed_v6_painted", entry_input(true, v6));
  write(dir / "seed_v6_painted_whole", entry_input(false, v6));
  const Bytes v8 = layered_state().save_bytes();
  if (v8.size() < 12 || v8[8] != 8) throw std::runtime_error("the layered seed soil was not written as version 8");
  write(dir / "seed_v8_layered_spray", entry_input(true, v8));
  write(dir / "seed_v8_layered_spray_whole", entry_input(false, v8));
  const Bytes v9 = cadence_state().save_bytes();
  if (v9.size() < 12 || v9[8] != 9) throw std::runtime_error("the cadence seed soil was not written as version 9");
  write(dir / "seed_v9_cadence", entry_input(true, v9));
  write(dir / "seed_v9_cadence_whole", entry_input(false, v9));
}

/// material_map's inputs: palette texts (mode 0), index PNGs (1: CRCs fixed; 2: as is) and
/// raw indices (3: width and rows bytes, then the file).
void material_map_seeds(const fs::path& dir) {
  auto text = [](const std::string& t) {
    Bytes out = {0};
    out.insert(out.end(), t.begin(), t.end());
    return out;
  };
  write(dir / "seed_palette", text("# index preset fields\n0 sand\n1 sand name=mud bekker_kphi=1.5e6 alpha=0.3\n\n"
                                   "2 sand name=gravel bekker_kphi=6e6 theta_out=0.6 spray.adhesion=0\n"));
  write(dir / "seed_palette_other_depth", text("0 sand\n1 mud\n"));  // the terrain refuses mud's soil depth
  write(dir / "seed_palette_one", text("0 snow friction_angle=0.3 cohesion=500\n"));
  write(dir / "seed_palette_rigid", text("0 rigid\n1 rigid friction=0.4\n"));
  const std::vector<unsigned char> index = {0, 1, 2, 1, 0, 3, 3, 2, 0, 1, 2, 3};  // 4 x 3
  Bytes png = {1};
  stbi_write_png_to_func(stb_write_to, &png, 4, 3, 1, index.data(), 4);
  write(dir / "seed_png_4x3", png);
  png[0] = 2;
  write(dir / "seed_png_4x3_as_is", png);
  Bytes raw = {3, 3, 2};  // width 4, rows 3
  raw.insert(raw.end(), index.begin(), index.end());
  write(dir / "seed_raw_4x3", raw);
  Bytes by_size = {3, 1, 200};  // width 2, rows from the size
  by_size.insert(by_size.end(), {5, 0, 0, 7});
  write(dir / "seed_raw_by_size", by_size);
}

/// A coupled world mid-run: the ball has pressed the soil and entered the water; with
/// links (seed_links_*), the multibody's base and wheel have too; with the car
/// (seed_car_*), its wheels.
void checkpoint_seeds(const fs::path& dir) {
  for (const int kind : {0, 1, 2}) {
    const bool links = kind == 1, car = kind == 2;
    shore::fuzz::CoupledWorld w(links, car);
    const std::string prefix = links ? "seed_links_" : car ? "seed_car_" : "seed_";
    const Bytes start = w.checkpoint();
    write(dir / (prefix + "start"), entry_input(true, start));
    for (int k = 0; k < 30; ++k) w.step();
    const Bytes mid = w.checkpoint();
    write(dir / (prefix + "mid_run"), entry_input(true, mid));
    write(dir / (prefix + "mid_run_whole"), entry_input(false, mid));
  }
}

/// soil_delta's mode 2 input (mode 6: a version 3 delta): the mode byte, quantum, from, to
/// (the delta's own header fields, bytes 16 to 40) and the payload its zstd frame holds.
Bytes payload_input(const Bytes& delta, unsigned char mode = 2) {
  constexpr std::size_t kFieldsAt = 16, kFieldsEnd = 40, kFrameAt = 56;
  const std::size_t frame = delta.size() - kFrameAt - 8;
  const unsigned long long raw_size = ZSTD_getFrameContentSize(delta.data() + kFrameAt, frame);
  if (raw_size == ZSTD_CONTENTSIZE_UNKNOWN || raw_size == ZSTD_CONTENTSIZE_ERROR)
    throw std::runtime_error("a soil delta's frame without its size");
  Bytes raw(raw_size);
  if (ZSTD_decompress(raw.data(), raw.size(), delta.data() + kFrameAt, frame) != raw.size())
    throw std::runtime_error("a soil delta's frame did not decompress");
  Bytes out = {mode};
  out.insert(out.end(), delta.begin() + kFieldsAt, delta.begin() + kFieldsEnd);
  out.insert(out.end(), raw.begin(), raw.end());
  return out;
}

void soil_delta_seeds(const fs::path& dir) {
  shore::fuzz::DeltaServer server;
  server.press_again();
  const std::uint64_t since = server.first_generation();
  const Bytes step = shore::terrain::SoilDelta::encode(server.soil(), since, {});
  const Bytes exact = shore::terrain::SoilDelta::encode(server.soil(), since, {.quantum = 0.0});
  const Bytes snapshot = shore::terrain::SoilDelta::encode(server.soil(), 0, {.compression_level = 19});
  write(dir / "seed_step", entry_input(true, step));
  write(dir / "seed_step_exact", entry_input(true, exact));
  write(dir / "seed_snapshot_whole", entry_input(false, snapshot));
  write(dir / "seed_step_payload", payload_input(step));
  write(dir / "seed_exact_payload", payload_input(exact));
  // Version 3: the palette and the repainted tiles travel too.
  server.paint();
  const Bytes painted = shore::terrain::SoilDelta::encode(server.soil(), since, {.quantum = 0.0});
  write(dir / "seed_painted_exact", entry_input(true, painted));
  write(dir / "seed_painted_payload", payload_input(painted, 6));
  // Version 5: the repainted tiles' layers travel too.
  server.layer();
  const Bytes layered = shore::terrain::SoilDelta::encode(server.soil(), since, {.quantum = 0.0});
  if (layered.size() < 12 || layered[8] != 5) throw std::runtime_error("the layered seed delta was not version 5");
  write(dir / "seed_layered_exact", entry_input(true, layered));
  write(dir / "seed_layered_payload", payload_input(layered, 10));
  // Version 6: soil clings to a plate between two clinging steps of its cadence.
  shore::fuzz::DeltaServer sliding;
  sliding.press_again();
  sliding.slide();
  const Bytes cadence = shore::terrain::SoilDelta::encode(sliding.soil(), since, {.quantum = 0.0});
  if (cadence.size() < 12 || cadence[8] != 6 || !(sliding.soil().volume().clinging > 0.0))
    throw std::runtime_error("the cadence seed delta was not version 6 with soil clinging");
  write(dir / "seed_cadence_exact", entry_input(true, cadence));
  write(dir / "seed_cadence_payload", payload_input(cadence, 18));
}

/// A small recording's layout (shore/bullet/recording_file.h): one soil, one water, two
/// bodies, three frames, and with `multibodies` two multibodies (one of two links, its
/// base and second link with colliders; one a lone base without a collider) and two
/// vehicles (of four wheels and of one). The nested
/// parts are short stand-ins (their own loaders are fuzzed by their own targets): what this
/// loader reads is the layout around them, and the water states' XOR chain (a state that
/// grows, changes in a few bytes, then shrinks). Without multibodies it is written as
/// version 2 (the seeds seed_three_frames*), so that the old layout stays fuzzed.
void recording_seeds(const fs::path& dir, bool multibodies) {
  shore::bullet::Recording rec;
  rec.version = multibodies ? shore::bullet::Recording::kVersion : 2;
  rec.scene = multibodies ? "rover" : "pond";
  rec.seconds = 0.05, rec.substep = 1.0 / 60.0, rec.cell = 0.1, rec.material = "sand", rec.smoke = true;
  rec.substeps = 3;
  rec.state_hash = 0x0123456789abcdefull;
  const Bytes initial = {'S', 'H', 'O', 'R', 'E', 'C', 'K', 'P', 1, 0, 0, 0};
  rec.initial = initial;
  rec.terrain_generations = {7};
  rec.waters = 1;
  if (multibodies) {
    rec.multibodies = {{.links = 2, .values = 13 + 2 * 2, .colliders = {1, 0, 1}}, {.values = 13, .colliders = {0}}};
    rec.vehicle_wheels = {4, 1};
  }
  std::vector<Bytes> owned;
  owned.reserve(16);
  shore::bullet::StateChain chain;
  const Bytes delta = {'S', 'H', 'O', 'R', 'E', 'S', 'D', 'L', 1, 0, 0, 0, 4, 3, 2, 1};
  const auto keep = [&owned](const std::vector<btScalar>& v) {
    const auto* p = reinterpret_cast<const unsigned char*>(v.data());
    owned.emplace_back(p, p + v.size() * sizeof(btScalar));
    return std::span<const unsigned char>(owned.back());
  };
  for (int k = 1; k <= 3; ++k) {
    shore::bullet::Recording::Frame f;
    f.substep = k;
    f.terrain_deltas = {delta};
    std::vector<btScalar> bodies;
    for (int b = 0; b < 2; ++b) {
      const btScalar state[18] = {1, 0, 0, 0, 1, 0, 0, 0, 1, btScalar(b), 0, btScalar(0.1 * k), 0, 0, btScalar(-k),
                                  0, 0, 0};
      bodies.insert(bodies.end(), state, state + 18);
    }
    f.bodies = keep(bodies);
    f.body_count = 2;
    if (multibodies) {
      std::vector<btScalar> m;
      for (const shore::bullet::Recording::MultiBodyLayout& l : rec.multibodies) {
        for (std::uint32_t v = 0; v < l.values; ++v) m.push_back(btScalar(0.01 * k * v));
        for (std::uint32_t c = 0; c < l.collider_count(); ++c) {
          const btScalar pose[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, btScalar(0.1 * k), btScalar(c), btScalar(0.5)};
          m.insert(m.end(), pose, pose + 12);
        }
      }
      f.multibodies = keep(m);
      std::vector<btScalar> wheels;
      for (int w = 0; w < 5; ++w) {
        const btScalar pose[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, btScalar(0.1 * k), btScalar(w), btScalar(0.4)};
        wheels.insert(wheels.end(), pose, pose + 12);
      }
      f.wheels = keep(wheels);
    }
    Bytes water(k == 3 ? 24 : 40, 0);
    for (std::size_t i = 0; i < water.size(); ++i) water[i] = static_cast<unsigned char>(i * (k == 2 ? 5 : 3));
    owned.push_back(chain.encode(water));
    f.water_diffs = {owned.back()};
    rec.frames.push_back(std::move(f));
  }
  const std::string name = multibodies ? "seed_multibodies" : "seed_three_frames";
  const Bytes file = shore::bullet::write_recording(rec);
  write(dir / name, entry_input(true, file));
  write(dir / (name + "_whole"), entry_input(false, file));
  const shore::bullet::Recording back = shore::bullet::read_recording(file, "seed");
  // recording's mode 2 (a version 2 container) or 14 (version 4): u32 scalar bytes, then the raw layout
  Bytes payload = {static_cast<unsigned char>(multibodies ? 14 : 2)};
  const std::uint32_t scalar = shore::bullet::scalar_bytes();
  const auto* p = reinterpret_cast<const unsigned char*>(&scalar);
  payload.insert(payload.end(), p, p + sizeof scalar);
  payload.insert(payload.end(), back.raw.begin(), back.raw.end());
  write(dir / (name + "_payload"), payload);
}

void png_seeds(const fs::path& dir) {
  const char* names[] = {"", "seed_grey8", "seed_grey_alpha8", "seed_rgb8", "seed_rgba8"};
  for (int channels = 1; channels <= 4; ++channels) {
    std::vector<unsigned char> px(3 * 2 * static_cast<std::size_t>(channels));
    for (std::size_t k = 0; k < px.size(); ++k) px[k] = static_cast<unsigned char>(37 * k + 11);
    Bytes png = {1};  // the entry's mode byte: CRCs fixed after mutation
    stbi_write_png_to_func(stb_write_to, &png, 3, 2, channels, px.data(), 3 * channels);
    write(dir / names[channels], png);
  }
  auto with_mode = [](unsigned char mode, Bytes png) {
    png.insert(png.begin(), mode);
    return png;
  };
  write(dir / "seed_grey16", with_mode(1, shore::fuzz::png16(2, 2, {0, 1000, 65535, 30000})));
  write(dir / "seed_grey16_row", with_mode(1, shore::fuzz::png16(5, 1, {1, 2, 3, 4, 5})));
  write(dir / "seed_grey16_as_is", with_mode(0, shore::fuzz::png16(3, 3, {9, 8, 7, 6, 5, 4, 3, 2, 1})));
}

Bytes raw_input(unsigned char width_byte, unsigned char rows_byte, const std::vector<float>& samples) {
  Bytes out = {width_byte, rows_byte};
  const auto* p = reinterpret_cast<const unsigned char*>(samples.data());
  out.insert(out.end(), p, p + samples.size() * sizeof(float));
  return out;
}

void raw_seeds(const fs::path& dir) {
  write(dir / "seed_3x2", raw_input(2, 1, {0.5f, -0.25f, 3.0f, 1.5f, 2.0f, 0.0f}));
  write(dir / "seed_4_by_size", raw_input(3, 200, {1, 2, 3, 4, 5, 6, 7, 8}));
  write(dir / "seed_1x1", raw_input(0, 0, {1e30f}));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: shore-fuzz-corpus <folder>   (writes <folder>/<target>/seed_*)\n");
    return 2;
  }
  const fs::path root = argv[1];
  terrain_seeds(root / "terrain_state");
  checkpoint_seeds(root / "coupled_checkpoint");
  png_seeds(root / "heightmap_png");
  raw_seeds(root / "heightmap_raw");
  material_map_seeds(root / "material_map");
  soil_delta_seeds(root / "soil_delta");
  recording_seeds(root / "recording", false);
  recording_seeds(root / "recording", true);
  std::printf("seeds written to %s\n", root.c_str());
  return 0;
}
