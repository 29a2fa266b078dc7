#pragma once
// A material map as an image: one 8-bit palette index per pixel, painted onto a terrain's
// columns with Terrain::paint_image (the palette is the terrain's, set in code with
// Terrain::set_palette). Pixel (c, r) (r = 0 the image's top row) is the index of column
// (i0 + c, j0 + rows - 1 - r): seen from above with y pointing up, the map looks like the
// image, as heightmaps do (shore/terrain/height_source.h).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace shore::terrain {

/// Most pixels a material image may hold (16384 x 16384): larger headers are refused before
/// anything is allocated.
inline constexpr std::size_t kMaxMaterialImagePixels = std::size_t{1} << 28;

class MaterialImage {
 public:
  /// index: width * rows palette indices, row-major, row 0 the top row. `name` stands for
  /// the source in error messages. Throws InvalidSetting on sizes that do not match.
  MaterialImage(int width, int rows, std::vector<std::uint8_t> index, std::string name);

  /// An 8-bit greyscale PNG whose pixel values are the indices (a colour, grey+alpha or
  /// 16-bit PNG is refused: its values are not indices). Throws shore::FileError naming the
  /// file and the problem; chunks and sizes are checked as the heightmap loader checks them.
  static MaterialImage from_png(const std::filesystem::path& file);
  /// from_png() of bytes already in memory; `name` stands for the file in messages.
  static MaterialImage from_png_bytes(std::span<const unsigned char> bytes, const std::string& name);
  /// Headerless bytes, one index per pixel, row-major, row 0 the top row; the size must be
  /// exactly width * rows bytes, else shore::FileError.
  static MaterialImage from_raw(const std::filesystem::path& file, int width, int rows);
  /// from_raw() of bytes already in memory.
  static MaterialImage from_raw_bytes(std::span<const unsigned char> bytes, const std::string& name, int width,
                                      int rows);

  [[nodiscard]] int width() const noexcept { return width_; }
  [[nodiscard]] int rows() const noexcept { return rows_; }
  [[nodiscard]] const std::string& name() const noexcept { return name_; }
  /// Index at pixel (c, r).
  [[nodiscard]] std::uint8_t at(int c, int r) const { return index_[static_cast<std::size_t>(r) * width_ + c]; }

 private:
  int width_ = 0, rows_ = 0;
  std::vector<std::uint8_t> index_;
  std::string name_;
};

}  // namespace shore::terrain
