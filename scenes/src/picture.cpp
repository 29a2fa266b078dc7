#include "shore/scenes/picture.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "shore/core/error.h"

namespace shore::scenes {
namespace {

constexpr Rgb kInk{30, 30, 30};
constexpr Rgb kPaper{255, 255, 255};
constexpr int kTitleHeight = 24;
constexpr int kLegendHeight = 40;

}  // namespace

std::string format_length(double metres, bool signed_value) {
  char buf[48];
  const double a = std::abs(metres);
  const char* sign = signed_value && metres > 0 ? "+" : "";
  if (a != 0.0 && a < 0.001)
    std::snprintf(buf, sizeof buf, "%s%.0f um", sign, metres * 1e6);
  else if (a < 0.5)
    std::snprintf(buf, sizeof buf, "%s%.1f mm", sign, metres * 1e3);
  else
    std::snprintf(buf, sizeof buf, "%s%.3f m", sign, metres);
  return buf;
}

Legend deformation_legend(double scale) {
  return {Legend::Map::diverging, format_length(-scale, true) + " lowered", "0",
          "raised " + format_length(scale, true)};
}

namespace {
/// A colour bar with its low / middle / high labels underneath, as wide as the labels need.
void draw_legend(Image& out, int y, const Legend& legend) {
  const int x = 6, gap = 24;
  const int needed = text_width(legend.low, 2) + text_width(legend.mid, 2) + text_width(legend.high, 2) + 2 * gap;
  const int bar_w = std::clamp(needed, 256, std::max(256, out.width() - 2 * x));
  for (int k = 0; k < bar_w; ++k) {
    const double t = static_cast<double>(k) / (bar_w - 1);
    const Rgb c = legend.map == Legend::Map::diverging ? diverging_colour(2.0 * t - 1.0)
                  : legend.map == Legend::Map::water   ? water_colour(2.0 * t - 1.0)
                                                       : height_colour(t);
    out.fill_rect(x + k, y, 1, 10, c);
  }
  draw_text(out, x, y + 14, legend.low, kInk, 2);
  draw_text(out, x + bar_w - text_width(legend.high, 2), y + 14, legend.high, kInk, 2);
  if (!legend.mid.empty() && needed <= bar_w)
    draw_text(out, x + (bar_w - text_width(legend.mid, 2)) / 2, y + 14, legend.mid, kInk, 2);
}
}  // namespace

Image framed_picture(const Image& picture, const std::string& title, const Legend* legend) {
  const int top = title.empty() ? 0 : kTitleHeight;
  const int bottom = legend ? kLegendHeight : 0;
  const int width = std::max(picture.width(), legend ? 480 : 1);
  Image out(width, picture.height() + top + bottom, kPaper);
  out.blit(picture, 0, top);
  if (!title.empty()) draw_text(out, 6, 5, title, kInk, 2);
  if (legend) draw_legend(out, top + picture.height() + 6, *legend);
  return out;
}

Image filmstrip(const std::vector<Image>& frames, const std::vector<std::string>& labels, int columns) {
  if (frames.empty()) throw InvalidSetting("scenes.filmstrip.frames", "0 frames", ">= 1 frame");
  columns = std::clamp(columns, 1, static_cast<int>(frames.size()));
  int cw = 0, ch = 0;
  for (const Image& f : frames) {
    cw = std::max(cw, f.width());
    ch = std::max(ch, f.height());
  }
  const int gap = 8, label_h = 22;
  const int rows = (static_cast<int>(frames.size()) + columns - 1) / columns;
  Image out(columns * (cw + gap) + gap, rows * (ch + label_h + gap) + gap, kPaper);
  for (std::size_t n = 0; n < frames.size(); ++n) {
    const int c = static_cast<int>(n) % columns, r = static_cast<int>(n) / columns;
    const int x = gap + c * (cw + gap), y = gap + r * (ch + label_h + gap);
    out.blit(frames[n], x, y);
    if (n < labels.size()) draw_text(out, x + 4, y + ch + 4, labels[n], kInk, 2);
  }
  return out;
}

}  // namespace shore::scenes
