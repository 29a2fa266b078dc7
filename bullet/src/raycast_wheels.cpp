#include "raycast_wheels.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "body_registry.h"
#include "bt_convert.h"
#include "shore/core/error.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

namespace {

constexpr double kMaxWidth = 10.0;  // m: wider is no wheel
constexpr double kRolling = 0.05;   // m/s: a wheel slower than this is standing

/// The wheel's pose for its cylinder: resting on the point its ray hit (Bullet's own wheel
/// transform is made before the ray and lags a falling wheel), local x along its steered
/// axle, local z up the suspension.
btTransform wheel_pose(const btWheelInfo& info) {
  const btVector3 up = -info.m_raycastInfo.m_wheelDirectionWS.normalized();
  btVector3 axle = info.m_raycastInfo.m_wheelAxleWS.rotate(up, info.m_steering);
  axle = (axle - up * axle.dot(up)).normalized();
  const btVector3 forward = up.cross(axle);
  btMatrix3x3 basis(axle.x(), forward.x(), up.x(), axle.y(), forward.y(), up.y(), axle.z(), forward.z(), up.z());
  return btTransform(basis, info.m_raycastInfo.m_contactPointWS + up * info.m_wheelsRadius);
}

/// The columns' push on the cylinder's sloped faces, resolved horizontally along `forward`:
/// a column at distance s ahead of the wheel's centre meets the rim at slope s / sqrt(R^2 - s^2).
double compaction_push(const terrain::Terrain& terrain, const terrain::Bearing& bearing, const btVector3& centre,
                       const btVector3& forward, double radius, double load) {
  if (!(bearing.capacity > 0.0) || !std::isfinite(bearing.capacity)) return 0.0;
  const double share = load / bearing.capacity;  // the load the columns carry, in proportion to their capacity
  double push = 0.0;
  for (const terrain::ColumnForce& c : bearing.columns) {
    const double dx = terrain.column_x(c.i) - double(centre.x()), dy = terrain.column_y(c.j) - double(centre.y());
    const double s = std::clamp(dx * double(forward.x()) + dy * double(forward.y()), -0.95 * radius, 0.95 * radius);
    push -= share * c.force * s / std::sqrt(radius * radius - s * s);
  }
  return std::clamp(push, -load, load);
}

/// Keeps the columns at and ahead of the wheel's lowest point along `heading`: a rolling
/// wheel bears on its front arc (Bekker's rolling wheel); the soil behind it unloads as the
/// rim rises away.
void keep_front(const terrain::Terrain& terrain, const btVector3& centre, const btVector3& heading,
                EnvelopeRaster& envelope) {
  for (int b = 0; b < envelope.ny; ++b)
    for (int a = 0; a < envelope.nx; ++a) {
      const std::int64_t i = envelope.i0 + a, j = envelope.j0 + b;
      const double dx = terrain.column_x(i) - double(centre.x()), dy = terrain.column_y(j) - double(centre.y());
      if (dx * double(heading.x()) + dy * double(heading.y()) < 0.0)
        envelope.lower[envelope.index(i, j)] = EnvelopeRaster::kNoLower;
    }
}

}  // namespace

void RaycastWheels::add(btRaycastVehicle* vehicle, std::span<const double> widths, double cell,
                        const EnvelopeOptions& options) {
  const std::string where = "bullet.TerrainCoupling.add_vehicle";
  if (vehicle == nullptr) throw InvalidSetting(where + "(vehicle)", "null", "must be a btRaycastVehicle");
  for (const Vehicle& v : vehicles_)
    if (v.vehicle == vehicle) throw InvalidSetting(where + "(vehicle)", "added already", "must be added once");
  const int n = vehicle->getNumWheels();
  if (widths.size() != static_cast<std::size_t>(n))
    throw InvalidSetting(where + "(widths)", std::to_string(widths.size()) + " widths",
                         "must give one width per wheel (" + std::to_string(n) + ")");
  Vehicle v{vehicle, vehicle->getRigidBody(), {}};
  v.wheels.reserve(widths.size());
  for (int k = 0; k < n; ++k) {
    const double b = widths[static_cast<std::size_t>(k)], r = double(vehicle->getWheelInfo(k).m_wheelsRadius);
    const std::string field = where + "(widths[" + std::to_string(k) + "])";
    if (!(b > 0.0 && b <= kMaxWidth))
      throw InvalidSetting(field, detail::to_text(b), "must be a wheel width in (0, 10] m");
    if (!(r > 0.0 && std::isfinite(r)))
      throw InvalidSetting(where + " wheel " + std::to_string(k) + " radius", detail::to_text(r), "must be > 0");
    Wheel w;
    w.shape = std::make_unique<btCylinderShapeX>(btVector3(btScalar(b / 2), btScalar(r), btScalar(r)));
    w.shape->setMargin(btScalar(0));
    w.reach = check_rasterizable(*w.shape, cell, options);
    v.wheels.push_back(std::move(w));
  }
  vehicles_.push_back(std::move(v));
}

