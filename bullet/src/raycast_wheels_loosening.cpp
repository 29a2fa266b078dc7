#include "raycast_wheels_loosening.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "shore/core/det_math.h"
#include "shore/terrain/shear.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

namespace {
constexpr double kUnknown = -1.0;  // a strip's weight not worked out yet (weights lie in (0, 1])
// Below this share of the heading across a line of columns, its strips are runs of three
// columns and more, found by bisection (weigh_runs); above, each column is placed.
constexpr double kLongStrips = 0.35;

/// Calls fill(p, q, k) for runs [p, q] of positions first..last along a line that lie in
/// one strip k, covering every position. strip_at(p) is monotone along the line (the
/// column's distance ahead rounds monotonically), so a span whose ends share a strip lies in
/// it whole: spans are halved until their ends agree.
template <class StripAt, class Fill>
void weigh_runs(std::size_t first, std::size_t last, const StripAt& strip_at, const Fill& fill) {
  struct Span {
    std::size_t p, q, kp, kq;
  };
  std::array<Span, 128> stack;  // one entry a halving, two per level at most
  std::size_t n = 0;
  stack[n++] = {first, last, strip_at(first), strip_at(last)};
  while (n > 0) {
    const Span s = stack[--n];
    if (s.kp == s.kq) {
      fill(s.p, s.q, s.kp);
    } else if (s.q - s.p <= 1) {
      fill(s.p, s.p, s.kp), fill(s.q, s.q, s.kq);
    } else {
      const std::size_t mid = s.p + (s.q - s.p) / 2, km = strip_at(mid);
      stack[n++] = {mid, s.q, km, s.kq};  // the later half after the earlier
      stack[n++] = {s.p, mid, s.kp, km};
    }
  }
}
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
  // A strip's weight is worked out when a column of it is first weighed (kUnknown until
  // then): a rolling wheel's rear half covers none.
  rect_ = envelope;
  weight_.resize(envelope.size());
  strip_.assign(theta_.size(), kUnknown);
  const auto nx = static_cast<std::size_t>(envelope.nx), ny = static_cast<std::size_t>(envelope.ny);
  along_x_.resize(nx), along_y_.resize(ny);
  const double fx = double(forward.x()), fy = double(forward.y()), inv_cell = 1.0 / cell;
  for (std::size_t x = 0; x < nx; ++x) along_x_[x] = from_centre.dx(envelope.i0 + static_cast<std::int64_t>(x)) * fx;
  for (std::size_t y = 0; y < ny; ++y) along_y_[y] = from_centre.dy(envelope.j0 + static_cast<std::int64_t>(y)) * fy;
  const auto strip_of = [&](std::size_t x, std::size_t y) {
    const double s = std::clamp(along_x_[x] + along_y_[y], -reach, reach);
    return static_cast<std::size_t>(std::clamp(static_cast<int>(round_half_away(s * inv_cell)), -half_, half_) + half_);
  };
  const auto weigh = [&](std::size_t k) {
    if (strip_[k] == kUnknown) strip_[k] = terrain::shear::remoulding(m, shear.at(theta_[k]));
    return strip_[k];
  };
  // Lines of columns along the axis the heading crosses least steeply: a strip is then
  // several columns long along a line (about 1 / |that component|).
  const bool rows = std::abs(fx) <= std::abs(fy);
  const std::size_t lines = rows ? ny : nx, length = rows ? nx : ny, step = rows ? 1 : nx;
  const bool runs = std::min(std::abs(fx), std::abs(fy)) <= kLongStrips;
  for (std::size_t line = 0; line < lines; ++line) {
    const std::size_t start = rows ? line * nx : line;  // the line's first column
    const auto at = [&](std::size_t p) { return start + p * step; };
    const auto strip_at = [&](std::size_t p) { return rows ? strip_of(p, line) : strip_of(line, p); };
    const auto covered = [&](std::size_t p) { return envelope.lower[at(p)] != EnvelopeRaster::kNoLower; };
    if (!runs) {
      for (std::size_t p = 0; p < length; ++p)
        if (covered(p)) weight_[at(p)] = weigh(strip_at(p));
      continue;
    }
    std::size_t first = 0, last = length;  // the covered columns' span, [first, last)
    while (first < last && !covered(first)) ++first;
    while (first < last && !covered(last - 1)) --last;
    if (first == last) continue;
    weigh_runs(first, last - 1, strip_at, [&](std::size_t p, std::size_t q, std::size_t k) {
      const double w = weigh(k);
      for (std::size_t r = p; r <= q; ++r) weight_[at(r)] = w;
    });
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
