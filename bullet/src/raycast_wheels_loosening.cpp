#include "raycast_wheels_loosening.h"

#include <algorithm>
#include <cmath>

#include "shore/core/det_math.h"
#include "shore/terrain/shear.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

namespace {
constexpr double kUnknown = -1.0;  // a strip's weight not worked out yet (weights lie in (0, 1])
}  // namespace

void RimLoosening::angles(double radius, double cell) {
  if (radius == radius_ && cell == cell_) return;
  radius_ = radius, cell_ = cell;
  const double reach = 0.95 * radius;
  half_ = static_cast<int>(std::ceil(reach / cell));
  theta_.resize(static_cast<std::size_t>(2 * half_ + 1));
  for (int b = -half_; b <= half_; ++b) theta_[static_cast<std::size_t>(b + half_)] = rim_angle(b * cell, radius);
}

void RimLoosening::build(double cell, const EnvelopeRaster& envelope, const ColumnOffsets& from_centre,
                         const btVector3& forward, double radius, const RimShear& shear, const terrain::Material& m) {
  const double reach = 0.95 * radius;
  angles(radius, cell);
  // A strip's weight is worked out when a covered column first falls in it (kUnknown until
  // then): a rolling wheel's rear half covers none.
  rect_ = envelope;
  weight_.resize(envelope.size());
  strip_.assign(theta_.size(), kUnknown);
  along_x_.resize(static_cast<std::size_t>(envelope.nx));
  const double fx = double(forward.x()), fy = double(forward.y()), inv_cell = 1.0 / cell;
  for (int x = 0; x < envelope.nx; ++x) along_x_[static_cast<std::size_t>(x)] = from_centre.dx(envelope.i0 + x) * fx;
  for (int y = 0; y < envelope.ny; ++y) {
    const double along_y = from_centre.dy(envelope.j0 + y) * fy;
    const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(envelope.nx);
    for (std::size_t x = 0; x < static_cast<std::size_t>(envelope.nx); ++x) {
      if (envelope.lower[row + x] == EnvelopeRaster::kNoLower) continue;  // not covered: never bears
      const double s = std::clamp(along_x_[x] + along_y, -reach, reach);
      const auto k =
          static_cast<std::size_t>(std::clamp(static_cast<int>(round_half_away(s * inv_cell)), -half_, half_) + half_);
      if (strip_[k] == kUnknown) strip_[k] = terrain::shear::remoulding(m, shear.at(theta_[k]));
      weight_[row + x] = strip_[k];
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
