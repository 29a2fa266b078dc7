// Bad input is refused with an error naming the field, before any state changes; files
// round-trip bit-exactly and corrupt ones are refused.
#include <gtest/gtest.h>
#include <stb_image_write.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

#include "png_writer.h"
#include "shore/core/error.h"
#include "shore/core/hash.h"
#include "shore/terrain/terrain.h"
#include "terrain_fixtures.h"

using namespace shore::terrain;
using namespace shore::terrain::testing;
using shore::fuzz::png16;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

std::filesystem::path temp_file(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("shore_terrain_test_" + name);
}

void write_bytes(const std::filesystem::path& p, const std::vector<unsigned char>& bytes) {
  std::ofstream out(p, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

std::vector<unsigned char> read_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A terrain with some history: a sphere pressed into sand.
Terrain pressed_sand(double active_reach = TerrainSettings{}.active_reach) {
  TerrainSettings s;
  s.material = Material::sand();
  s.active_reach = active_reach;
  s.tile_columns = 16;
  Terrain t(s);
  for (int k = 1; k <= 5; ++k) {
    const shore::EnvelopeRaster env = sphere_envelope(t, 0.0, 0.0, 0.1 - 0.004 * k, 0.1);
    const Imprint im{&env};
    t.step({&im, 1});
  }
  return t;
}

}  // namespace

TEST(Errors, SettingsNameTheField) {
  auto bad = [](const std::function<void(TerrainSettings&)>& edit) {
    TerrainSettings s;
    edit(s);
    return message_of<shore::InvalidSetting>([&] { Terrain t(s); });
  };
  EXPECT_TRUE(mentions(bad([](auto& s) { s.cell = 0.0; }), "cell = 0"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.cell = -0.01; }), "cell"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.cell = kNaN; }), "cell"));
  // The edges of the ranges (a fuzzer's 1e155 cell overflowed the volume, a denormal one
  // stalled the step): just outside refused, the edge itself accepted.
  EXPECT_TRUE(mentions(bad([](auto& s) { s.cell = 0.99e-4; }), "cell"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.cell = 1001.0; }), "cell"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.cell = 1e-4; }), "(no exception)"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.cell = 1e3; }), "(no exception)"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.origin_y = 2e12; }), "origin_y"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.max_erosion_passes = 1001; }), "max_erosion_passes"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.max_erosion_passes = 1000; }), "(no exception)"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.active_margin = 257; }), "active_margin"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.active_margin = 256; }), "(no exception)"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.threads = 1025; }), "threads"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.idle_tile_steps = -1; }), "idle_tile_steps"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.origin_x = kInf; }), "origin_x"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.tile_columns = 2; }), "tile_columns"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.material.alpha = 1.5; }), "alpha = 1.5"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.material.alpha = -0.1; }), "alpha"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.material.theta_out = 0.0; }), "theta_out"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.material.theta_in = 2.0; }), "theta_in"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.material.theta_stop = -1.0; }), "theta_stop"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.material.sigma = 2.0; }), "sigma"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.base_height = kNaN; }), "base_height"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.max_erosion_passes = -1; }), "max_erosion_passes"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.active_margin = 0; }), "active_margin"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.contact_tolerance = -1e-3; }), "contact_tolerance"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.active_reach = 0.0; }), "active_reach = 0"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.active_reach = kNaN; }), "active_reach"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.threads = -2; }), "threads"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.parallel_min_columns = -1; }), "parallel_min_columns"));
  EXPECT_TRUE(mentions(bad([](auto&) {}), "(no exception)"));
}

