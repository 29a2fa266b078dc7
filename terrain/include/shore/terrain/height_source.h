#pragma once
// Where untouched ground lies: flat, lattice noise, or an imported heightmap.

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace shore::terrain {

/// Height (m) of the untouched ground at a world position. Must be deterministic and
/// thread-safe (const).
class HeightSource {
 public:
  virtual ~HeightSource() = default;
  [[nodiscard]] virtual double height(double x, double y) const = 0;
  /// Heights along a row of grid points: out[c] = height(origin_x + double(i0 + c) * cell, y),
  /// bit for bit. This asks height() point by point; a source that keeps its heights (a
  /// cache of a costly ground) answers a row at once.
  virtual void row(double origin_x, double cell, std::int64_t i0, double y, std::span<double> out) const;
};

/// Level ground.
class FlatHeight final : public HeightSource {
 public:
  explicit FlatHeight(double level);  ///< m, finite (throws InvalidSetting otherwise)
  [[nodiscard]] double height(double x, double y) const override;

 private:
  double level_;
};

/// A plane: level + slope_x x + slope_y y (slopes as rise over run, dimensionless).
class PlaneHeight final : public HeightSource {
 public:
  PlaneHeight(double level, double slope_x, double slope_y);  ///< all finite (throws InvalidSetting otherwise)
  [[nodiscard]] double height(double x, double y) const override;

 private:
  double level_, slope_x_, slope_y_;
};

/// Sumner et al.'s initial ground: random values on a square lattice, interpolated with
/// Catmull-Rom splines in x and y (a variant of 2-D Perlin noise). The lattice values come
/// from an integer hash of (seed, octave, lattice i, lattice j), so the same settings give
/// the same ground on every machine and thread. Octaves add finer lattices (spacing / 2^k)
/// with amplitude * persistence^k.
struct LatticeNoiseSettings {
  std::uint64_t seed = 1;    ///< any value
  double spacing = 0.5;      ///< m, lattice period of the first octave, finite and > 0
  double amplitude = 0.02;   ///< m, lattice values lie in [-amplitude, amplitude], finite and >= 0
  double mean = 0.0;         ///< m, height the noise varies around, finite
  int octaves = 1;           ///< in [1, 16]
  double persistence = 0.5;  ///< amplitude ratio between octaves, in (0, 1]

  /// Throws shore::InvalidSetting naming the field, the value and the allowed range.
  void validate() const;
};

class LatticeNoise final : public HeightSource {
 public:
  explicit LatticeNoise(LatticeNoiseSettings settings);  ///< validates
  [[nodiscard]] double height(double x, double y) const override;
  /// out[k] = height(x, ys[k]), bit for bit (the same arithmetic in the same order), for
  /// points sharing one x: each octave's four splines along x are worked out once per
  /// lattice cell the ys cross instead of once a point. out.size() must equal ys.size().
  void heights_along_y(double x, std::span<const double> ys, std::span<double> out) const;
  /// Value at lattice point (li, lj) of octave k, in [-1, 1] (before amplitude).
  [[nodiscard]] double lattice_value(int octave, std::int64_t li, std::int64_t lj) const;
  [[nodiscard]] const LatticeNoiseSettings& settings() const noexcept { return settings_; }

 private:
  /// The 16 lattice values around lattice cell (li, lj) of the octave (lattice_value's,
  /// bit for bit), [4 * b + a] for point (li - 1 + a, lj - 1 + b); kept per thread until
  /// another cell of that octave and lattice row (modulo 4) is asked.
  [[nodiscard]] const double* patch(int octave, std::int64_t li, std::int64_t lj) const;

  LatticeNoiseSettings settings_;
  std::array<std::uint64_t, 16> octave_hash_{};  ///< the hash chain after (seed, octave)
};

/// Where a heightmap lies and how its samples become heights.
/// Sample (c, r) (column c, row r, r = 0 the image's top row) stands at world
/// x = x0 + c spacing, y = y0 + (rows - 1 - r) spacing: seen from above with y pointing up,
/// the map looks like the image. (x0, y0) is the bottom-left sample.
/// height = vertical_offset + vertical_scale * v, with v = pixel / 255 or / 65535 for PNG
/// (so v in [0, 1]) and the stored value for raw float32.
struct HeightmapPlacement {
  double x0 = 0.0;               ///< m, finite
  double y0 = 0.0;               ///< m, finite
  double spacing = 1.0;          ///< m between samples, finite and > 0
  double vertical_scale = 1.0;   ///< m per unit sample value, finite
  double vertical_offset = 0.0;  ///< m, finite

  /// Throws shore::InvalidSetting naming the field, the value and the allowed range.
  void validate() const;
};

/// Most samples a heightmap file may hold (16384 x 16384): larger headers are refused
/// before anything is allocated.
inline constexpr std::size_t kMaxHeightmapSamples = std::size_t{1} << 28;

/// Imported ground, bilinearly interpolated between samples; outside the map the edge
/// samples extend outward. The file loaders are fuzzed (fuzz/README.md): whatever the
/// bytes, they give a heightmap or a shore::FileError, never a crash.
class Heightmap final : public HeightSource {
 public:
  /// values: width * rows samples, row-major, row 0 the top row. Throws InvalidSetting on
  /// sizes that do not match or non-finite values.
  Heightmap(int width, int rows, std::vector<float> values, HeightmapPlacement placement);

  /// 8- or 16-bit PNG (grey, grey+alpha, RGB or RGBA; colour is converted to grey by
  /// luminance, alpha ignored). Throws shore::FileError naming the file and the problem.
  /// Every chunk must lie inside the file and match its CRC; headers claiming more than
  /// kMaxHeightmapSamples pixels, or more pixels than the file's size can hold compressed,
  /// are refused as corrupt.
  static Heightmap from_png(const std::filesystem::path& file, HeightmapPlacement placement);
  /// from_png() of bytes already in memory; `name` stands for the file in error messages.
  static Heightmap from_png_bytes(std::span<const unsigned char> bytes, const std::string& name,
                                  HeightmapPlacement placement);
  /// Headerless little-endian float32 samples, row-major, row 0 the top row. The file size
  /// must be exactly width * rows * 4 bytes and every sample finite, else shore::FileError.
  static Heightmap from_raw_float32(const std::filesystem::path& file, int width, int rows,
                                    HeightmapPlacement placement);
  /// from_raw_float32() of bytes already in memory; `name` stands for the file in messages.
  static Heightmap from_raw_float32_bytes(std::span<const unsigned char> bytes, const std::string& name, int width,
                                          int rows, HeightmapPlacement placement);

  [[nodiscard]] double height(double x, double y) const override;
  [[nodiscard]] int width() const noexcept { return width_; }
  [[nodiscard]] int rows() const noexcept { return rows_; }
  /// Stored sample (c, r), before the vertical scale and offset.
  [[nodiscard]] float sample(int c, int r) const { return values_[static_cast<std::size_t>(r) * width_ + c]; }
  [[nodiscard]] const HeightmapPlacement& placement() const noexcept { return placement_; }

 private:
  int width_ = 0;
  int rows_ = 0;
  std::vector<float> values_;
  HeightmapPlacement placement_;
};

}  // namespace shore::terrain
