#include "shore/terrain/height_source.h"

#include <stb_image.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <string>

#include "png_checks.h"
#include "shore/core/error.h"
#include "shore/core/file_bytes.h"

namespace shore::terrain {

void HeightSource::row(double origin_x, double cell, std::int64_t i0, double y, std::span<double> out) const {
  for (std::size_t c = 0; c < out.size(); ++c)
    out[c] = height(origin_x + static_cast<double>(i0 + static_cast<std::int64_t>(c)) * cell, y);
}

// ---- flat ----------------------------------------------------------------------------

FlatHeight::FlatHeight(double level) : level_(level) { Check{"terrain.FlatHeight"}.finite("level", level); }

double FlatHeight::height(double, double) const { return level_; }

PlaneHeight::PlaneHeight(double level, double slope_x, double slope_y)
    : level_(level), slope_x_(slope_x), slope_y_(slope_y) {
  const Check c{"terrain.PlaneHeight"};
  c.finite("level", level);
  c.finite("slope_x", slope_x);
  c.finite("slope_y", slope_y);
}

double PlaneHeight::height(double x, double y) const { return level_ + slope_x_ * x + slope_y_ * y; }

// ---- lattice noise -------------------------------------------------------------------

void LatticeNoiseSettings::validate() const {
  const Check c{"terrain.LatticeNoiseSettings"};
  c.positive("spacing", spacing);
  c.non_negative("amplitude", amplitude);
  c.finite("mean", mean);
  if (!(octaves >= 1 && octaves <= 16))
    throw InvalidSetting(c.name("octaves"), detail::to_text(octaves), "must be in [1, 16]");
  c.in_left_open("persistence", persistence, 0.0, 1.0);
}

namespace {

// SplitMix64 finaliser: a well-mixed 64-bit hash of one word.
std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

constexpr std::uint64_t kSeedSalt = 0x9e3779b97f4a7c15ull;

/// 53 random bits of a hash to [0, 1), then to [-1, 1).
double unit(std::uint64_t h) { return static_cast<double>(h >> 11) * 0x1.0p-52 - 1.0; }

// Catmull-Rom spline through p1 (t = 0) and p2 (t = 1); inline: 15 a noise call.
[[gnu::always_inline]] inline double catmull_rom(double p0, double p1, double p2, double p3, double t) {
  return 0.5 * (2.0 * p1 + (p2 - p0) * t + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t * t +
                (3.0 * (p1 - p2) + p3 - p0) * t * t * t);
}

/// The 4 x 4 lattice values around one lattice cell of one octave, kept per thread and
/// octave: neighbouring points (a tile's columns, a flight's samples, a block's columns)
/// mostly fall in the same lattice cell. A lattice value depends only on (seed, octave, li,
/// lj), so a patch kept under those is exact for every LatticeNoise that asks it.
struct LatticePatch {
  bool filled = false;
  std::uint64_t seed = 0;
  std::int64_t li = 0, lj = 0;
  double value[16] = {};  ///< [4 * b + a]: lattice point (li - 1 + a, lj - 1 + b)
};

/// Patches kept per octave, by lattice row (lj mod kRowsKept): a column of points crosses a
/// few lattice rows, and the next column (mostly the same lattice column) crosses them again.
constexpr std::size_t kRowsKept = 4;
thread_local std::array<LatticePatch, 16 * kRowsKept> t_patches;  // [octave * kRowsKept + lj mod kRowsKept]

/// floor(v), bit for bit (a -0 stays -0), without the library call where |v| < 2^52.
double exact_floor(double v) {
  if (!(std::abs(v) < 0x1.0p52)) return std::floor(v);
  const auto t = static_cast<double>(static_cast<std::int64_t>(v));  // v truncated: exact here
  return t > v ? t - 1.0 : (t < v ? t : v);
}

}  // namespace

LatticeNoise::LatticeNoise(LatticeNoiseSettings settings) : settings_(settings) {
  settings_.validate();
  const std::uint64_t seeded = mix64(settings_.seed ^ kSeedSalt);
  for (int k = 0; k < settings_.octaves; ++k)
    octave_hash_[static_cast<std::size_t>(k)] = mix64(seeded ^ static_cast<std::uint64_t>(k));
}

double LatticeNoise::lattice_value(int octave, std::int64_t li, std::int64_t lj) const {
  std::uint64_t h = mix64(settings_.seed ^ kSeedSalt);
  h = mix64(h ^ static_cast<std::uint64_t>(octave));
  h = mix64(h ^ static_cast<std::uint64_t>(li));
  h = mix64(h ^ static_cast<std::uint64_t>(lj));
  return unit(h);
}

const double* LatticeNoise::patch(int octave, std::int64_t li, std::int64_t lj) const {
  LatticePatch& p =
      t_patches[static_cast<std::size_t>(octave) * kRowsKept + (static_cast<std::uint64_t>(lj) & (kRowsKept - 1))];
  if (p.filled && p.seed == settings_.seed && p.li == li && p.lj == lj) return p.value;
  // lattice_value's chain of four mixes with its first two (seed, octave) done once, and
  // the third (li) shared by the patch's four rows: 20 mixes a patch instead of 64.
  const std::uint64_t h = octave_hash_[static_cast<std::size_t>(octave)];
  std::uint64_t column[4];
  for (int a = 0; a < 4; ++a) column[a] = mix64(h ^ static_cast<std::uint64_t>(li - 1 + a));
  for (int b = 0; b < 4; ++b) {
    const auto j = static_cast<std::uint64_t>(lj - 1 + b);
    for (int a = 0; a < 4; ++a) p.value[4 * b + a] = unit(mix64(column[a] ^ j));
  }
  p.filled = true, p.seed = settings_.seed, p.li = li, p.lj = lj;
  return p.value;
}

double LatticeNoise::height(double x, double y) const {
  double sum = settings_.mean;
  double amp = settings_.amplitude;
  double spacing = settings_.spacing;
  for (int k = 0; k < settings_.octaves; ++k) {
    const double u = x / spacing, v = y / spacing;
    const double fu = exact_floor(u), fv = exact_floor(v);
    const auto li = static_cast<std::int64_t>(fu), lj = static_cast<std::int64_t>(fv);
    const double tu = u - fu, tv = v - fv;
    const double* w = patch(k, li, lj);
    double row[4];
    for (int b = 0; b < 4; ++b) row[b] = catmull_rom(w[4 * b], w[4 * b + 1], w[4 * b + 2], w[4 * b + 3], tu);
    sum += amp * catmull_rom(row[0], row[1], row[2], row[3], tv);
    amp *= settings_.persistence;
    spacing *= 0.5;
  }
  return sum;
}

void LatticeNoise::heights_along_y(double x, std::span<const double> ys, std::span<double> out) const {
  if (out.size() != ys.size())
    throw InvalidSetting("terrain.LatticeNoise.heights_along_y.out.size()", detail::to_text(out.size()),
                         "must equal ys.size() = " + detail::to_text(ys.size()));
  std::fill(out.begin(), out.end(), settings_.mean);
  double amp = settings_.amplitude;
  double spacing = settings_.spacing;
  for (int k = 0; k < settings_.octaves; ++k) {
    const double u = x / spacing, fu = exact_floor(u);
    const auto li = static_cast<std::int64_t>(fu);
    const double tu = u - fu;
    double row[4] = {};
    std::int64_t row_lj = 0;
    bool have_rows = false;
    for (std::size_t p = 0; p < ys.size(); ++p) {
      const double v = ys[p] / spacing, fv = exact_floor(v);
      const auto lj = static_cast<std::int64_t>(fv);
      if (!have_rows || lj != row_lj) {  // height()'s four splines along x, for this lattice cell
        const double* w = patch(k, li, lj);
        for (int b = 0; b < 4; ++b) row[b] = catmull_rom(w[4 * b], w[4 * b + 1], w[4 * b + 2], w[4 * b + 3], tu);
        row_lj = lj, have_rows = true;
      }
      out[p] += amp * catmull_rom(row[0], row[1], row[2], row[3], v - fv);
    }
    amp *= settings_.persistence;
    spacing *= 0.5;
  }
}

// ---- heightmap -----------------------------------------------------------------------

void HeightmapPlacement::validate() const {
  const Check c{"terrain.HeightmapPlacement"};
  c.finite("x0", x0);
  c.finite("y0", y0);
  c.positive("spacing", spacing);
  c.finite("vertical_scale", vertical_scale);
  c.finite("vertical_offset", vertical_offset);
}

Heightmap::Heightmap(int width, int rows, std::vector<float> values, HeightmapPlacement placement)
    : width_(width), rows_(rows), values_(std::move(values)), placement_(placement) {
  const Check c{"terrain.Heightmap"};
  placement_.validate();
  if (width < 1) throw InvalidSetting(c.name("width"), detail::to_text(width), "must be >= 1");
  if (rows < 1) throw InvalidSetting(c.name("rows"), detail::to_text(rows), "must be >= 1");
  const auto expected = static_cast<std::size_t>(width) * static_cast<std::size_t>(rows);
  if (values_.size() != expected)
    throw InvalidSetting(c.name("values.size()"), detail::to_text(values_.size()),
                         "must equal width * rows = " + detail::to_text(expected));
  for (std::size_t k = 0; k < values_.size(); ++k)
    if (!std::isfinite(values_[k]))
      throw InvalidSetting(c.name("values") + "[" + std::to_string(k) + "]", detail::to_text(values_[k]),
                           "must be finite");
}

namespace {

struct StbFree {
  void operator()(void* p) const { stbi_image_free(p); }
};

}  // namespace

Heightmap Heightmap::from_png(const std::filesystem::path& file, HeightmapPlacement placement) {
  placement.validate();
  return from_png_bytes(read_file_bytes(file, "heightmap PNG"), file.string(), placement);
}

Heightmap Heightmap::from_png_bytes(std::span<const unsigned char> bytes, const std::string& name,
                                    HeightmapPlacement placement) {
  placement.validate();
  const std::string where = "heightmap PNG " + name + ": ";
  const CheckedPng png = checked_png(bytes, where, kMaxHeightmapSamples, "samples a heightmap may hold");
  const int len = static_cast<int>(png.bytes.size());
  int w = png.width, h = png.height, channels = png.channels;
  const std::size_t samples = png.pixels;
  const bool sixteen = stbi_is_16_bit_from_memory(png.bytes.data(), len) != 0;
  std::vector<float> values;
  if (sixteen) {
    std::unique_ptr<stbi_us, StbFree> pixels(stbi_load_16_from_memory(png.bytes.data(), len, &w, &h, &channels, 1));
    if (!pixels) throw FileError(where + "cannot decode 16-bit image (" + stbi_failure_reason() + ")");
    values.resize(samples);
    for (std::size_t k = 0; k < values.size(); ++k) values[k] = static_cast<float>(pixels.get()[k] / 65535.0);
  } else {
    std::unique_ptr<stbi_uc, StbFree> pixels(stbi_load_from_memory(png.bytes.data(), len, &w, &h, &channels, 1));
    if (!pixels) throw FileError(where + "cannot decode 8-bit image (" + stbi_failure_reason() + ")");
    values.resize(samples);
    for (std::size_t k = 0; k < values.size(); ++k) values[k] = static_cast<float>(pixels.get()[k] / 255.0);
  }
  return Heightmap(w, h, std::move(values), placement);
}

Heightmap Heightmap::from_raw_float32(const std::filesystem::path& file, int width, int rows,
                                      HeightmapPlacement placement) {
  placement.validate();
  if (width < 1 || rows < 1)  // before reading: the message names the sizes, whatever the file
    return from_raw_float32_bytes({}, file.string(), width, rows, placement);
  return from_raw_float32_bytes(read_file_bytes(file, "heightmap raw float32"), file.string(), width, rows, placement);
}

Heightmap Heightmap::from_raw_float32_bytes(std::span<const unsigned char> bytes, const std::string& name, int width,
                                            int rows, HeightmapPlacement placement) {
  placement.validate();
  const std::string where = "heightmap raw float32 " + name + ": ";
  if (width < 1 || rows < 1)
    throw FileError(where + "width and rows must be >= 1 (got " + std::to_string(width) + " x " + std::to_string(rows) +
                    ")");
  const auto count = static_cast<std::size_t>(width) * static_cast<std::size_t>(rows);
  if (count > kMaxHeightmapSamples)
    throw FileError(where + std::to_string(width) + " x " + std::to_string(rows) + " samples, more than the " +
                    std::to_string(kMaxHeightmapSamples) + " a heightmap may hold");
  if (bytes.size() != count * 4)
    throw FileError(where + "size is " + std::to_string(bytes.size()) + " bytes, expected " +
                    std::to_string(count * 4) + " (" + std::to_string(width) + " x " + std::to_string(rows) +
                    " float32 samples)");
  std::vector<float> values(count);
  for (std::size_t k = 0; k < count; ++k) {
    std::uint32_t word = 0;
    std::memcpy(&word, bytes.data() + 4 * k, 4);
    if constexpr (std::endian::native == std::endian::big) word = __builtin_bswap32(word);
    values[k] = std::bit_cast<float>(word);
    if (!std::isfinite(values[k]))
      throw FileError(where + "sample " + std::to_string(k) + " (column " + std::to_string(k % width) + ", row " +
                      std::to_string(k / width) + ") is not finite");
  }
  return Heightmap(width, rows, std::move(values), placement);
}

double Heightmap::height(double x, double y) const {
  // Continuous sample coordinates, row counted from the top.
  double u = (x - placement_.x0) / placement_.spacing;
  double v = static_cast<double>(rows_ - 1) - (y - placement_.y0) / placement_.spacing;
  if (std::isnan(u)) u = 0.0;  // never reached from the grid; keeps the casts below defined
  if (std::isnan(v)) v = 0.0;
  u = std::clamp(u, 0.0, static_cast<double>(width_ - 1));
  v = std::clamp(v, 0.0, static_cast<double>(rows_ - 1));
  const int c0 = std::min(static_cast<int>(u), std::max(width_ - 2, 0));
  const int r0 = std::min(static_cast<int>(v), std::max(rows_ - 2, 0));
  const int c1 = std::min(c0 + 1, width_ - 1), r1 = std::min(r0 + 1, rows_ - 1);
  const double tu = u - c0, tv = v - r0;
  const double top = (1.0 - tu) * sample(c0, r0) + tu * sample(c1, r0);
  const double bottom = (1.0 - tu) * sample(c0, r1) + tu * sample(c1, r1);
  return placement_.vertical_offset + placement_.vertical_scale * ((1.0 - tv) * top + tv * bottom);
}

}  // namespace shore::terrain