TEST(Errors, BadEnvelopesAndOffsetsLeaveTheGridUntouched) {
  Terrain t = pressed_sand();
  t.take_changed();
  const std::uint64_t before = t.state_hash();
  const std::size_t tiles = t.tile_count();
  const shore::EnvelopeRaster good = sphere_envelope(t, 0.3, 0.0, 0.09, 0.1);
  auto step_with = [&](const shore::EnvelopeRaster& env, double offset) {
    // A valid imprint first, so a partial step would show in the hash.
    const Imprint ims[2] = {{&good}, {&env, offset}};
    return message_of<shore::InvalidSetting>([&] { t.step(ims); });
  };
  shore::EnvelopeRaster env = sphere_envelope(t, 0.0, 0.0, 0.05, 0.1);
  env.lower[env.lower.size() / 2] = kNaN;
  EXPECT_TRUE(mentions(step_with(env, 0.0), "terrain.Imprint[1].envelope.lower[")) << step_with(env, 0.0);
  env.lower[env.lower.size() / 2] = -kInf;
  EXPECT_TRUE(mentions(step_with(env, 0.0), "-inf"));
  env = sphere_envelope(t, 0.0, 0.0, 0.05, 0.1);
  EXPECT_TRUE(mentions(step_with(env, -0.001), "terrain.Imprint[1].offset"));
  EXPECT_TRUE(mentions(step_with(env, kInf), "offset"));
  EXPECT_TRUE(mentions(step_with(env, kNaN), "offset"));
  env.lower.pop_back();
  EXPECT_TRUE(mentions(step_with(env, 0.0), "lower.size()"));
  const Imprint null_envelope{};
  EXPECT_TRUE(mentions(message_of<shore::InvalidSetting>([&] { t.step({&null_envelope, 1}); }), "envelope"));
  env = sphere_envelope(t, 0.0, 0.0, 0.05, 0.1);
  env.lower[3] = kNaN;
  EXPECT_TRUE(mentions(message_of<shore::InvalidSetting>([&] { (void)t.bearing(env); }), "lower[3]"));
  EXPECT_TRUE(mentions(message_of<shore::InvalidSetting>([&] { (void)t.bearing_offset(good, -1.0); }), "load"));
  EXPECT_TRUE(mentions(message_of<shore::InvalidSetting>([&] { t.set_height(0, 0, kNaN); }), "h = nan"));
  EXPECT_EQ(t.state_hash(), before);
  EXPECT_EQ(t.tile_count(), tiles);
  EXPECT_TRUE(t.take_changed().empty());
}

TEST(Files, SaveLoadRoundTripIsBitExactAndContinuesIdentically) {
  Terrain a = pressed_sand();
  const auto file = temp_file("roundtrip.state");
  a.save(file);
  EXPECT_FALSE(std::filesystem::exists(file.string() + ".tmp"));
  Terrain b = Terrain::load(file);
  EXPECT_EQ(b.state_hash(), a.state_hash());
  EXPECT_EQ(b.tile_count(), a.tile_count());
  EXPECT_EQ(b.volume().compacted, a.volume().compacted);
  EXPECT_EQ(b.settings().material.name, "sand");
  // Both continue the same way.
  for (Terrain* t : {&a, &b}) {
    const shore::EnvelopeRaster env = sphere_envelope(*t, 0.05, 0.0, 0.07, 0.1);
    const Imprint im{&env};
    t->step({&im, 1});
  }
  EXPECT_EQ(b.state_hash(), a.state_hash());
  std::filesystem::remove(file);
}

namespace {

// Byte positions of a saved state of pressed_sand (layout at the top of terrain_io.cpp).
constexpr std::size_t kReachAt = 76;  // f64 active_reach, after parallel_min_columns (version 2 on)
constexpr std::size_t kSprayBytes = 8 * 8 + 1 + 4 + 8 + 6 * 8;       // spray settings (version 4 on)
constexpr std::size_t kUnloadBytes = 8;                              // unload_modulus (version 5 on)
constexpr std::size_t kQuietSprayState = 8 + 8 + 6 * 8 + 8 + 8 + 8;  // spray state of a soil that never sprayed

/// The state's bytes rewritten as version 3: without the precision field (4 bytes after
/// the byte-order mark), idle_tile_steps (i32 after active_reach), the spray settings and
/// the unloading modulus (after the material's shear fields) and the spray state (after the eroding regions).
void strip_spray(std::vector<unsigned char>& bytes) {
  std::uint32_t real_bytes = 0;
  std::memcpy(&real_bytes, bytes.data() + 16, sizeof real_bytes);
  ASSERT_EQ(real_bytes, 8u);
  bytes.erase(bytes.begin() + 16, bytes.begin() + 20);
  bytes.erase(bytes.begin() + kReachAt + 8, bytes.begin() + kReachAt + 12);
  const std::size_t spray_at = kReachAt + 8 + 4 + 4 + 10 * 8 + 1 + 6 * 8;
  bytes.erase(bytes.begin() + spray_at, bytes.begin() + spray_at + kSprayBytes + kUnloadBytes);
  const std::size_t regions_at = spray_at + 2 * 8;
  std::uint64_t regions = 0;
  std::memcpy(&regions, bytes.data() + regions_at, sizeof regions);
  ASSERT_LT(regions, 100U);
  const std::size_t state_at = regions_at + 8 + 24 * regions;
  std::int64_t step = -1;
  std::memcpy(&step, bytes.data() + state_at, sizeof step);
  ASSERT_EQ(step, 0) << "a soil that never sprayed";
  bytes.erase(bytes.begin() + state_at, bytes.begin() + state_at + kQuietSprayState);
  bytes[8] = 3;  // version, little-endian u32
}

}  // namespace

