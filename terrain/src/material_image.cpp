// Material images (shore/terrain/material_image.h): 8-bit greyscale PNG or raw bytes of
// palette indices.

#include "shore/terrain/material_image.h"

#include <stb_image.h>

#include <cstring>
#include <limits>
#include <memory>
#include <utility>

#include "png_checks.h"
#include "shore/core/error.h"
#include "shore/core/file_bytes.h"

namespace shore::terrain {

namespace {
struct StbFree {
  void operator()(void* p) const { stbi_image_free(p); }
};
}  // namespace

MaterialImage::MaterialImage(int width, int rows, std::vector<std::uint8_t> index, std::string name)
    : width_(width), rows_(rows), index_(std::move(index)), name_(std::move(name)) {
  const Check c{"terrain.MaterialImage(" + name_ + ")"};
  if (width < 1) throw InvalidSetting(c.name("width"), detail::to_text(width), "must be >= 1");
  if (rows < 1) throw InvalidSetting(c.name("rows"), detail::to_text(rows), "must be >= 1");
  const auto expected = static_cast<std::size_t>(width) * static_cast<std::size_t>(rows);
  if (expected > kMaxMaterialImagePixels)
    throw InvalidSetting(c.name("width * rows"), detail::to_text(expected),
                         "must be at most " + detail::to_text(kMaxMaterialImagePixels));
  if (index_.size() != expected)
    throw InvalidSetting(c.name("index.size()"), detail::to_text(index_.size()),
                         "must equal width * rows = " + detail::to_text(expected));
}

MaterialImage MaterialImage::from_png(const std::filesystem::path& file) {
  return from_png_bytes(read_file_bytes(file, "material image PNG"), file.string());
}

MaterialImage MaterialImage::from_png_bytes(std::span<const unsigned char> bytes, const std::string& name) {
  const std::string where = "material image PNG " + name + ": ";
  const CheckedPng png = checked_png(bytes, where, kMaxMaterialImagePixels, "a material image may hold");
  const int len = static_cast<int>(png.bytes.size());
  int w = png.width, h = png.height, channels = png.channels;
  const std::size_t pixels = png.pixels;
  // Indices are the stored values: anything converted on decoding (colour to grey, 16 bits
  // to 8) would paint other materials than the file says.
  if (stbi_is_16_bit_from_memory(png.bytes.data(), len))
    throw FileError(where + "16-bit image; a material image is 8-bit greyscale (pixel value = palette index)");
  if (channels != 1)
    throw FileError(where + std::to_string(channels) +
                    " channels (colour, indexed colour or alpha); a material image is 8-bit greyscale (pixel "
                    "value = palette index)");
  std::unique_ptr<stbi_uc, StbFree> decoded(stbi_load_from_memory(png.bytes.data(), len, &w, &h, &channels, 1));
  if (!decoded) throw FileError(where + "cannot decode image (" + stbi_failure_reason() + ")");
  std::vector<std::uint8_t> index(decoded.get(), decoded.get() + pixels);
  return MaterialImage(w, h, std::move(index), name);
}

MaterialImage MaterialImage::from_raw(const std::filesystem::path& file, int width, int rows) {
  if (width < 1 || rows < 1)  // before reading: the message names the sizes, whatever the file
    return from_raw_bytes({}, file.string(), width, rows);
  return from_raw_bytes(read_file_bytes(file, "material image raw"), file.string(), width, rows);
}

MaterialImage MaterialImage::from_raw_bytes(std::span<const unsigned char> bytes, const std::string& name, int width,
                                            int rows) {
  const std::string where = "material image raw " + name + ": ";
  if (width < 1 || rows < 1)
    throw FileError(where + "width and rows must be >= 1 (got " + std::to_string(width) + " x " + std::to_string(rows) +
                    ")");
  const auto count = static_cast<std::size_t>(width) * static_cast<std::size_t>(rows);
  if (count > kMaxMaterialImagePixels)
    throw FileError(where + std::to_string(width) + " x " + std::to_string(rows) + " pixels, more than the " +
                    std::to_string(kMaxMaterialImagePixels) + " a material image may hold");
  if (bytes.size() != count)
    throw FileError(where + "size is " + std::to_string(bytes.size()) + " bytes, expected " + std::to_string(count) +
                    " (" + std::to_string(width) + " x " + std::to_string(rows) + " one-byte indices)");
  return MaterialImage(width, rows, std::vector<std::uint8_t>(bytes.begin(), bytes.end()), name);
}

}  // namespace shore::terrain
