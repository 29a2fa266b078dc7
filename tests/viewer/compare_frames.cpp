// Checks a shore-viewer screenshot taken in a window (under Xvfb) against a headless
// render of the same frame by pixel statistics: both show a scene (not blank), they agree
// overall, and at every body's pixel (from the --report of each run) they show the same.
//   viewer_compare_frames window.png window.json headless.png headless.json
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>

namespace {

struct Picture {
  int w = 0, h = 0;
  unsigned char* rgb = nullptr;
  explicit Picture(const char* file) { rgb = stbi_load(file, &w, &h, nullptr, 3); }
  ~Picture() { stbi_image_free(rgb); }
  [[nodiscard]] double at(int x, int y, int c) const { return rgb[(static_cast<std::size_t>(y) * w + x) * 3 + c]; }
};

/// Standard deviation of luminance: a blank (one-colour) picture has 0.
double spread(const Picture& p) {
  double s = 0, s2 = 0;
  const double n = double(p.w) * p.h;
  for (int y = 0; y < p.h; ++y)
    for (int x = 0; x < p.w; ++x) {
      const double l = (p.at(x, y, 0) + p.at(x, y, 1) + p.at(x, y, 2)) / 3.0;
      s += l;
      s2 += l * l;
    }
  return std::sqrt(std::max(0.0, s2 / n - (s / n) * (s / n)));
}

/// Mean |a - b| over the 9 x 9 patch at (x, y) (0..255), or over the whole picture with r < 0.
double difference(const Picture& a, const Picture& b, int cx, int cy, int r) {
  const int x0 = r < 0 ? 0 : std::max(cx - r, 0), x1 = r < 0 ? a.w - 1 : std::min(cx + r, a.w - 1);
  const int y0 = r < 0 ? 0 : std::max(cy - r, 0), y1 = r < 0 ? a.h - 1 : std::min(cy + r, a.h - 1);
  double d = 0;
  long n = 0;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x, ++n)
      for (int c = 0; c < 3; ++c) d += std::abs(a.at(x, y, c) - b.at(x, y, c)) / 3.0;
  return n ? d / double(n) : 1e9;
}

int fail(const std::string& why) {
  std::fprintf(stderr, "viewer frames differ: %s\n", why.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) return fail("usage: window.png window.json headless.png headless.json");
  const Picture win(argv[1]), head(argv[3]);
  if (!win.rgb || !head.rgb) return fail("cannot read the screenshots");
  if (win.w != head.w || win.h != head.h) return fail("sizes differ");
  nlohmann::json wj, hj;
  std::ifstream(argv[2]) >> wj;
  std::ifstream(argv[4]) >> hj;
  const double sw = spread(win), sh = spread(head);
  std::printf("luminance spread: window %.1f, headless %.1f\n", sw, sh);
  if (sw < 10 || sh < 10) return fail("a screenshot is (nearly) blank");
  const double all = difference(win, head, 0, 0, -1);
  std::printf("mean |window - headless| = %.2f / 255\n", all);
  if (all > 6.0) return fail("the pictures disagree overall");
  if (wj["bodies"].size() != hj["bodies"].size() || wj["bodies"].size() < 5)
    return fail("not the same bodies (the chassis, four wheels, two dropped)");
  int seen = 0;
  for (std::size_t k = 0; k < wj["bodies"].size(); ++k) {
    const double px = wj["bodies"][k]["pixel"][0], py = wj["bodies"][k]["pixel"][1];
    const double hx = hj["bodies"][k]["pixel"][0], hy = hj["bodies"][k]["pixel"][1];
    if (std::hypot(px - hx, py - hy) > 1.0) return fail("body " + std::to_string(k) + " is elsewhere on screen");
    if (px < 0 || py < 0 || px >= win.w || py >= win.h) continue;
    ++seen;
    const double d = difference(win, head, int(px), int(py), 4);
    std::printf("body %zu at (%.0f, %.0f): patch difference %.2f\n", k, px, py, d);
    if (d > 12.0) return fail("body " + std::to_string(k) + " looks different");
  }
  if (seen < 3) return fail("fewer than 3 bodies on screen");
  std::printf("1 passed, 0 failed\n");
  return 0;
}
