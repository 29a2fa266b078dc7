#pragma once
// Private: the checks every PNG loader makes before stb_image decodes a file (stb_image
// checks neither chunk bounds nor CRCs), shared by the heightmap and material image loaders.

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace shore::terrain {

/// Walks the PNG's chunks up to IEND, checking that each lies inside the file and matches
/// its CRC. Returns the file without its empty IDAT chunks, or an empty vector when there
/// are none to drop. Throws shore::FileError prefixed with `where`.
std::vector<unsigned char> checked_png_chunks(std::span<const unsigned char> bytes, const std::string& where);

/// Whether a PNG of file_bytes bytes can hold w x h pixels (deflate expands at most 1032 times).
bool plausible_png_size(std::size_t file_bytes, int w, int h);

/// A PNG whose signature, chunks, size and header passed every check: ready to decode.
struct CheckedPng {
  std::vector<unsigned char> stripped;   ///< the file without its empty IDAT chunks (empty: none dropped)
  std::span<const unsigned char> bytes;  ///< what to decode: `stripped` or the caller's bytes
  int width = 0, height = 0, channels = 0;
  std::size_t pixels = 0;

  CheckedPng() = default;
  CheckedPng(CheckedPng&&) noexcept = default;  // a moved vector keeps its buffer: `bytes` stays valid
  CheckedPng& operator=(CheckedPng&&) noexcept = default;
  CheckedPng(const CheckedPng&) = delete;  // a copy's `bytes` would point into the original
  CheckedPng& operator=(const CheckedPng&) = delete;
};
/// Checks a PNG before stb_image decodes it: signature, size, chunks and CRCs, a readable
/// header, at most max_pixels pixels (`too_many` ends that message: "samples a heightmap
/// may hold") and no more than its bytes can hold. Throws shore::FileError prefixed with
/// `where`. The result refers to `bytes`: keep them alive while it is used.
CheckedPng checked_png(std::span<const unsigned char> bytes, const std::string& where, std::size_t max_pixels,
                       const std::string& too_many);

}  // namespace shore::terrain
