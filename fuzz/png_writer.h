#pragma once
// A minimal PNG writer for 16-bit grey images (one stored, uncompressed deflate block): the
// 16-bit heightmaps of the loader tests and the fuzz seeds (stb_image_write writes 8-bit
// only). Header-only.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace shore::fuzz {

namespace png_detail {
inline std::uint32_t crc32(const unsigned char* p, std::size_t n, std::uint32_t c = 0xffffffffu) {
  for (std::size_t i = 0; i < n; ++i) {
    c ^= p[i];
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return c;
}
inline void put_be32(std::vector<unsigned char>& v, std::uint32_t x) {
  for (int s = 24; s >= 0; s -= 8) v.push_back(static_cast<unsigned char>(x >> s));
}
inline void put_chunk(std::vector<unsigned char>& png, const char* type, const std::vector<unsigned char>& data) {
  put_be32(png, static_cast<std::uint32_t>(data.size()));
  std::vector<unsigned char> body(type, type + 4);
  body.insert(body.end(), data.begin(), data.end());
  png.insert(png.end(), body.begin(), body.end());
  put_be32(png, crc32(body.data(), body.size()) ^ 0xffffffffu);
}
}  // namespace png_detail

/// A w x h 16-bit grey PNG of the samples px (row-major, row 0 the top row). The pixel rows
/// must fit one stored deflate block (under 64 KiB).
inline std::vector<unsigned char> png16(int w, int h, const std::vector<std::uint16_t>& px) {
  using namespace png_detail;
  std::vector<unsigned char> raw;  // filter byte 0 per row, big-endian samples
  for (int r = 0; r < h; ++r) {
    raw.push_back(0);
    for (int c = 0; c < w; ++c)
      raw.push_back(static_cast<unsigned char>(px[r * w + c] >> 8)),
          raw.push_back(static_cast<unsigned char>(px[r * w + c]));
  }
  std::vector<unsigned char> z = {0x78, 0x01, 0x01};  // zlib header, one final stored block
  z.push_back(static_cast<unsigned char>(raw.size())), z.push_back(static_cast<unsigned char>(raw.size() >> 8));
  z.push_back(static_cast<unsigned char>(~raw.size())), z.push_back(static_cast<unsigned char>(~raw.size() >> 8));
  z.insert(z.end(), raw.begin(), raw.end());
  std::uint32_t a = 1, b = 0;
  for (unsigned char ch : raw) a = (a + ch) % 65521, b = (b + a) % 65521;
  put_be32(z, (b << 16) | a);
  std::vector<unsigned char> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::vector<unsigned char> ihdr;
  put_be32(ihdr, static_cast<std::uint32_t>(w)), put_be32(ihdr, static_cast<std::uint32_t>(h));
  ihdr.insert(ihdr.end(), {16, 0, 0, 0, 0});  // 16-bit grey
  put_chunk(png, "IHDR", ihdr);
  put_chunk(png, "IDAT", z);
  put_chunk(png, "IEND", {});
  return png;
}

}  // namespace shore::fuzz
