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

}  // namespace shore::terrain
