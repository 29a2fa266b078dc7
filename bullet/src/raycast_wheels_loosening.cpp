#include "raycast_wheels_loosening.h"

#include <algorithm>
#include <cmath>

#include "shore/core/det_math.h"
#include "shore/terrain/shear.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

void RimLoosening::build(const terrain::Terrain& terrain, const GridRect& rect, const btVector3& centre,
                         const btVector3& forward, double radius, const RimShear& shear, const terrain::Material& m) {
  const double cell = terrain.settings().cell, reach = 0.95 * radius;
  const int half = static_cast<int>(std::ceil(reach / cell));
  strip_.resize(static_cast<std::size_t>(2 * half + 1));
  for (int b = -half; b <= half; ++b) {
    const double s = std::clamp(b * cell, -reach, reach);
    const double theta = det::atan2(s, std::sqrt(radius * radius - s * s));
    strip_[static_cast<std::size_t>(b + half)] = terrain::shear::remoulding(m, shear.at(theta));
  }
  rect_ = rect;
  weight_.resize(rect.size());
  const double fx = double(forward.x()), fy = double(forward.y());
  for (int y = 0; y < rect.ny; ++y) {
    const double along_y = (terrain.column_y(rect.j0 + y) - double(centre.y())) * fy;
    for (int x = 0; x < rect.nx; ++x) {
      const double s = std::clamp((terrain.column_x(rect.i0 + x) - double(centre.x())) * fx + along_y, -reach, reach);
      const int b = std::clamp(static_cast<int>(std::lround(s / cell)), -half, half);
      weight_[static_cast<std::size_t>(y) * static_cast<std::size_t>(rect.nx) + static_cast<std::size_t>(x)] =
          strip_[static_cast<std::size_t>(b + half)];
    }
  }
}

double RimLoosening::capacity(const terrain::Bearing& bearing) const {
  if (!std::isfinite(bearing.capacity)) return bearing.capacity;  // bedrock carries anything
  double sum = 0.0;
  for (const terrain::ColumnForce& c : bearing.columns) sum += weight(c) * c.force;
  return sum;
}

void RimLoosening::apply(const terrain::Bearing& bearing, terrain::Bearing& out) const {
  out.patch_width = bearing.patch_width;
  out.contact_columns = bearing.contact_columns;
  out.columns.resize(bearing.columns.size());
  double sum = 0.0;
  for (std::size_t k = 0; k < bearing.columns.size(); ++k) {
    terrain::ColumnForce c = bearing.columns[k];
    c.force *= weight(c);
    sum += c.force;
    out.columns[k] = c;
  }
  out.capacity = std::isfinite(bearing.capacity) ? sum : bearing.capacity;
}

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
