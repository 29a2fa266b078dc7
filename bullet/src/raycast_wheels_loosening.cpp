#include "raycast_wheels_loosening.h"

#include <algorithm>
#include <cmath>

#include "shore/core/det_math.h"
#include "shore/terrain/shear.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

void RimLoosening::angles(double radius, double cell) {
  if (radius == radius_ && cell == cell_) return;
  radius_ = radius, cell_ = cell;
  const double reach = 0.95 * radius;
  half_ = static_cast<int>(std::ceil(reach / cell));
  theta_.resize(static_cast<std::size_t>(2 * half_ + 1));
  for (int b = -half_; b <= half_; ++b) {
    const double s = std::clamp(b * cell, -reach, reach);
    theta_[static_cast<std::size_t>(b + half_)] = det::atan2(s, std::sqrt(radius * radius - s * s));
  }
}

void RimLoosening::build(const terrain::Terrain& terrain, const EnvelopeRaster& envelope, const btVector3& centre,
                         const btVector3& forward, double radius, const RimShear& shear, const terrain::Material& m) {
  const double cell = terrain.settings().cell, reach = 0.95 * radius;
  angles(radius, cell);
  // Each covered column's strip first (the columns' offsets along the heading, per axis),
  // then the weights of the strips that hold one: a rolling wheel's rear half holds none.
  rect_ = envelope;
  weight_.resize(envelope.size());
  along_x_.resize(static_cast<std::size_t>(envelope.nx));
  const double fx = double(forward.x()), fy = double(forward.y()), inv_cell = 1.0 / cell;
  for (int x = 0; x < envelope.nx; ++x)
    along_x_[static_cast<std::size_t>(x)] = (terrain.column_x(envelope.i0 + x) - double(centre.x())) * fx;
  std::vector<int>& strip = strip_of_;
  strip.resize(envelope.size());
  int lo = half_, hi = -half_;
  for (int y = 0; y < envelope.ny; ++y) {
    const double along_y = (terrain.column_y(envelope.j0 + y) - double(centre.y())) * fy;
    const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(envelope.nx);
    for (std::size_t x = 0; x < static_cast<std::size_t>(envelope.nx); ++x) {
      if (envelope.lower[row + x] == EnvelopeRaster::kNoLower) continue;  // not covered: never bears
      const double s = std::clamp(along_x_[x] + along_y, -reach, reach);
      const double q = s * inv_cell;  // rounded half away from zero, as lround (a call) would
      const int b = std::clamp(static_cast<int>(q + (q < 0.0 ? -0.5 : 0.5)), -half_, half_);
      strip[row + x] = b + half_;
      lo = std::min(lo, b), hi = std::max(hi, b);
    }
  }
  strip_.resize(theta_.size());
  for (int b = lo; b <= hi; ++b) {
    const auto k = static_cast<std::size_t>(b + half_);
    strip_[k] = terrain::shear::remoulding(m, shear.at(theta_[k]));
  }
  for (std::size_t k = 0; k < envelope.size(); ++k)
    weight_[k] = envelope.lower[k] == EnvelopeRaster::kNoLower ? 1.0 : strip_[static_cast<std::size_t>(strip[k])];
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
