// WaterCoupling's raycast vehicles: their wheels, each a cylinder at the pose its ray found
// (coupled_raycast_wheel.h), floated and displacing water like any body; their pushes act
// on the chassis.
#include <algorithm>
#include <string>

#include "coupled_raycast_wheel.h"
#include "coupling_directory.h"
#include "framed_body.h"
#include "raycast_wheels.h"
#include "shore/bullet/water_coupling.h"
#include "shore/core/error.h"
#include "water_coupling_parts.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace {
using Directory = coupling_detail::WorldDirectory<WaterCoupling>;

bool holds_vehicle(const std::vector<coupling_detail::WaterVehicle>& vehicles, const btRaycastVehicle* vehicle) {
  return std::any_of(vehicles.begin(), vehicles.end(),
                     [vehicle](const coupling_detail::WaterVehicle& v) { return v.vehicle == vehicle; });
}
}  // namespace

void WaterCoupling::add_vehicle(btRaycastVehicle* vehicle, std::span<const double> wheel_widths,
                                WaterBodySettings body_settings) {
  const std::string where = "bullet.WaterCoupling.add_vehicle";
  if (vehicle == nullptr) throw InvalidSetting(where + "(vehicle)", "null", "must be a btRaycastVehicle");
  if (detached_)
    throw InvalidSetting(where + "(vehicle)", "after detach()",
                         "a detached coupling takes no vehicles: make a new one");
  if (holds_vehicle(parts_->vehicles, vehicle))
    throw InvalidSetting(where + "(vehicle)", "added already", "must be added once (remove_vehicle first)");
  Directory::for_each_other(&world_, this, [&](const WaterCoupling& other) {
    if (holds_vehicle(other.parts_->vehicles, vehicle))
      throw InvalidSetting(where + "(vehicle)", "in another water coupling of this world",
                           "must be in one water coupling (else both would float its wheels)");
  });
  coupling_detail::check_wheel_widths(*vehicle, wheel_widths, where);
  coupling_detail::cast_wheel_rays(*vehicle);
  coupling_detail::WaterVehicle added{vehicle, {}};
  for (int k = 0; k < vehicle->getNumWheels(); ++k) {
    auto wheel = coupling_detail::CoupledRaycastWheel::make(*vehicle, k, wheel_widths[static_cast<std::size_t>(k)]);
    added.wheels.push_back(&wheel->object());
    parts_->enroll(*this, coupling_detail::couple(std::move(wheel), settings_.frame), body_settings, where.c_str(),
                   "wheel");
  }
  parts_->vehicles.push_back(std::move(added));
}

void WaterCoupling::remove_vehicle(const btRaycastVehicle* vehicle) {
  auto& vehicles = parts_->vehicles;
  const auto v = std::find_if(vehicles.begin(), vehicles.end(),
                              [vehicle](const coupling_detail::WaterVehicle& w) { return w.vehicle == vehicle; });
  if (v == vehicles.end()) return;
  for (const btCollisionObject* wheel : v->wheels) parts_->bodies.remove(wheel);
  vehicles.erase(v);
}

BodyWater WaterCoupling::wheel_water(const btRaycastVehicle* vehicle, int wheel) const {
  for (const coupling_detail::WaterVehicle& v : parts_->vehicles) {
    if (v.vehicle != vehicle) continue;
    if (wheel < 0 || static_cast<std::size_t>(wheel) >= v.wheels.size()) return {};
    const Parts::Entry* e = parts_->bodies.find(v.wheels[static_cast<std::size_t>(wheel)]);
    return e != nullptr ? parts_->in_world(*e) : BodyWater{};
  }
  return {};
}

void WaterCoupling::Parts::forget_lost_vehicles() {
  std::erase_if(vehicles, [this](const coupling_detail::WaterVehicle& v) {
    return !v.wheels.empty() && bodies.find(v.wheels.front()) == nullptr;
  });
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