TEST(Files, VersionThreeStatesLoadWithSprayOff) {
  Terrain a = pressed_sand();
  const auto file = temp_file("v3.state");
  a.save(file);
  std::vector<unsigned char> bytes = read_bytes(file);
  strip_spray(bytes);
  reseal(bytes);
  write_bytes(file, bytes);
  const Terrain b = Terrain::load(file);
  EXPECT_EQ(b.state_hash(), a.state_hash());
  // Stepped without spray, they carry on without it.
  EXPECT_FALSE(b.settings().spray.enabled);
  EXPECT_TRUE(a.settings().spray.enabled);
  EXPECT_EQ(b.settings().material.spray.adhesion, Material{}.spray.adhesion);
  EXPECT_EQ(b.settings().active_reach, a.settings().active_reach);
  std::filesystem::remove(file);
}

TEST(Files, VersionOneStatesLoadWithAnInfiniteReach) {
  // A version 4 file made into a version 1 file: version 1 had none of version 4's fields,
  // no active_reach (8 bytes after parallel_min_columns, at byte 76).
  Terrain a = pressed_sand(0.25);
  const auto file = temp_file("v2.state");
  a.save(file);
  std::vector<unsigned char> bytes = read_bytes(file);
  strip_spray(bytes);  // nor version 4's fields
  double stored = 0.0;
  std::memcpy(&stored, bytes.data() + kReachAt, sizeof stored);
  ASSERT_EQ(stored, 0.25);
  bytes.erase(bytes.begin() + kReachAt, bytes.begin() + kReachAt + 8);
  // Nor the material's shear fields (6 f64 after its rigid flag, version 3 on).
  const std::size_t material_end = kReachAt + 4 + 4 + 10 * 8 + 1;
  bytes.erase(bytes.begin() + material_end, bytes.begin() + material_end + 6 * 8);
  // Nor a list of regions still eroding: after the volume bookkeeping, a u64 count and 24
  // bytes per region.
  const std::size_t regions_at = material_end + 2 * 8;
  std::uint64_t regions = 0;
  std::memcpy(&regions, bytes.data() + regions_at, sizeof regions);
  ASSERT_LT(regions, 100U);
  const auto first = bytes.begin() + static_cast<std::ptrdiff_t>(regions_at);
  bytes.erase(first, first + static_cast<std::ptrdiff_t>(8 + 24 * regions));
  bytes[8] = 1;  // version, little-endian u32
  reseal(bytes);
  write_bytes(file, bytes);
  const Terrain b = Terrain::load(file);
  EXPECT_EQ(b.state_hash(), a.state_hash());
  // Version 1 states were stepped with every covered column under the body.
  EXPECT_EQ(b.settings().active_reach, std::numeric_limits<double>::infinity());
  EXPECT_EQ(b.settings().parallel_min_columns, a.settings().parallel_min_columns);
  EXPECT_EQ(b.settings().idle_tile_steps, TerrainSettings{}.idle_tile_steps);
  EXPECT_EQ(b.settings().material.name, "sand");
  EXPECT_FALSE(b.settings().spray.enabled);
  std::filesystem::remove(file);
}

TEST(Files, CorruptStatesAreRefusedByName) {
  const Terrain a = pressed_sand();
  const auto file = temp_file("good.state");
  a.save(file);
  const std::vector<unsigned char> good = read_bytes(file);
  const auto bad = temp_file("bad.state");
  auto load_error = [&](const std::vector<unsigned char>& bytes) {
    write_bytes(bad, bytes);
    return message_of<shore::FileError>([&] { (void)Terrain::load(bad); });
  };
  EXPECT_TRUE(mentions(load_error({}), "magic"));
  EXPECT_TRUE(mentions(load_error({'P', 'K', 3, 4, 0, 0, 0, 0, 0, 0}), "not a Shore terrain state"));
  std::vector<unsigned char> cut(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(good.size() / 2));
  EXPECT_TRUE(mentions(load_error(cut), "checksum")) << load_error(cut);
  cut.assign(good.begin(), good.begin() + 14);
  EXPECT_TRUE(mentions(load_error(cut), "truncated"));
  std::vector<unsigned char> flipped = good;
  flipped[good.size() / 3] ^= 0x10;
  EXPECT_TRUE(mentions(load_error(flipped), "checksum"));
  std::vector<unsigned char> version = good;
  version[8] = 99;
  EXPECT_TRUE(mentions(load_error(version), "version"));
  EXPECT_TRUE(
      mentions(message_of<shore::FileError>([&] { (void)Terrain::load(temp_file("missing.state")); }), "cannot open"));
  std::filesystem::remove(file);
  std::filesystem::remove(bad);
}