void RaycastWheels::remove(const btRaycastVehicle* vehicle) {
  std::erase_if(vehicles_, [vehicle](const Vehicle& v) { return v.vehicle == vehicle; });
}

double RaycastWheels::push(const btRaycastVehicle* vehicle, int k) const {
  for (const Vehicle& v : vehicles_)
    if (v.vehicle == vehicle && k >= 0 && static_cast<std::size_t>(k) < v.wheels.size())
      return v.wheels[static_cast<std::size_t>(k)].push;
  return 0.0;
}

int RaycastWheels::forget_lost(const btCollisionWorld& world) {
  if (vehicles_.empty()) return 0;
  const HeldObjects held(world);
  return static_cast<int>(std::erase_if(vehicles_, [&](const Vehicle& v) { return !held.holds(v.chassis); }));
}

const terrain::Imprint* RaycastWheels::press(const terrain::Terrain& terrain, EnvelopeRasterizer& rasterizer, double h,
                                             bool deforms, btRaycastVehicle& vehicle, const btWheelInfo& info,
                                             Wheel& wheel) {
  const double load = info.m_wheelsSuspensionForce;
  const btTransform world_pose = wheel_pose(info);
  const btTransform pose = framed_ ? to_ground_ * world_pose : world_pose;  // in the terrain's coordinates
  if (!(load > 0.0) || !pose_rasterizable(pose, wheel.reach, rasterizer.grid())) return nullptr;
  if (rasterizer.rasterize(*wheel.shape, pose, wheel.envelope) == 0) return nullptr;
  const btVector3 forward = pose.getBasis().getColumn(1), world_forward = world_pose.getBasis().getColumn(1);
  btRigidBody* chassis = vehicle.getRigidBody();
  const btVector3 at = info.m_raycastInfo.m_contactPointWS - chassis->getCenterOfMassPosition();
  const btVector3 world_velocity = chassis->getVelocityInLocalPoint(at);
  // Rolling (faster than kRolling along its heading): the front arc bears; at rest, both.
  const double speed = double(world_velocity.dot(world_forward));
  wheel.bearing_part = wheel.envelope;
  if (std::abs(speed) > kRolling)
    keep_front(terrain, pose.getOrigin(), speed > 0 ? forward : -forward, wheel.bearing_part);
  const double offset = terrain.bearing_offset(wheel.bearing_part, load);
  const double radius = info.m_wheelsRadius;
  const double push =
      compaction_push(terrain, terrain.bearing(wheel.bearing_part, offset), pose.getOrigin(), forward, radius, load);
  chassis->applyImpulse(world_forward * btScalar(push * h), at);
  wheel.push = push;
  if (!deforms) return nullptr;
  wheel.imprint = terrain::Imprint{&wheel.envelope, offset};
  const btVector3 velocity = chassis->getVelocityInLocalPoint(at);  // after the push
  wheel.imprint.velocity = to_vec3(framed_ ? to_ground_.getBasis() * velocity : velocity);
  wheel.imprint.centre = to_vec3(pose.getOrigin());
  wheel.imprint.spray = false;  // Bullet's wheel has no spin the spray could read
  return &wheel.imprint;
}

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
