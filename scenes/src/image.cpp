#include "shore/scenes/image.h"

#include <stb_image_write.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <system_error>

#include "shore/core/error.h"

namespace shore::scenes {

Image::Image(int width, int height, Rgb fill) : width_(width), height_(height) {
  const Check c{"scenes.Image"};
  c.at_least("width", width, 1);
  c.at_least("height", height, 1);
  pixels_.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), fill);
}

void Image::put(int x, int y, Rgb c) {
  if (x >= 0 && y >= 0 && x < width_ && y < height_) at(x, y) = c;
}

void Image::fill_rect(int x, int y, int w, int h, Rgb c) {
  for (int yy = std::max(y, 0); yy < std::min(y + h, height_); ++yy)
    for (int xx = std::max(x, 0); xx < std::min(x + w, width_); ++xx) at(xx, yy) = c;
}

void Image::blit(const Image& src, int x, int y) {
  for (int yy = 0; yy < src.height(); ++yy)
    for (int xx = 0; xx < src.width(); ++xx) put(x + xx, y + yy, src.at(xx, yy));
}

std::filesystem::path write_png(const std::filesystem::path& path, const Image& image) {
  if (image.width() <= 0 || image.height() <= 0) throw FileError("write_png: empty image for " + path.string());
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  if (stbi_write_png(tmp.c_str(), image.width(), image.height(), 3, image.data(), image.width() * 3) == 0)
    throw FileError("write_png: cannot write " + tmp.string());
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw FileError("write_png: cannot rename " + tmp.string() + " to " + path.string() + ": " + ec.message());
  return path;
}

Rgb mix(Rgb a, Rgb b, double t) {
  t = std::clamp(t, 0.0, 1.0);
  auto lerp = [t](std::uint8_t p, std::uint8_t q) {
    return static_cast<std::uint8_t>(std::lround(p + (static_cast<double>(q) - p) * t));
  };
  return {lerp(a.r, b.r), lerp(a.g, b.g), lerp(a.b, b.b)};
}

Rgb shade(Rgb c, double s) {
  s = std::max(0.0, std::isfinite(s) ? s : 0.0);
  auto scale = [s](std::uint8_t p) { return static_cast<std::uint8_t>(std::clamp(std::lround(p * s), 0L, 255L)); };
  return {scale(c.r), scale(c.g), scale(c.b)};
}

namespace {
// Piecewise-linear colour ramp through stops at t = 0, 1/(n-1), ..., 1.
template <std::size_t N>
Rgb ramp(const std::array<Rgb, N>& stops, double t) {
  t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0);
  const double x = t * (N - 1);
  const std::size_t k = std::min(static_cast<std::size_t>(x), N - 2);
  return mix(stops[k], stops[k + 1], x - static_cast<double>(k));
}
}  // namespace

Rgb diverging_colour(double t) {
  // lowered: blue; untouched: a warm neutral grey; raised: orange to red.
  static constexpr std::array<Rgb, 5> stops{
      {{33, 102, 172}, {120, 172, 208}, {224, 218, 204}, {240, 150, 100}, {178, 24, 43}}};
  return ramp(stops, 0.5 * (t + 1.0));
}

Rgb height_colour(double t) {
  static constexpr std::array<Rgb, 4> stops{{{84, 120, 72}, {160, 160, 104}, {196, 168, 122}, {246, 240, 228}}};
  return ramp(stops, t);
}

Rgb water_colour(double t) {
  static constexpr std::array<Rgb, 3> stops{{{10, 50, 110}, {40, 118, 186}, {200, 236, 248}}};
  return ramp(stops, 0.5 * (t + 1.0));
}

