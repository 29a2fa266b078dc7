#include "shore/scenes/film.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace shore::scenes {

std::string time_label(double seconds) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "t = %.2f s", seconds);
  return buf;
}

std::vector<int> evenly_spread(int substeps, int frames) {
  std::vector<int> at;
  for (int q = 0; q < frames; ++q)
    at.push_back(static_cast<int>(std::lround(static_cast<double>(substeps) * q / (frames - 1))));
  return at;
}

std::vector<int> evenly_spread_film(int substeps, bool smoke) { return evenly_spread(substeps, smoke ? 3 : 6); }

std::vector<int> at_fractions(int substeps, std::span<const double> fractions, int first) {
  std::vector<int> at;
  for (double f : fractions) at.push_back(std::clamp(static_cast<int>(std::lround(f * substeps)), first, substeps));
  return at;
}

}  // namespace shore::scenes
