// The checks every PNG loader makes before decoding (png_checks.h).

#include "png_checks.h"

#include <stb_image.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "shore/core/error.h"

namespace shore::terrain {

namespace {

std::uint32_t big_endian_32(const unsigned char* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | std::uint32_t{p[3]};
}

std::uint32_t png_crc(const unsigned char* p, std::size_t n) {
  std::uint32_t c = 0xffffffffu;
  for (std::size_t i = 0; i < n; ++i) {
    c ^= p[i];
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return c ^ 0xffffffffu;
}

}  // namespace

/// Walks the PNG's chunks up to IEND, checking that each lies inside the file and matches
/// its CRC (stb_image checks neither: a flipped bit would decode to wrong ground, or read
/// past a chunk). Returns the file without its empty IDAT chunks (legal, but stb_image
/// copies them from a null buffer), or an empty vector when there are none to drop.
std::vector<unsigned char> checked_png_chunks(std::span<const unsigned char> bytes, const std::string& where) {
  std::vector<unsigned char> kept;
  bool dropped = false;
  std::size_t pos = 8;
  for (;;) {
    if (bytes.size() - pos < 12) throw FileError(where + "truncated (the file ends before its IEND chunk)");
    const std::uint32_t length = big_endian_32(bytes.data() + pos);
    const std::string type(reinterpret_cast<const char*>(bytes.data() + pos + 4), 4);
    const std::string chunk = "chunk \"" + type + "\" at byte " + std::to_string(pos);
    if (length > 0x7fffffffu || bytes.size() - pos - 12 < length)
      throw FileError(where + "truncated (" + chunk + " of " + std::to_string(length) + " bytes runs past the end)");
    if (png_crc(bytes.data() + pos + 4, 4 + std::size_t{length}) != big_endian_32(bytes.data() + pos + 8 + length))
      throw FileError(where + chunk + " fails its CRC (corrupt)");
    const std::size_t end = pos + 12 + length;
    if (type == "IDAT" && length == 0) {
      if (!dropped) kept.assign(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(pos));
      dropped = true;
    } else if (dropped) {
      kept.insert(kept.end(), bytes.begin() + static_cast<std::ptrdiff_t>(pos),
                  bytes.begin() + static_cast<std::ptrdiff_t>(end));
    }
    pos = end;
    if (type == "IEND") return kept;
  }
}

/// A deflate stream expands at most 1032 times (zlib's limit): a PNG of S bytes holds at
/// most 1032 S bytes of pixel rows, each of at least one filter byte and one bit per pixel.
/// A header claiming more is corrupt, and is refused before anything is allocated for it.
bool plausible_png_size(std::size_t file_bytes, int w, int h) {
  const double least_raw = static_cast<double>(h) * (1.0 + std::ceil(static_cast<double>(w) / 8.0));
  return least_raw <= 1032.0 * static_cast<double>(file_bytes);
}

CheckedPng checked_png(std::span<const unsigned char> bytes, const std::string& where, std::size_t max_pixels,
                       const std::string& too_many) {
  static constexpr unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kPngSignature, 8) != 0)
    throw FileError(where + "not a PNG file (signature missing)");
  if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw FileError(where + "file too large");
  CheckedPng png;
  png.stripped = checked_png_chunks(bytes, where);
  png.bytes = png.stripped.empty() ? bytes : std::span<const unsigned char>(png.stripped);
  const int len = static_cast<int>(png.bytes.size());
  int& w = png.width;
  int& h = png.height;
  if (!stbi_info_from_memory(png.bytes.data(), len, &w, &h, &png.channels))
    throw FileError(where + "unreadable header (" + stbi_failure_reason() + ")");
  if (w < 1 || h < 1) throw FileError(where + "empty image");
  png.pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  if (png.pixels > max_pixels)
    throw FileError(where + std::to_string(w) + " x " + std::to_string(h) + " pixels, more than the " +
                    std::to_string(max_pixels) + " " + too_many);
  if (!plausible_png_size(png.bytes.size(), w, h))
    throw FileError(where + "header claims " + std::to_string(w) + " x " + std::to_string(h) + " pixels, more than " +
                    std::to_string(png.bytes.size()) + " bytes can hold (corrupt)");
  return png;
}

}  // namespace shore::terrain
