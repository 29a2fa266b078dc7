#pragma once
// A regular grid of heights (terrain, water surface, or a body's top envelope) in world
// units: column (i, j) sits at (x0 + i * cell, y0 + j * cell). The scene helpers render and
// export it; the physics modules have their own storage and copy into one of these.

#include <cstddef>
#include <vector>

namespace shore::scenes {

struct HeightGrid {
  int nx = 0;             ///< columns along x, >= 1
  int ny = 0;             ///< columns along y, >= 1
  double cell = 0.01;     ///< m, spacing, > 0
  double x0 = 0.0;        ///< m, world x of column (0, 0)
  double y0 = 0.0;        ///< m, world y of column (0, 0)
  std::vector<double> z;  ///< m, row-major: z[j * nx + i]; NaN marks "no value" (e.g. no body)

  HeightGrid() = default;
  /// Throws shore::InvalidSetting for non-positive sizes or cell.
  HeightGrid(int columns_x, int columns_y, double spacing, double origin_x, double origin_y, double fill = 0.0);

  [[nodiscard]] std::size_t index(int i, int j) const {
    return static_cast<std::size_t>(j) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(i);
  }
  double& at(int i, int j) { return z[index(i, j)]; }
  [[nodiscard]] double at(int i, int j) const { return z[index(i, j)]; }
  [[nodiscard]] double x(int i) const { return x0 + i * cell; }
  [[nodiscard]] double y(int j) const { return y0 + j * cell; }
  /// Bilinear height at fractional column coordinates (clamped to the grid).
  [[nodiscard]] double sample(double fi, double fj) const;
  /// Bilinear height at world (x, y) (clamped to the grid).
  [[nodiscard]] double sample_world(double wx, double wy) const { return sample((wx - x0) / cell, (wy - y0) / cell); }
  /// Number of NaN or infinite values.
  [[nodiscard]] long non_finite_count() const;
};

}  // namespace shore::scenes
