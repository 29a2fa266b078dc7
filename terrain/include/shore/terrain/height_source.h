#pragma once
// Where untouched ground lies: flat, lattice noise, or an imported heightmap.

#include <cstdint>
#include <filesystem>
#include <vector>

namespace shore::terrain {

/// Height (m) of the untouched ground at a world position. Must be deterministic and
/// thread-safe (const).
class HeightSource {
 public:
  virtual ~HeightSource() = default;
  [[nodiscard]] virtual double height(double x, double y) const = 0;
};

}  // namespace shore::terrain