TEST(Files, Png8And16BitAndRawFloatHeightmaps) {
  const HeightmapPlacement place{10.0, 20.0, 0.5, 2.0, -1.0};  // x0, y0, spacing, scale, offset
  // 8-bit, written by stb_image_write: 3 x 2 grey.
  const unsigned char px8[6] = {0, 51, 102, 153, 204, 255};
  const auto f8 = temp_file("h8.png");
  ASSERT_TRUE(stbi_write_png(f8.string().c_str(), 3, 2, 1, px8, 3));
  const Heightmap h8 = Heightmap::from_png(f8, place);
  ASSERT_EQ(h8.width(), 3);
  ASSERT_EQ(h8.rows(), 2);
  // Sample (c, r) at (x0 + c s, y0 + (rows - 1 - r) s): the top row is the far (high y) one.
  EXPECT_NEAR(h8.height(10.0, 20.5), -1.0 + 2.0 * 0 / 255.0, 1e-6);
  EXPECT_NEAR(h8.height(11.0, 20.5), -1.0 + 2.0 * 102 / 255.0, 1e-6);
  EXPECT_NEAR(h8.height(10.5, 20.0), -1.0 + 2.0 * 204 / 255.0, 1e-6);
  EXPECT_NEAR(h8.height(10.25, 20.0), -1.0 + 2.0 * (153 + 204) / 2 / 255.0, 1e-6);  // bilinear
  EXPECT_NEAR(h8.height(-5.0, 100.0), -1.0, 1e-6);                                  // edge extends outward
  // 16-bit, hand-encoded.
  const std::vector<std::uint16_t> px16 = {0, 1000, 65535, 30000};
  const auto f16 = temp_file("h16.png");
  write_bytes(f16, png16(2, 2, px16));
  const Heightmap h16 = Heightmap::from_png(f16, place);
  EXPECT_NEAR(h16.height(10.5, 20.5), -1.0 + 2.0 * 1000 / 65535.0, 1e-6);
  EXPECT_NEAR(h16.height(10.0, 20.0), -1.0 + 2.0 * 65535 / 65535.0, 1e-6);
  EXPECT_NEAR(h16.height(10.5, 20.0), -1.0 + 2.0 * 30000 / 65535.0, 1e-6);
  // Raw float32.
  const std::vector<float> raw = {0.5f, -0.25f, 3.0f, 1.5f, 2.0f, 0.0f};
  const auto fr = temp_file("h.raw");
  write_bytes(fr, std::vector<unsigned char>(reinterpret_cast<const unsigned char*>(raw.data()),
                                             reinterpret_cast<const unsigned char*>(raw.data() + raw.size())));
  const Heightmap hr = Heightmap::from_raw_float32(fr, 3, 2, place);
  EXPECT_NEAR(hr.height(10.5, 20.5), -1.0 + 2.0 * -0.25, 1e-6);
  EXPECT_NEAR(hr.height(11.0, 20.0), -1.0 + 2.0 * 0.0, 1e-6);
  // As a terrain's base.
  TerrainSettings s;
  s.cell = 0.5, s.origin_x = 10.0, s.origin_y = 20.0;
  s.base = std::make_shared<Heightmap>(hr);
  Terrain t(s);
  EXPECT_NEAR(t.height(1, 1), -1.0 + 2.0 * -0.25, 1e-6);
  EXPECT_EQ(t.tile_count(), 0u);

  // Bad files.
  auto png_error = [&](const std::vector<unsigned char>& bytes) {
    const auto f = temp_file("bad.png");
    write_bytes(f, bytes);
    return message_of<shore::FileError>([&] { (void)Heightmap::from_png(f, place); });
  };
  EXPECT_TRUE(mentions(png_error({'G', 'I', 'F', '8'}), "not a PNG"));
  std::vector<unsigned char> png = png16(2, 2, px16);
  png.resize(png.size() - 30);
  EXPECT_TRUE(mentions(png_error(png), "heightmap PNG")) << png_error(png);
  EXPECT_TRUE(mentions(message_of<shore::FileError>([&] { (void)Heightmap::from_raw_float32(fr, 4, 2, place); }),
                       "expected 32"));
  // A fixed-size copy: GCC's -Wnull-dereference cannot prove a copied vector non-empty.
  std::array<float, 6> nan_raw{};
  std::copy_n(raw.begin(), nan_raw.size(), nan_raw.begin());
  nan_raw[4] = std::numeric_limits<float>::quiet_NaN();
  write_bytes(fr, std::vector<unsigned char>(reinterpret_cast<const unsigned char*>(nan_raw.data()),
                                             reinterpret_cast<const unsigned char*>(nan_raw.data() + nan_raw.size())));
  EXPECT_TRUE(
      mentions(message_of<shore::FileError>([&] { (void)Heightmap::from_raw_float32(fr, 3, 2, place); }), "sample 4"));
  HeightmapPlacement bad_place = place;
  bad_place.spacing = 0.0;
  EXPECT_TRUE(mentions(
      message_of<shore::InvalidSetting>([&] { (void)Heightmap::from_raw_float32(fr, 3, 2, bad_place); }), "spacing"));
  for (const auto& f : {f8, f16, fr}) std::filesystem::remove(f);
}

