#pragma once
// The ray a btRaycastVehicle's wheel casts, for wheels on Shore's soft ground.
//
// Bullet's stock raycaster reports the hit triangle's normal, and btRaycastVehicle reads
// its suspension's velocity along that normal (the damper) and pushes along it. On soil a
// wheel rides its own rut: every few cells its ray lands on a triangle across a column step
// tilted 0.2 to 0.4, and the damper reads the chassis' forward speed as the suspension
// extending, dropping the suspension force for that substep (1.3 to 2.5 kN on a 4.4 kN
// wheel, docs/terrain.md "Raycast wheels"). A SoilRaycaster wraps btDefaultVehicleRaycaster
// and, for a hit on its coupling's terrain, reports the untouched ground's normal at the
// wheel's scale instead: the slope of the terrain's base heights over `span` either side
// of the hit. The base, not the surface: the ruts and bow waves are the wheels' own
// pressing, which the coupling already answers (bearing, compaction push, the rut walls'
// side push), and a plane fitted to them would tilt with the rut the wheel is in. Hits on
// anything else keep Bullet's answer.
//
// A vehicle built with it, and added with it (TerrainCoupling::add_vehicle's `raycaster`),
// also rises onto soil that carries more than its load where its ray hit (the ray finds
// the floor the wheel pressed, whatever the soil carries; without the rise a depth pressed
// once is kept): the wheel is raised until the soil carries the suspension force the
// ground raised that far would give.
//
//   shore::bullet::SoilRaycaster raycaster(coupling);              // was btDefaultVehicleRaycaster
//   auto* car = new btRaycastVehicle(tuning, chassis, &raycaster); // or a SoilVehicle
//   coupling.add_vehicle(car, widths, &raycaster);
//
// The raycaster must outlive the vehicles built with it; the coupling must outlive it.

#include <BulletDynamics/Vehicle/btRaycastVehicle.h>
#include <BulletDynamics/Vehicle/btVehicleRaycaster.h>

#include "shore/bullet/config.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

class TerrainCoupling;

struct SoilRaycasterSettings {
  /// m, > 0 and finite: the half-width over which the base's slope is taken (central
  /// differences at the hit +- span along the ground's x and y). Default 0.4 m, about a
  /// car wheel's radius; taken as at least one cell.
  double span = 0.4;

  /// Throws shore::InvalidSetting naming `field`.span for a value out of range.
  void validate(const char* field) const;
};

class SoilRaycaster : public btVehicleRaycaster {
 public:
  /// Casts in the coupling's world. Throws InvalidSetting for bad settings.
  explicit SoilRaycaster(TerrainCoupling& coupling, SoilRaycasterSettings settings = {});

  /// btDefaultVehicleRaycaster's hit; on the coupling's terrain, its normal is the base's.
  void* castRay(const btVector3& from, const btVector3& to, btVehicleRaycasterResult& result) override;

  [[nodiscard]] const TerrainCoupling& coupling() const noexcept { return coupling_; }
  [[nodiscard]] const SoilRaycasterSettings& settings() const noexcept { return settings_; }

 private:
  btDefaultVehicleRaycaster inner_;
  TerrainCoupling& coupling_;
  SoilRaycasterSettings settings_;
};

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
