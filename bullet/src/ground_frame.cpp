#include "shore/bullet/ground_frame.h"

#include <algorithm>
#include <cmath>

#include "shore/core/error.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

namespace {
constexpr double kRotationTolerance = 1e-5;  // float rounding of a rotation given in btScalar
}  // namespace

GroundFrame GroundFrame::y_up() {
  GroundFrame f;
  // Columns: ground x -> world x, ground y -> world -z, ground up -> world y.
  f.rotation.setValue(1, 0, 0, 0, 0, 1, 0, -1, 0);
  return f;
}

bool GroundFrame::identity() const {
  const btMatrix3x3 one = btMatrix3x3::getIdentity();
  for (int r = 0; r < 3; ++r)
    if (rotation[r] != one[r]) return false;
  return origin == btVector3(0, 0, 0);
}

void GroundFrame::validate(const std::string& field) const {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(double(rotation[r][c])))
        throw InvalidSetting(field + ".rotation[" + std::to_string(r) + "][" + std::to_string(c) + "]",
                             detail::to_text(double(rotation[r][c])), "must be finite");
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(double(origin[k])))
      throw InvalidSetting(field + ".origin", detail::to_text(double(origin[k])), "must be finite");
  double deviation = 0.0;  // largest |a_i . a_j - delta_ij| over the columns
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      deviation = std::max(deviation,
                           std::abs(double(rotation.getColumn(i).dot(rotation.getColumn(j))) - (i == j ? 1.0 : 0.0)));
  if (!(deviation <= kRotationTolerance))
    throw InvalidSetting(field + ".rotation", "columns off orthonormal by " + detail::to_text(deviation),
                         "must be a rotation: orthonormal columns within 1e-5 (no scale or shear)");
  const double det = double(rotation.determinant());
  if (!(det > 0.0))
    throw InvalidSetting(field + ".rotation", "determinant " + detail::to_text(det),
                         "must be a proper rotation (determinant +1, not a mirror)");
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
