#pragma once
// Two-way coupling of Bullet bodies with the spring-mass water surface.
//
//   shore::water::Surface pond(settings);
//   shore::bullet::WaterCoupling water(world, pond);   // adds itself; steps the water
//   water.add_body(box);                               // floats, makes rings and a wake
//
// Water to body: buoyancy and drag from the body's shape against the water plane fitted
// under it (buoyancy.h), applied as impulses each substep (forces added inside a Bullet
// substep would accumulate across substeps). water_force() reports them.
//
// Body to water: the swept displacement. The node heights form a surface that passes
// through bodies (the body hides it). Each substep, for every node, ds = s(new pose) -
// s(old pose) is the change of the body's submerged length in that node's cell (the mean
// over samples_per_cell^2 sub-samples of the cell), both taken at the current water
// height; ds is smoothed with a volume-conserving [1 2 1]/4 kernel (smoothing_passes) and
// displacement_gain * ds is added to the same nodes' heights. The swept change, not the
// total, keeps the water's own motion from feeding back into itself; tracking starts from
// the pose at add_body, so the first substep does not dump the whole submerged volume. A
// body sliding sideways makes a wake. A body at rest costs no displacement work: its
// envelopes are not sampled again until its pose moves by more than 1e-3 of a cell from
// the pose they were last sampled at (the motion is then displaced whole, so none is lost).
//
// The water under every body is kept awake (Surface::wake), so sleeping tiles never hide
// a body's water.
//
// add_body() checks the body: a finite pose, a shape the water can take, a positive volume
// (InvalidSetting naming what is wrong). A body whose pose breaks later (non-finite, not a
// rotation, farther than 1e9 m from the origin along an axis), or faster than max_speed, is
// skipped for that substep and counted in stats().skipped_bodies.
//
// Lifetimes: add_body of a body already added replaces it (added once); remove_body of a
// body not added does nothing; a body taken out of the world or deleted without
// remove_body is dropped at the next substep (stats().lost_bodies; see terrain_coupling.h
// for the one case this cannot tell). The world and the surface must outlive the coupling,
// or detach() is called first. A body may be in a water coupling and a terrain coupling at
// once (a body on a beach: the terrain bears it, the water floats it). It may be in several water couplings of one
// world only if their surfaces do not overlap (each node standing for the cell of side h around it), else both would
// float it: add_body of a body that another water coupling of the same world holds over an overlapping surface throws
// InvalidSetting naming the body and both surfaces' rectangles, and changes nothing.

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <BulletDynamics/Dynamics/btActionInterface.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include "shore/bullet/buoyancy.h"
#include "shore/bullet/config.h"
#include "shore/bullet/ground_frame.h"
#include "shore/water/surface.h"

class btMultiBodyLinkCollider;
class btRaycastVehicle;

namespace shore::terrain {
class Terrain;
}

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

struct WaterCouplingSettings {
  FluidSettings fluid;             ///< density is taken from the surface's settings
  double displacement_gain = 0.5;  ///< share of the swept displacement given to the nodes, [0, 1]
  int smoothing_passes = 2;        ///< [1 2 1]/4 smoothing passes of the displacement, in [0, 8]
  double max_speed = 500.0;        ///< m/s: faster bodies (or non-finite poses) are skipped and counted
  bool step_water = true;          ///< step the surface inside every substep (false: the caller does)
  /// Where the water lies in the world (shore/bullet/ground_frame.h): the identity for a
  /// Z-up world, GroundFrame::y_up() for a Y-up one; the same as the terrain coupling's
  /// when both share a world. Buoyancy lifts along the frame's up; water_force is in world
  /// coordinates.
  GroundFrame frame;
  void validate() const;
};

struct WaterCouplingStats {
  std::int64_t substeps = 0;
  std::int64_t skipped_bodies = 0;
  /// Bodies dropped because the world no longer held them (taken out of it or deleted
  /// without remove_body; noticed by address at the next substep, never read; total).
  std::int64_t lost_bodies = 0;
  int water_substeps = 0;         ///< internal substeps the surface took in the last substep
  double coupling_seconds = 0.0;  ///< last substep: buoyancy, drag, displacement
  double water_seconds = 0.0;     ///< last substep: the surface's own step
  double displaced_volume = 0.0;  ///< m^3 added to the water in total (signed)
};

/// Per-body choices.
struct WaterBodySettings {
  bool disturb = true;  ///< the body displaces water: it makes rings and a wake (false: it only floats)
};

class WaterCoupling : public btActionInterface {
 public:
  /// Adds itself to world (world.addAction) and removes itself when destroyed. The surface
  /// and world must outlive it (or call detach() first).
  WaterCoupling(btDiscreteDynamicsWorld& world, water::Surface& surface, WaterCouplingSettings settings = {});
  ~WaterCoupling() override;
  WaterCoupling(const WaterCoupling&) = delete;
  WaterCoupling& operator=(const WaterCoupling&) = delete;

