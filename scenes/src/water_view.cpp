#include "shore/scenes/water_view.h"

#include <algorithm>
#include <cmath>

namespace shore::scenes {

HeightGrid surface_grid(const water::Surface& s) {
  HeightGrid g(s.nx(), s.ny(), s.spacing(), s.node_x(0), s.node_y(0));
  for (int j = 0; j < s.ny(); ++j)
    for (int i = 0; i < s.nx(); ++i) g.at(i, j) = s.height(i, j);
  return g;
}

double max_deviation(const water::Surface& s) {
  const double rest = s.settings().rest_height;
  double m = 0.0;
  for (int j = 0; j < s.ny(); ++j)
    for (int i = 0; i < s.nx(); ++i)
      if (!s.is_fixed(i, j)) m = std::max(m, std::abs(s.height(i, j) - rest));
  return m;
}

}  // namespace shore::scenes