TEST(HeightSources, LatticeNoiseInterpolatesItsLatticeReproducibly) {
  LatticeNoiseSettings ns;
  ns.seed = 42, ns.spacing = 0.5, ns.amplitude = 0.1, ns.mean = 1.0;
  const LatticeNoise a(ns), b(ns);
  ns.seed = 43;
  const LatticeNoise c(ns);
  double differ = 0.0, lo = kInf, hi = -kInf;
  for (int k = 0; k < 400; ++k) {
    const double x = -3.1 + 0.037 * k, y = 2.3 - 0.021 * k;
    EXPECT_EQ(a.height(x, y), b.height(x, y));
    differ = std::max(differ, std::abs(a.height(x, y) - c.height(x, y)));
    lo = std::min(lo, a.height(x, y)), hi = std::max(hi, a.height(x, y));
  }
  EXPECT_GT(differ, 0.01);
  // Catmull-Rom passes through the lattice values; bicubic overshoot is at most 1.25^2.
  for (int li = -3; li <= 3; ++li)
    for (int lj = -3; lj <= 3; ++lj)
      EXPECT_NEAR(a.height(0.5 * li, 0.5 * lj), 1.0 + 0.1 * a.lattice_value(0, li, lj), 1e-12);
  EXPECT_GE(lo, 1.0 - 0.1 * 1.5625);
  EXPECT_LE(hi, 1.0 + 0.1 * 1.5625);
  // Continuous across lattice lines.
  EXPECT_NEAR(a.height(0.5 - 1e-9, 0.3), a.height(0.5 + 1e-9, 0.3), 1e-7);
  LatticeNoiseSettings bad;
  bad.octaves = 0;
  EXPECT_TRUE(mentions(message_of<shore::InvalidSetting>([&] { LatticeNoise n(bad); }), "octaves"));
  EXPECT_TRUE(mentions(message_of<shore::InvalidSetting>([&] { FlatHeight f(kNaN); }), "level"));
}

namespace {

// The noise's definition written out from its public lattice values: Catmull-Rom along x
// through the four lattice points of each of four rows, then along y, octave by octave.
double noise_by_definition(const LatticeNoise& n, double x, double y) {
  const auto spline = [](double p0, double p1, double p2, double p3, double t) {
    return 0.5 * (2.0 * p1 + (p2 - p0) * t + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t * t +
                  (3.0 * (p1 - p2) + p3 - p0) * t * t * t);
  };
  const LatticeNoiseSettings& s = n.settings();
  double sum = s.mean, amp = s.amplitude, spacing = s.spacing;
  for (int k = 0; k < s.octaves; ++k) {
    const double u = x / spacing, v = y / spacing;
    const auto li = static_cast<std::int64_t>(std::floor(u)), lj = static_cast<std::int64_t>(std::floor(v));
    const double tu = u - std::floor(u), tv = v - std::floor(v);
    double row[4];
    for (int b = 0; b < 4; ++b)
      row[b] = spline(n.lattice_value(k, li - 1, lj - 1 + b), n.lattice_value(k, li, lj - 1 + b),
                      n.lattice_value(k, li + 1, lj - 1 + b), n.lattice_value(k, li + 2, lj - 1 + b), tu);
    sum += amp * spline(row[0], row[1], row[2], row[3], tv);
    amp *= s.persistence;
    spacing *= 0.5;
  }
  return sum;
}

}  // namespace

