#include "shore/scenes/render.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "shore/core/error.h"

namespace shore::scenes {
namespace {

constexpr Rgb kInk{30, 30, 30};
constexpr Rgb kPaper{255, 255, 255};
constexpr Rgb kBody{150, 158, 176};
constexpr int kTitleHeight = 24;
constexpr int kLegendHeight = 40;

/// Light direction (towards the light) for an azimuth clockwise from +y and an altitude.
struct Light {
  double x, y, z;
};
Light light_direction(double azimuth_deg, double altitude_deg) {
  const double az = azimuth_deg * std::numbers::pi / 180.0;
  const double alt = altitude_deg * std::numbers::pi / 180.0;
  return {std::sin(az) * std::cos(alt), std::cos(az) * std::cos(alt), std::sin(alt)};
}

/// Lambert term of the surface with slopes (gx, gy) = (dz/dx, dz/dy).
double lambert(double gx, double gy, const Light& l) {
  if (!std::isfinite(gx) || !std::isfinite(gy)) return 0.0;
  const double n = std::sqrt(gx * gx + gy * gy + 1.0);
  return std::max(0.0, (-gx * l.x - gy * l.y + l.z) / n);
}

/// Brightness factor from a hillshade value: flat ground (sin 45 deg) keeps its colour,
/// slopes facing the light brighten, slopes facing away darken.
double light_multiplier(double hillshade_value) {
  return std::clamp(1.0 + 1.5 * (hillshade_value - std::numbers::sqrt2 / 2.0), 0.3, 1.35);
}

/// Derivative along one axis of values spaced h apart: central inside, one-sided at ends.
template <class Get>
double derivative(Get get, int k, int n, double h) {
  if (n < 2) return 0.0;
  if (k == 0) return (get(1) - get(0)) / h;
  if (k == n - 1) return (get(n - 1) - get(n - 2)) / h;
  return (get(k + 1) - get(k - 1)) / (2.0 * h);
}

/// A height grid resampled to pixels (f pixels per cell), with colours and shading.
struct Field {
  int w = 0, h = 0;
  double pixel = 1.0;         // m per pixel
  HeightGrid ground;          // pixel-resolution heights, row j = 0 at the south edge
  HeightGrid body;            // pixel-resolution body tops (NaN: none)
  HeightGrid body_bottom;     // pixel-resolution body undersides (NaN: none or unknown)
  std::vector<Rgb> colour;    // unshaded colour per pixel (same indexing as ground)
  std::vector<double> light;  // shading multiplier per pixel
  double zmin = 0, zmax = 0;  // over ground and bodies
  std::string legend_low, legend_mid, legend_high;
  bool diverging = false;
};

int pixels_per_cell(const HeightGrid& g, int min_pixels) {
  const int longest = std::max(std::max(g.nx, g.ny) - 1, 1);
  return std::clamp((min_pixels + longest - 1) / longest, 1, 64);
}

HeightGrid resample(const HeightGrid& g, int f) {
  HeightGrid r((g.nx - 1) * f + 1, (g.ny - 1) * f + 1, g.cell / f, g.x0, g.y0);
  for (int j = 0; j < r.ny; ++j)
    for (int i = 0; i < r.nx; ++i) r.at(i, j) = g.sample(static_cast<double>(i) / f, static_cast<double>(j) / f);
  return r;
}

/// Resampling of a body envelope onto the pixel grid `like`: bilinear where the four
/// surrounding columns all hold a value, nearest column otherwise (NaN outside bodies).
HeightGrid resample_body(const HeightGrid& g, const HeightGrid& like) {
  HeightGrid r(like.nx, like.ny, like.cell, like.x0, like.y0, std::numeric_limits<double>::quiet_NaN());
  for (int j = 0; j < r.ny; ++j)
    for (int i = 0; i < r.nx; ++i) {
      const double fi = (r.x(i) - g.x0) / g.cell, fj = (r.y(j) - g.y0) / g.cell;
      const int i0 = std::clamp(static_cast<int>(std::floor(fi)), 0, g.nx - 1);
      const int j0 = std::clamp(static_cast<int>(std::floor(fj)), 0, g.ny - 1);
      const int i1 = std::min(i0 + 1, g.nx - 1), j1 = std::min(j0 + 1, g.ny - 1);
      if (std::isfinite(g.at(i0, j0)) && std::isfinite(g.at(i1, j0)) && std::isfinite(g.at(i0, j1)) &&
          std::isfinite(g.at(i1, j1))) {
        r.at(i, j) = g.sample(fi, fj);
        continue;
      }
      const int gi = static_cast<int>(std::lround(fi)), gj = static_cast<int>(std::lround(fj));
      if (gi >= 0 && gj >= 0 && gi < g.nx && gj < g.ny) r.at(i, j) = g.at(gi, gj);
    }
  return r;
}

void min_max(const HeightGrid& g, double& lo, double& hi) {
  for (double v : g.z)
    if (std::isfinite(v)) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
}

Field make_field(const HeightGrid& heights, const ReliefStyle& style) {
  if (heights.nx < 2 || heights.ny < 2)
    throw InvalidSetting("scenes.render.heights", "grid smaller than 2 x 2", ">= 2 x 2");
  Field fd;
  const int f = pixels_per_cell(heights, style.min_pixels);
  fd.ground = resample(heights, f);
  fd.w = fd.ground.nx;
  fd.h = fd.ground.ny;
  fd.pixel = fd.ground.cell;
  const HeightGrid none(fd.w, fd.h, fd.pixel, fd.ground.x0, fd.ground.y0, std::numeric_limits<double>::quiet_NaN());
  fd.body = style.bodies ? resample_body(*style.bodies, fd.ground) : none;
  fd.body_bottom = style.bodies && style.body_bottoms ? resample_body(*style.body_bottoms, fd.ground) : none;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  min_max(fd.ground, lo, hi);
  fd.zmin = lo;
  fd.zmax = hi;
  min_max(fd.body, fd.zmin, fd.zmax);
  if (!std::isfinite(fd.zmin)) fd.zmin = fd.zmax = 0.0;

  fd.colour.resize(fd.ground.z.size());
  if (style.baseline) {
    const HeightGrid& b = *style.baseline;
    if (b.nx != heights.nx || b.ny != heights.ny)
      throw InvalidSetting("scenes.ReliefStyle.baseline", "size differs from heights", "same nx, ny as the heights");
    double scale = style.deformation_scale;
    if (!(scale > 0.0)) {
      scale = 0.0;
      for (std::size_t k = 0; k < heights.z.size(); ++k)
        if (std::isfinite(heights.z[k] - b.z[k])) scale = std::max(scale, std::abs(heights.z[k] - b.z[k]));
    }
    const HeightGrid base = resample(b, f);
    for (std::size_t k = 0; k < fd.colour.size(); ++k) {
      const double d = fd.ground.z[k] - base.z[k];
      fd.colour[k] = diverging_colour(scale > 0.0 ? d / scale : 0.0);
    }
    fd.diverging = true;
    const Legend legend = deformation_legend(scale);
    fd.legend_low = legend.low;
    fd.legend_mid = legend.mid;
    fd.legend_high = legend.high;
  } else {
    const double range = hi - lo;
    for (std::size_t k = 0; k < fd.colour.size(); ++k)
      fd.colour[k] = height_colour(range > 0.0 ? (fd.ground.z[k] - lo) / range : 0.5);
    fd.legend_low = format_length(lo, false);
    fd.legend_mid = "";
    fd.legend_high = format_length(hi, false);
  }

  const std::vector<double> s = hillshade(fd.ground, 315.0, 45.0, style.exaggeration);
  fd.light.resize(s.size());
  for (std::size_t k = 0; k < s.size(); ++k) fd.light[k] = light_multiplier(s[k]);
  return fd;
}

constexpr Rgb kSpray{92, 62, 30};  // dark earth: reads on every colour map

/// A filled disc of `radius` pixels (at least 0.75) at pixel (cx, cy) of the picture.
void draw_dot(Image& pic, double cx, double cy, double radius) {
  const double r = std::max(radius, 0.75);
  const int x0 = static_cast<int>(std::floor(cx - r)), x1 = static_cast<int>(std::ceil(cx + r));
  const int y0 = static_cast<int>(std::floor(cy - r)), y1 = static_cast<int>(std::ceil(cy + r));
  for (int y = std::max(y0, 0); y <= std::min(y1, pic.height() - 1); ++y)
    for (int x = std::max(x0, 0); x <= std::min(x1, pic.width() - 1); ++x)
      if ((x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r) pic.at(x, y) = kSpray;
}

/// Adds a title strip above and the field's legend below a picture.
Image frame_picture(const Image& picture, const std::string& title, const Field* field) {
  if (field == nullptr) return framed_picture(picture, title, nullptr);
  const Legend legend{field->diverging ? Legend::Map::diverging : Legend::Map::height, field->legend_low,
                      field->legend_mid, field->legend_high};
  return framed_picture(picture, title, &legend);
}

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

std::vector<double> hillshade(const HeightGrid& g, double azimuth_deg, double altitude_deg, double exaggeration) {
  const Light l = light_direction(azimuth_deg, altitude_deg);
  std::vector<double> s(g.z.size(), 0.0);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const double gx = exaggeration * derivative([&](int k) { return g.at(k, j); }, i, g.nx, g.cell);
      const double gy = exaggeration * derivative([&](int k) { return g.at(i, k); }, j, g.ny, g.cell);
      s[g.index(i, j)] = lambert(gx, gy, l);
    }
  return s;
}

Image render_relief(const HeightGrid& heights, const ReliefStyle& style) {
  const Field fd = make_field(heights, style);
  Image pic(fd.w, fd.h);
  for (int j = 0; j < fd.h; ++j)
    for (int i = 0; i < fd.w; ++i) {
      const std::size_t k = fd.ground.index(i, j);
      pic.at(i, fd.h - 1 - j) = shade(fd.colour[k], fd.light[k]);  // north up
    }
  // Bodies: tinted, outlined (body pixels with a neighbour outside the body).
  auto in_body = [&](int i, int j) {
    return i >= 0 && j >= 0 && i < fd.w && j < fd.h && std::isfinite(fd.body.at(i, j));
  };
  for (int j = 0; j < fd.h; ++j)
    for (int i = 0; i < fd.w; ++i)
      if (in_body(i, j) && (!in_body(i - 1, j) || !in_body(i + 1, j) || !in_body(i, j - 1) || !in_body(i, j + 1)))
        pic.at(i, fd.h - 1 - j) = kInk;
      else if (in_body(i, j))
        pic.at(i, fd.h - 1 - j) = mix(pic.at(i, fd.h - 1 - j), kBody, 0.45);
  if (style.spray != nullptr)  // seen from above: where each particle is over the ground
    for (const Dot& d : *style.spray)
      draw_dot(pic, (d.x - fd.ground.x0) / fd.pixel, fd.h - 1 - (d.y - fd.ground.y0) / fd.pixel, d.radius / fd.pixel);
  return frame_picture(pic, style.title, style.legend ? &fd : nullptr);
}

Image render_oblique(const HeightGrid& heights, const ReliefStyle& style, double elevation_deg) {
  const Field fd = make_field(heights, style);
  const double e = std::clamp(elevation_deg, 5.0, 90.0) * std::numbers::pi / 180.0;
  const double sin_e = std::sin(e), cos_e = std::cos(e);
  const double ex = style.exaggeration;
  const double base_depth = std::max(0.04 * (fd.h - 1) * fd.pixel, (fd.zmax - fd.zmin) * 0.2 + 1e-9);
  const double zbase = fd.zmin - base_depth / std::max(ex, 1e-9);
  // Screen "up" coordinate (m) of a world point, measured from the front-bottom corner.
  auto up = [&](double y_rel, double z) { return y_rel * sin_e + (z - zbase) * ex * cos_e; };
  const double top_up = up((fd.h - 1) * fd.pixel, fd.zmax);
  const int margin = 4;
  const int height = static_cast<int>(std::ceil(top_up / fd.pixel)) + 2 * margin + 1;
  Image pic(fd.w, height, kPaper);
  auto row_of = [&](double u) { return height - 1 - margin - static_cast<int>(std::lround(u / fd.pixel)); };

  // Front (south) to back: the first sample to reach a pixel is the nearest, so each
  // vertical segment fills only pixels still empty. Ground columns reach down to the base
  // (the front row draws the block's skirt); bodies span their lower to upper envelope.
  std::vector<std::uint8_t> written(static_cast<std::size_t>(fd.w) * static_cast<std::size_t>(height), 0);
  auto fill_segment = [&](int i, int row_top, int row_bottom, Rgb surface, Rgb face) {
    for (int r = std::max(row_top, 0); r <= std::min(row_bottom, height - 1); ++r) {
      std::uint8_t& w =
          written[static_cast<std::size_t>(r) * static_cast<std::size_t>(fd.w) + static_cast<std::size_t>(i)];
      if (w) continue;
      w = 1;
      pic.at(i, r) = r - row_top < 2 ? surface : face;
    }
  };
  const std::vector<double> body_light = hillshade(fd.body, 315.0, 45.0, 1.0);
  for (int j = 0; j < fd.h; ++j) {
    const double y_rel = j * fd.pixel;
    for (int i = 0; i < fd.w; ++i) {
      const std::size_t k = fd.ground.index(i, j);
      const double g = fd.ground.z[k];
      const double b = fd.body.z[k];
      if (std::isfinite(b) && b > g) {
        const double under = std::isfinite(fd.body_bottom.z[k]) ? std::max(fd.body_bottom.z[k], g) : g;
        fill_segment(i, row_of(up(y_rel, b)), row_of(up(y_rel, under)), shade(kBody, light_multiplier(body_light[k])),
                     shade(kBody, 0.62));
      }
      fill_segment(i, row_of(up(y_rel, g)), row_of(up(y_rel, zbase)), shade(fd.colour[k], fd.light[k]),
                   shade(fd.colour[k], j == 0 ? 0.55 : 0.62));
    }
  }
  if (style.spray != nullptr)  // over everything: particles are in the air in front of the ground
    for (const Dot& d : *style.spray) {
      const double u = up(d.y - fd.ground.y0, d.z) / fd.pixel;
      draw_dot(pic, (d.x - fd.ground.x0) / fd.pixel, height - 1 - margin - u, d.radius / fd.pixel);
    }
  return frame_picture(pic, style.title, style.legend ? &fd : nullptr);
}

Image render_water(const HeightGrid& surface, double rest_level, double scale, const std::string& title,
                   int min_pixels) {
  if (surface.nx < 2 || surface.ny < 2)
    throw InvalidSetting("scenes.render_water.surface", "grid smaller than 2 x 2", ">= 2 x 2");
  const int f = pixels_per_cell(surface, min_pixels);
  const HeightGrid r = resample(surface, f);
  if (!(scale > 0.0)) {
    scale = 0.0;
    for (double v : surface.z)
      if (std::isfinite(v)) scale = std::max(scale, std::abs(v - rest_level));
  }
  // Ripples are tiny against the cell: exaggerate the shading so the steepest slope reads
  // as about 0.6.
  double steepest = 0.0;
  for (int j = 0; j < surface.ny; ++j)
    for (int i = 0; i + 1 < surface.nx; ++i)
      steepest = std::max(steepest, std::abs(surface.at(i + 1, j) - surface.at(i, j)) / surface.cell);
  const double exaggeration = steepest > 0.0 ? std::clamp(0.6 / steepest, 1.0, 1e5) : 1.0;
  const std::vector<double> s = hillshade(r, 315.0, 45.0, exaggeration);
  Image pic(r.nx, r.ny);
  for (int j = 0; j < r.ny; ++j)
    for (int i = 0; i < r.nx; ++i) {
      const std::size_t k = r.index(i, j);
      const double t = scale > 0.0 ? (r.z[k] - rest_level) / scale : 0.0;
      pic.at(i, r.ny - 1 - j) = shade(water_colour(t), 0.45 + 0.7 * s[k]);
    }
  Image out(std::max(pic.width(), 480), pic.height() + (title.empty() ? 0 : kTitleHeight) + kLegendHeight, kPaper);
  const int top = title.empty() ? 0 : kTitleHeight;
  out.blit(pic, 0, top);
  if (!title.empty()) draw_text(out, 6, 5, title, kInk, 2);
  const int y = top + pic.height() + 6;
  const int bar_w = std::min(out.width() - 12, 480);
  for (int k = 0; k < bar_w; ++k) out.fill_rect(6 + k, y, 1, 10, water_colour(2.0 * k / (bar_w - 1) - 1.0));
  const std::string lo = format_length(-scale, true) + " trough", hi = "crest " + format_length(scale, true);
  draw_text(out, 6, y + 14, lo, kInk, 2);
  draw_text(out, 6 + bar_w - text_width(hi, 2), y + 14, hi, kInk, 2);
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

namespace {
ReliefStyle frame_style(const HeightGrid* baseline, const BodyEnvelopes* bodies, int min_pixels,
                        const std::string& title) {
  ReliefStyle style;
  style.baseline = baseline;
  if (bodies != nullptr) {
    style.bodies = &bodies->top;
    style.body_bottoms = &bodies->bottom;
  }
  style.min_pixels = min_pixels;
  style.title = title;
  return style;
}
}  // namespace

Image relief_frame(const HeightGrid& heights, const HeightGrid* baseline, const BodyEnvelopes* bodies, int min_pixels,
                   const std::string& title, const std::vector<Dot>* spray) {
  ReliefStyle style = frame_style(baseline, bodies, min_pixels, title);
  style.spray = spray;
  return render_relief(heights, style);
}

Image oblique_frame(const HeightGrid& heights, const HeightGrid& baseline, const BodyEnvelopes* bodies,
                    double exaggeration, int min_pixels, const std::string& title, double deformation_scale,
                    double elevation_deg, bool legend, const std::vector<Dot>* spray) {
  ReliefStyle style = frame_style(&baseline, bodies, min_pixels, title);
  style.deformation_scale = deformation_scale;
  style.exaggeration = exaggeration;
  style.legend = legend;
  style.spray = spray;
  return render_oblique(heights, style, elevation_deg);
}

}  // namespace shore::scenes
