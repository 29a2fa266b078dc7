#include "shore/scenes/height_grid.h"

#include <algorithm>
#include <cmath>

#include "shore/core/error.h"

namespace shore::scenes {

HeightGrid::HeightGrid(int columns_x, int columns_y, double spacing, double origin_x, double origin_y, double fill)
    : nx(columns_x), ny(columns_y), cell(spacing), x0(origin_x), y0(origin_y) {
  const Check c{"scenes.HeightGrid"};
  c.at_least("nx", nx, 1);
  c.at_least("ny", ny, 1);
  c.positive("cell", cell);
  z.assign(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny), fill);
}

double HeightGrid::sample(double fi, double fj) const {
  fi = std::clamp(fi, 0.0, static_cast<double>(nx - 1));
  fj = std::clamp(fj, 0.0, static_cast<double>(ny - 1));
  const int i = std::min(static_cast<int>(fi), std::max(nx - 2, 0));
  const int j = std::min(static_cast<int>(fj), std::max(ny - 2, 0));
  const int i1 = std::min(i + 1, nx - 1);
  const int j1 = std::min(j + 1, ny - 1);
  const double u = fi - i;
  const double v = fj - j;
  const double bottom = (1 - u) * at(i, j) + u * at(i1, j);
  const double top = (1 - u) * at(i, j1) + u * at(i1, j1);
  return (1 - v) * bottom + v * top;
}

long HeightGrid::non_finite_count() const {
  return static_cast<long>(std::count_if(z.begin(), z.end(), [](double v) { return !std::isfinite(v); }));
}

}  // namespace shore::scenes
