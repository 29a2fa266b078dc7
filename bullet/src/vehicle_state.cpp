#include "shore/bullet/vehicle_state.h"

#include <array>
#include <cmath>
#include <cstdint>

#include "checkpoint_bytes.h"
#include "coupling_util.h"
#include "shore/bullet/soil_vehicle.h"
#include "shore/core/byte_io.h"
#include "shore/core/error.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

namespace coupling_detail {
/// A SoilVehicle's per-wheel soil state, read and written whole.
struct SoilVehicleState {
  using Wheels = std::vector<SoilVehicle::WheelSoil>;
  static void put(ByteWriter& w, SoilVehicle& v) {
    for (int k = 0; k < v.getNumWheels(); ++k) {
      const SoilVehicle::WheelSoil& s = v.soil(k);
      const WheelTraction& t = s.last;
      w.put(s.held_spin), w.put(static_cast<std::uint8_t>(t.on_soil));
      for (const double x : {t.spin, t.slip, t.forward, t.side, t.torque, t.resistance}) w.put(x);
    }
  }
  static Wheels get(ByteReader& r, int wheels) {
    Wheels out(static_cast<std::size_t>(wheels));
    for (SoilVehicle::WheelSoil& s : out) {
      s.held_spin = r.get<double>("a wheel's held spin");  // NaN: not held
      const auto on = r.get<std::uint8_t>("a wheel's traction");
      if (on > 1) r.fail("a wheel's on-soil flag " + std::to_string(on) + " is not 0 or 1");
      WheelTraction& t = s.last;
      t.on_soil = on != 0;
      for (double* x : {&t.spin, &t.slip, &t.forward, &t.side, &t.torque, &t.resistance}) {
        *x = r.get<double>("a wheel's traction");
        if (!std::isfinite(*x)) r.fail("a wheel's traction is not finite");
      }
      if (std::isinf(s.held_spin)) r.fail("a wheel's held spin is infinite");
    }
    return out;
  }
  static void set(SoilVehicle& v, Wheels wheels) { v.soil_ = std::move(wheels); }
};
}  // namespace coupling_detail

namespace {
constexpr char kMagic[8] = {'S', 'H', 'V', 'E', 'H', 'I', 'C', 'L'};
constexpr std::uint32_t kVersion = 1;

/// What Bullet's vehicle keeps of a wheel from step to step: its rotation, last rotation
/// step and the game's inputs, and what its last ray found (the couplings read the contact,
/// load and directions before the vehicle casts again in a substep). Not the ground
/// object: only the vehicle's own update reads it, after casting again.
struct WheelRecord {
  btScalar rotation = 0, delta_rotation = 0, steering = 0, engine_force = 0, brake = 0;
  btScalar suspension_force = 0, suspension_length = 0, relative_velocity = 0, clipped_inv_contact = 0, skid = 0;
  btVector3 contact_point{0, 0, 0}, contact_normal{0, 0, 0}, hard_point{0, 0, 0}, direction{0, 0, 0}, axle{0, 0, 0};
  btTransform pose = btTransform::getIdentity();
  bool in_contact = false;

  [[nodiscard]] std::array<btScalar*, 10> scalars() {
    return {&rotation,         &delta_rotation,    &steering,          &engine_force,        &brake,
            &suspension_force, &suspension_length, &relative_velocity, &clipped_inv_contact, &skid};
  }
  [[nodiscard]] std::array<btVector3*, 5> vectors() {
    return {&contact_point, &contact_normal, &hard_point, &direction, &axle};
  }
  static WheelRecord of(const btWheelInfo& i) {
    const btWheelInfo::RaycastInfo& ray = i.m_raycastInfo;
    return {i.m_rotation,
            i.m_deltaRotation,
            i.m_steering,
            i.m_engineForce,
            i.m_brake,
            i.m_wheelsSuspensionForce,
            ray.m_suspensionLength,
            i.m_suspensionRelativeVelocity,
            i.m_clippedInvContactDotSuspension,
            i.m_skidInfo,
            ray.m_contactPointWS,
            ray.m_contactNormalWS,
            ray.m_hardPointWS,
            ray.m_wheelDirectionWS,
            ray.m_wheelAxleWS,
            i.m_worldTransform,
            ray.m_isInContact};
  }
  void apply(btWheelInfo& i) const {
    btWheelInfo::RaycastInfo& ray = i.m_raycastInfo;
    i.m_rotation = rotation, i.m_deltaRotation = delta_rotation, i.m_steering = steering;
    i.m_engineForce = engine_force, i.m_brake = brake, i.m_wheelsSuspensionForce = suspension_force;
    ray.m_suspensionLength = suspension_length, i.m_suspensionRelativeVelocity = relative_velocity;
    i.m_clippedInvContactDotSuspension = clipped_inv_contact, i.m_skidInfo = skid;
    ray.m_contactPointWS = contact_point, ray.m_contactNormalWS = contact_normal, ray.m_hardPointWS = hard_point;
    ray.m_wheelDirectionWS = direction, ray.m_wheelAxleWS = axle, i.m_worldTransform = pose;
    ray.m_isInContact = in_contact;
    ray.m_groundObject = nullptr;  // cast again before the vehicle's update reads it
  }
};
}  // namespace