// ---- 5x7 font ---------------------------------------------------------------------
namespace {
struct Glyph {
  char c;
  const char* rows;  // 7 rows of 5 pixels, '#' = ink
};

// clang-format off
constexpr Glyph kFont[] = {
  {'A', ".###." "#...#" "#...#" "#####" "#...#" "#...#" "#...#"},
  {'B', "####." "#...#" "#...#" "####." "#...#" "#...#" "####."},
  {'C', ".###." "#...#" "#...." "#...." "#...." "#...#" ".###."},
  {'D', "####." "#...#" "#...#" "#...#" "#...#" "#...#" "####."},
  {'E', "#####" "#...." "#...." "####." "#...." "#...." "#####"},
  {'F', "#####" "#...." "#...." "####." "#...." "#...." "#...."},
  {'G', ".###." "#...#" "#...." "#.###" "#...#" "#...#" ".####"},
  {'H', "#...#" "#...#" "#...#" "#####" "#...#" "#...#" "#...#"},
  {'I', ".###." "..#.." "..#.." "..#.." "..#.." "..#.." ".###."},
  {'J', "..###" "...#." "...#." "...#." "...#." "#..#." ".##.."},
  {'K', "#...#" "#..#." "#.#.." "##..." "#.#.." "#..#." "#...#"},
  {'L', "#...." "#...." "#...." "#...." "#...." "#...." "#####"},
  {'M', "#...#" "##.##" "#.#.#" "#.#.#" "#...#" "#...#" "#...#"},
  {'N', "#...#" "#...#" "##..#" "#.#.#" "#..##" "#...#" "#...#"},
  {'O', ".###." "#...#" "#...#" "#...#" "#...#" "#...#" ".###."},
  {'P', "####." "#...#" "#...#" "####." "#...." "#...." "#...."},
  {'Q', ".###." "#...#" "#...#" "#...#" "#.#.#" "#..#." ".##.#"},
  {'R', "####." "#...#" "#...#" "####." "#.#.." "#..#." "#...#"},
  {'S', ".####" "#...." "#...." ".###." "....#" "....#" "####."},
  {'T', "#####" "..#.." "..#.." "..#.." "..#.." "..#.." "..#.."},
  {'U', "#...#" "#...#" "#...#" "#...#" "#...#" "#...#" ".###."},
  {'V', "#...#" "#...#" "#...#" "#...#" "#...#" ".#.#." "..#.."},
  {'W', "#...#" "#...#" "#...#" "#.#.#" "#.#.#" "#.#.#" ".#.#."},
  {'X', "#...#" "#...#" ".#.#." "..#.." ".#.#." "#...#" "#...#"},
  {'Y', "#...#" "#...#" ".#.#." "..#.." "..#.." "..#.." "..#.."},
  {'Z', "#####" "....#" "...#." "..#.." ".#..." "#...." "#####"},
  {'0', ".###." "#...#" "#..##" "#.#.#" "##..#" "#...#" ".###."},
  {'1', "..#.." ".##.." "..#.." "..#.." "..#.." "..#.." ".###."},
  {'2', ".###." "#...#" "....#" "...#." "..#.." ".#..." "#####"},
  {'3', "####." "....#" "....#" ".###." "....#" "....#" "####."},
  {'4', "...#." "..##." ".#.#." "#..#." "#####" "...#." "...#."},
  {'5', "#####" "#...." "####." "....#" "....#" "#...#" ".###."},
  {'6', "..##." ".#..." "#...." "####." "#...#" "#...#" ".###."},
  {'7', "#####" "....#" "...#." "..#.." ".#..." ".#..." ".#..."},
  {'8', ".###." "#...#" "#...#" ".###." "#...#" "#...#" ".###."},
  {'9', ".###." "#...#" "#...#" ".####" "....#" "...#." ".##.."},
  {'.', "....." "....." "....." "....." "....." ".##.." ".##.."},
  {',', "....." "....." "....." "....." ".##.." "..#.." ".#..."},
  {'-', "....." "....." "....." "#####" "....." "....." "....."},
  {'+', "....." "..#.." "..#.." "#####" "..#.." "..#.." "....."},
  {':', "....." ".##.." ".##.." "....." ".##.." ".##.." "....."},
  {'/', "....#" "....#" "...#." "..#.." ".#..." "#...." "#...."},
  {'=', "....." "....." "#####" "....." "#####" "....." "....."},
  {'%', "##..#" "##..#" "...#." "..#.." ".#..." "#..##" "#..##"},
  {'(', "...#." "..#.." ".#..." ".#..." ".#..." "..#.." "...#."},
  {')', ".#..." "..#.." "...#." "...#." "...#." "..#.." ".#..."},
  {'_', "....." "....." "....." "....." "....." "....." "#####"},
  {'*', "....." "..#.." "#.#.#" ".###." "#.#.#" "..#.." "....."},
  {'|', "..#.." "..#.." "..#.." "..#.." "..#.." "..#.." "..#.."},
};
// clang-format on

const char* glyph_rows(char c) {
  const char u = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  for (const Glyph& g : kFont)
    if (g.c == u) return g.rows;
  return nullptr;
}
constexpr int kGlyphW = 5;
constexpr int kGlyphH = 7;
constexpr int kAdvance = 6;  // glyph plus one blank column
}  // namespace

int text_width(std::string_view text, int scale) { return static_cast<int>(text.size()) * kAdvance * scale; }

int draw_text(Image& image, int x, int y, std::string_view text, Rgb colour, int scale) {
  for (char c : text) {
    if (const char* rows = glyph_rows(c)) {
      for (int r = 0; r < kGlyphH; ++r)
        for (int k = 0; k < kGlyphW; ++k)
          if (rows[r * kGlyphW + k] == '#') image.fill_rect(x + k * scale, y + r * scale, scale, scale, colour);
    }
    x += kAdvance * scale;
  }
  return x;
}

}  // namespace shore::scenes