  /// The body floats and (by default) disturbs the water. Throws InvalidSetting for a null
  /// body, a non-finite pose, an unsupported shape or one of zero volume, after detach(),
  /// or for a body another water coupling of this world holds over an overlapping surface.
  /// Adding a body again replaces its settings.
  void add_body(btRigidBody* body, WaterBodySettings body_settings = {});
  /// Does nothing for a body not added (or removed already).
  void remove_body(const btCollisionObject* body);
  /// A btMultiBody's base or link (its collider), with add_body's choices: buoyancy and
  /// drag act on the whole multibody through its Jacobian at the link's centre of mass.
  /// The world must be a btMultiBodyDynamicsWorld holding the multibody and the collider.
  /// Throws InvalidSetting as add_body does, and for another kind of world, a multibody or
  /// collider not in the world, a non-finite joint velocity, or a link this coupling
  /// holds already (remove_body it first to change its settings). remove_body and
  /// water_force take links too.
  void add_link(btMultiBodyLinkCollider* link, WaterBodySettings body_settings = {});
  /// A btRaycastVehicle's wheels in the water: each wheel is a cylinder of its radius and
  /// `wheel_widths[k]` (m, in (0, 10]) at the pose its ray found, floated, dragged and
  /// making waves and a wake like a body (`body_settings` for each), its push acting on the
  /// chassis at the wheel. The chassis is added apart (add_body) if it should float too.
  /// Throws InvalidSetting for a null vehicle, one added already (here or in another water
  /// coupling of this world), a width count other than the wheel count, a width out of
  /// range, or after detach(). A vehicle whose chassis leaves the world is dropped at the
  /// next substep (stats().lost_bodies counts each wheel); remove_vehicle before deleting
  /// it. The wheels are in checkpoints after the bodies added before them, in order.
  void add_vehicle(btRaycastVehicle* vehicle, std::span<const double> wheel_widths,
                   WaterBodySettings body_settings = {});
  /// Does nothing for a vehicle not added.
  void remove_vehicle(const btRaycastVehicle* vehicle);
  /// The water's force on wheel k of an added vehicle in the last substep (zeros for a
  /// vehicle not added or a bad index), in world coordinates.
  [[nodiscard]] BodyWater wheel_water(const btRaycastVehicle* vehicle, int wheel) const;
  /// Takes the coupling out of its world (the action removed, the bodies let go). After it
  /// the world may be destroyed before the coupling.
  void detach();

  void updateAction(btCollisionWorld* world, btScalar substep) override;
  /// Buoyancy centres and forces and the water grid's outline, as the drawer's debug mode
  /// bits ask (shore/bullet/debug_draw.h).
  void debugDraw(btIDebugDraw* drawer) override;

  /// Fixes every node over ground higher than the water's rest level (a shoreline): waves
  /// reflect there. Returns the number of fixed nodes.
  int fix_shoreline(const terrain::Terrain& ground);

  [[nodiscard]] const WaterCouplingStats& stats() const noexcept { return stats_; }
  [[nodiscard]] const WaterCouplingSettings& settings() const noexcept { return settings_; }
  [[nodiscard]] const water::Surface& surface() const noexcept { return surface_; }
  /// The added bodies' (and links') collision objects, in the order added; not wheels.
  [[nodiscard]] std::vector<const btCollisionObject*> bodies() const;
  /// Submerged volume of a body in the last substep (m^3), 0 if unknown.
  [[nodiscard]] double submerged_volume(const btCollisionObject* body) const;
  /// The water's force and torque on a body in the last substep (zeros if unknown). For a
  /// kinematic or static body (mass 0) they are reported but not applied.
  [[nodiscard]] BodyWater water_force(const btCollisionObject* body) const;

  /// The coupling's own state for a checkpoint (docs/checkpoints.md): per body the
  /// envelopes and pose its displacement was last taken from and its last forces; the
  /// totals of stats(). Not the surface (Surface::save_state).
  [[nodiscard]] std::vector<unsigned char> save_state() const;
  /// Restores save_state's bytes into a coupling built the same way (the same bodies added
  /// in the same order). FileError naming `source`, the coupling unchanged, for bytes of
  /// another version, truncated or corrupt ones, or other bodies.
  void restore_state(std::span<const unsigned char> bytes, const std::string& source);

  struct Parts;  ///< internal: the bodies and scratch (bullet/src/water_coupling_parts.h)

 private:
  btDiscreteDynamicsWorld& world_;
  water::Surface& surface_;
  WaterCouplingSettings settings_;
  WaterCouplingStats stats_;
  std::unique_ptr<Parts> parts_;
  bool detached_ = false;
};

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
