#include "terrain_body.h"

#include <algorithm>
#include <string>

#include "shore/core/error.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {
namespace {

/// Refuses a shape that covers no area seen from below (a zero-size box or ball): a point
/// or a line cannot bear on soil.
void check_has_area(const btCollisionShape& shape) {
  btVector3 lo, hi;
  shape.getAabb(btTransform::getIdentity(), lo, hi);
  const btVector3 size = hi - lo;
  const double extent = std::max({double(size.x()), double(size.y()), double(size.z())});
  EnvelopeRaster probe;
  const int covered = extent > 0.0
                          ? rasterize_envelope(shape, btTransform::getIdentity(),
                                               EnvelopeGrid{lo.x(), lo.y(), extent / 64.0}, nominal_solid(), probe)
                          : 0;
  if (covered == 0)
    throw InvalidSetting(std::string("bullet.TerrainCoupling.add_body(body) shape ") + shape.getName(),
                         "no size seen from below",
                         "must cover some area (a zero-size box, ball or line cannot bear on soil)");
}

}  // namespace

EnvelopeOptions nominal_solid() {
  EnvelopeOptions o;
  o.include_margin = false;
  return o;
}

double check_terrain_shape(const btCollisionShape& shape, double cell, const EnvelopeOptions& options) {
  const double reach = check_rasterizable(shape, cell, options);
  check_has_area(shape);
  return reach;
}

bool shape_still_fits(const CoupledBody& body, TerrainBody& record, double cell, const EnvelopeOptions& options) {
  ShapeCheck& check = record.shape;
  const btCollisionShape* shape = body.shape();
  if (shape == check.shape && (shape == nullptr || shape->getLocalScaling() == check.scaling)) return check.fits;
  check.shape = shape;
  check.scaling = shape ? shape->getLocalScaling() : btVector3(1, 1, 1);
  record.envelope.lower.clear();  // made for the old shape
  record.contact.state = contact_detail::ContactState::none;
  check.fits = false;
  if (shape == nullptr) return false;
  try {
    check.reach = check_terrain_shape(*shape, cell, options);
    check.fits = true;
  } catch (const InvalidSetting&) {
    // Skipped (and counted) while the terrain cannot take the shape.
  }
  return check.fits;
}

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
