#include "shore/bullet/soil_vehicle.h"

#include <cmath>
#include <string>

#include "shore/core/error.h"
#include "soft_ground.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

namespace {

void check_wheel(const btRaycastVehicle& vehicle, int wheel, const char* call) {
  if (wheel < 0 || wheel >= vehicle.getNumWheels())
    throw InvalidSetting(std::string("bullet.SoilVehicle.") + call + "(wheel)", std::to_string(wheel),
                         "must be a wheel index in [0, " + std::to_string(vehicle.getNumWheels()) + ")");
}

}  // namespace

bool SoilVehicle::on_soft_ground(const btVector3& world_point) const {
  for (const std::weak_ptr<const coupling_detail::SoftGround>& g : grounds_)
    if (const std::shared_ptr<const coupling_detail::SoftGround> ground = g.lock();
        ground && ground->holds(world_point))
      return true;
  return false;
}

void SoilVehicle::updateFriction(btScalar timeStep) {
  // Bullet's friction reads a wheel's ground object; a wheel on soft ground is shown none
  // for the call, so Bullet gives it neither side nor forward impulse: the coupling gives
  // it the soil's.
  btAlignedObjectArray<void*> hidden;
  hidden.resize(getNumWheels(), nullptr);
  for (int k = 0; k < getNumWheels(); ++k) {
    btWheelInfo& w = m_wheelInfo[k];
    if (w.m_raycastInfo.m_isInContact && on_soft_ground(w.m_raycastInfo.m_contactPointWS)) {
      hidden[k] = w.m_raycastInfo.m_groundObject;
      w.m_raycastInfo.m_groundObject = nullptr;
    }
  }
  btRaycastVehicle::updateFriction(timeStep);
  for (int k = 0; k < getNumWheels(); ++k)
    if (hidden[k] != nullptr) m_wheelInfo[k].m_raycastInfo.m_groundObject = hidden[k];
}

SoilVehicle::WheelSoil& SoilVehicle::soil(int wheel) {
  if (soil_.size() != static_cast<std::size_t>(getNumWheels())) soil_.resize(static_cast<std::size_t>(getNumWheels()));
  return soil_[static_cast<std::size_t>(wheel)];
}

void SoilVehicle::hold_wheel_spin(int wheel, double spin) {
  check_wheel(*this, wheel, "hold_wheel_spin");
  if (!std::isfinite(spin))
    throw InvalidSetting("bullet.SoilVehicle.hold_wheel_spin(spin)", detail::to_text(spin), "must be finite, rad/s");
  soil(wheel).held_spin = spin;
}

void SoilVehicle::release_wheel_spin(int wheel) {
  check_wheel(*this, wheel, "release_wheel_spin");
  soil(wheel).held_spin = std::numeric_limits<double>::quiet_NaN();
}

const WheelTraction& SoilVehicle::wheel_traction(int wheel) const {
  static const WheelTraction none{};
  if (wheel < 0 || static_cast<std::size_t>(wheel) >= soil_.size()) return none;
  return soil_[static_cast<std::size_t>(wheel)].last;
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