namespace {
/// The rally valley's noise settings (3 octaves, amplitude 0.35 m, persistence 0.45) with
/// a seed and a lattice spacing (m) of the test's choosing.
LatticeNoiseSettings rally_like_noise(std::uint64_t seed, double spacing) {
  LatticeNoiseSettings ns;
  ns.seed = seed, ns.spacing = spacing, ns.amplitude = 0.35, ns.octaves = 3, ns.persistence = 0.45;
  return ns;
}
}  // namespace

TEST(HeightSources, LatticeNoiseIsItsDefinitionBitForBit) {
  // height() keeps the lattice values of the last cell asked per octave and thread: points
  // in the same cell, in neighbouring cells, far apart and from two noises taking turns
  // (same octaves, other seeds) must all give the definition's bits.
  const LatticeNoise a(rally_like_noise(7, 5.0)), b(rally_like_noise(8, 2.0));
  for (int k = 0; k < 3000; ++k) {
    const double x = -40.0 + 0.0137 * k * (k % 3 == 0 ? 1.0 : 2.9), y = 25.0 - 0.0191 * k * (k % 7 == 0 ? -3.0 : 1.0);
    ASSERT_EQ(a.height(x, y), noise_by_definition(a, x, y)) << x << ", " << y;
    ASSERT_EQ(a.height(x, y), noise_by_definition(a, x, y)) << "asked again at " << x << ", " << y;
    if (k % 5 == 0) {
      ASSERT_EQ(b.height(x, y), noise_by_definition(b, x, y)) << x << ", " << y;
    }
  }
  std::thread other([&] {  // another thread keeps its own lattice cells
    for (int k = 0; k < 200; ++k) EXPECT_EQ(b.height(0.3 * k, -0.7 * k), noise_by_definition(b, 0.3 * k, -0.7 * k));
  });
  other.join();
}

TEST(HeightSources, LatticeNoiseAlongYIsItsDefinitionBitForBit) {
  // Columns of points sharing x (a grid's column: 4 cm apart over several lattice cells of
  // each octave, then points in no order, crossing cells back and forth), with another
  // noise asked in between: every answer the definition's bits.
  const LatticeNoise a(rally_like_noise(7, 5.0)), b(rally_like_noise(8, 2.0));
  std::vector<double> ys(400), out(400);
  for (int c = 0; c < 40; ++c) {
    const double x = -12.0 + 0.04 * (37 * c);
    for (std::size_t k = 0; k < ys.size(); ++k)
      ys[k] = c % 2 == 0 ? -16.0 + 0.04 * static_cast<double>(k) : 9.0 * std::sin(0.7 * static_cast<double>(k) + c);
    a.heights_along_y(x, ys, out);
    for (std::size_t k = 0; k < ys.size(); ++k)
      ASSERT_EQ(out[k], noise_by_definition(a, x, ys[k])) << x << ", " << ys[k];
    (void)b.height(x + 3.3, 1.7);  // another noise's cells in the per-thread keep
  }
  std::vector<double> short_out(3);
  EXPECT_TRUE(
      mentions(message_of<shore::InvalidSetting>([&] { a.heights_along_y(0.0, ys, short_out); }), "out.size()"));
}

TEST(HeightSources, ARowIsItsPointsGridPositions) {
  // HeightSource::row: the grid's points at origin + (i0 + c) cell, as a terrain places its
  // columns, each the definition's bits.
  LatticeNoiseSettings ns;
  ns.seed = 7, ns.spacing = 5.0, ns.amplitude = 0.35, ns.octaves = 3, ns.persistence = 0.45;
  const LatticeNoise a(ns);
  std::vector<double> out(150);
  const double origin_x = -0.02, cell = 0.04, y = -3.0 + 17.0 * 0.04;
  a.row(origin_x, cell, -75, y, out);
  for (std::size_t c = 0; c < out.size(); ++c) {
    const double x = origin_x + static_cast<double>(-75 + static_cast<std::int64_t>(c)) * cell;
    ASSERT_EQ(out[c], noise_by_definition(a, x, y)) << x;
  }
}
