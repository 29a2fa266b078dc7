#pragma once
// RGB images, PNG output (stb_image_write), colour maps and a tiny built-in font for
// labels, so every scene's pictures look alike.

#include <cstdint>
#include <filesystem>
#include <string_view>
#include <vector>

namespace shore::scenes {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  friend bool operator==(const Rgb&, const Rgb&) = default;
};

class Image {
 public:
  Image() = default;
  Image(int width, int height, Rgb fill = {255, 255, 255});
  [[nodiscard]] int width() const noexcept { return width_; }
  [[nodiscard]] int height() const noexcept { return height_; }
  Rgb& at(int x, int y) {
    return pixels_[static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x)];
  }
  [[nodiscard]] Rgb at(int x, int y) const {
    return pixels_[static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x)];
  }
  /// Sets a pixel if it lies inside the image.
  void put(int x, int y, Rgb c);
  void fill_rect(int x, int y, int w, int h, Rgb c);
  /// Copies src with its top-left corner at (x, y), clipped.
  void blit(const Image& src, int x, int y);
  [[nodiscard]] const std::uint8_t* data() const noexcept { return &pixels_.data()->r; }

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<Rgb> pixels_;
};
static_assert(sizeof(Rgb) == 3, "Image rows are packed RGB for stb_image_write");

/// Writes a PNG (through a temporary file renamed into place); returns the path.
/// Throws shore::FileError if it cannot.
std::filesystem::path write_png(const std::filesystem::path& path, const Image& image);

/// Diverging map for deformation, t in [-1, 1]: lowered (t < 0) blue, untouched (0)
/// neutral sand-grey, raised (t > 0) orange-red. Clamped outside [-1, 1].
Rgb diverging_colour(double t);
/// Hypsometric map for heights, t in [0, 1]: low green-brown to high pale.
Rgb height_colour(double t);
/// Water map, t in [-1, 1]: troughs deep blue, rest level mid blue, crests pale cyan.
Rgb water_colour(double t);
/// c scaled by s (0..~1.3), clamped.
Rgb shade(Rgb c, double s);
/// Linear mix: a at t = 0, b at t = 1.
Rgb mix(Rgb a, Rgb b, double t);

/// Draws text with the built-in 5x7 font (letters, digits and . , - + : / = % ( ) _ * |),
/// each pixel scaled by scale. Unknown characters draw as blanks. Returns the x after the text.
int draw_text(Image& image, int x, int y, std::string_view text, Rgb colour, int scale = 2);
/// Width in pixels of text at the given scale.
int text_width(std::string_view text, int scale = 2);

}  // namespace shore::scenes