std::vector<unsigned char> save_vehicle(const btRaycastVehicle& vehicle) {
  ByteWriter w;
  coupling_detail::put_header(w, kMagic, kVersion);
  auto* soil = dynamic_cast<SoilVehicle*>(const_cast<btRaycastVehicle*>(&vehicle));  // read only
  w.put(static_cast<std::uint8_t>(soil != nullptr));
  w.put(static_cast<std::uint32_t>(vehicle.getNumWheels()));
  for (int k = 0; k < vehicle.getNumWheels(); ++k) {
    WheelRecord wheel = WheelRecord::of(vehicle.getWheelInfo(k));
    for (const btScalar* x : wheel.scalars()) w.put(*x);
    for (const btVector3* v : wheel.vectors()) coupling_detail::put_vector(w, *v);
    coupling_detail::put_transform(w, wheel.pose);
    w.put(static_cast<std::uint8_t>(wheel.in_contact));
  }
  if (soil != nullptr) coupling_detail::SoilVehicleState::put(w, *soil);
  return std::move(w.bytes);
}

void restore_vehicle(btRaycastVehicle& vehicle, std::span<const unsigned char> bytes, const std::string& source) {
  ByteReader r(bytes, source);
  coupling_detail::check_header(r, kMagic, kVersion, "a raycast vehicle's state");
  auto* soil = dynamic_cast<SoilVehicle*>(&vehicle);
  const bool saved_soil = r.get<std::uint8_t>("the vehicle's class") != 0;
  if (saved_soil != (soil != nullptr))
    r.fail(std::string("was saved from ") + (saved_soil ? "a SoilVehicle" : "a stock btRaycastVehicle") +
           ", this vehicle is " + (soil != nullptr ? "a SoilVehicle" : "a stock btRaycastVehicle"));
  const auto count = r.get<std::uint32_t>("wheel count");
  if (count != static_cast<std::uint32_t>(vehicle.getNumWheels()))
    r.fail("holds " + std::to_string(count) + " wheels, the vehicle has " + std::to_string(vehicle.getNumWheels()));
  std::vector<WheelRecord> wheels(count);
  for (WheelRecord& wheel : wheels) {
    for (btScalar* x : wheel.scalars()) *x = r.get<btScalar>("a wheel's state");
    for (btVector3* v : wheel.vectors()) *v = coupling_detail::get_vector(r, "a wheel's ray");
    wheel.pose = coupling_detail::get_transform(r, "a wheel's transform");
    const auto contact = r.get<std::uint8_t>("a wheel's contact flag");
    if (contact > 1) r.fail("a wheel's contact flag " + std::to_string(contact) + " is not 0 or 1");
    wheel.in_contact = contact != 0;
    bool finite = coupling_detail::finite(wheel.pose);
    for (const btScalar* x : wheel.scalars()) finite = finite && std::isfinite(double(*x));
    for (const btVector3* v : wheel.vectors()) finite = finite && coupling_detail::finite(*v);
    if (!finite) r.fail("a wheel's state is not finite");
  }
  coupling_detail::SoilVehicleState::Wheels soil_wheels;
  if (soil != nullptr) soil_wheels = coupling_detail::SoilVehicleState::get(r, static_cast<int>(count));
  if (r.remaining() != 0) r.fail("bytes after the last wheel (corrupt)");
  for (int k = 0; k < vehicle.getNumWheels(); ++k) wheels[static_cast<std::size_t>(k)].apply(vehicle.getWheelInfo(k));
  if (soil != nullptr) coupling_detail::SoilVehicleState::set(*soil, std::move(soil_wheels));
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
