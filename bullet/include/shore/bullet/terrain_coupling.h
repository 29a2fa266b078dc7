#pragma once
// Two-way coupling of Bullet bodies with the deformable terrain (shore::terrain::Terrain).
//
// Add it to an existing btDiscreteDynamicsWorld; it is a btActionInterface, so its work
// runs inside every internal substep of stepSimulation(dt, maxSubSteps, fixedStep), after
// the solver and integration and before the next substep's collision detection:
//
//   shore::terrain::Terrain sand(settings);
//   shore::bullet::TerrainCoupling ground(world, sand);   // adds itself to the world
//   ground.add_body(wheel);                                // this body deforms the terrain
//   world.stepSimulation(1.0 / 60, 8, 1.0 / 240);
//
// What Shore does with added bodies (docs/ARCHITECTURE.md, "One substep"):
// - Soft soil: Shore, not Bullet, makes their contact with the ground (Bullet does not
//   collide them with the terrain's tiles: terrain_filter_bit). Each substep the terrain
//   says where and how hard it can push (terrain::Terrain::contact): along the underside's
//   normal at most Bekker's yield pressure times the substep, horizontally from the walls
//   of ruts and craters, along the surface with Janosi-Hanamoto's shear. Shore finds the
//   impulses that stop the body's approach and slip where the terrain can and lets it
//   yield where it cannot; it never pulls. The terrain deforms once per step_interval.
// - Rigid materials (Material::rigid): Bullet's ordinary heightfield contact.
// - Kinematic bodies press the terrain by their shape; bodies at rest press nothing new
//   and cost almost nothing.
// - A body driven below bedrock in one substep is lifted back (stats().rescues).
// - Bodies that are not added collide with the tiles through Bullet as with rigid ground.
//
// Bad input and lifetimes (tests/bullet/test_coupling_misuse.cpp):
// - add_body checks the body's shape once; a body whose pose breaks later (non-finite, not
//   a rotation, farther than 1e9 m from the origin along an axis), or faster than
//   max_speed, is skipped for that substep (stats().skipped_bodies). A shape or scaling
//   changed after add_body is checked again at the next substep.
// - add_body of a body already added replaces its settings; remove_body of a body not added
//   does nothing; a removed body collides with the tiles through Bullet again.
// - A body taken out of the world, or deleted, without remove_body is noticed at the next
//   substep by its address no longer being in the world (never read) and dropped
//   (stats().lost_bodies). A new body allocated at the deleted one's address before that
//   substep would be taken for it: call remove_body first.
// - A body switched between kinematic and dynamic is treated as what it is each substep.
// - A sleeping body is woken when the terrain under it changes.
// - The world and the terrain must outlive the coupling; to destroy the world first, call
//   detach() before.
// - A body may be in several terrain couplings of one world only if their regions are
//   disjoint (regions that only share an edge are): add_body refuses a body another
//   coupling of the same world holds over an overlapping region (InvalidSetting naming the
//   body and both regions). A terrain coupling and a water coupling at once is fine.

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <BulletDynamics/Dynamics/btActionInterface.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include "shore/bullet/config.h"
#include "shore/bullet/envelope.h"
#include "shore/bullet/ground_frame.h"
#include "shore/bullet/terrain_tiles.h"
#include "shore/core/byte_io.h"
#include "shore/core/envelope.h"
#include "shore/terrain/terrain.h"

class btRaycastVehicle;
class btMultiBodyLinkCollider;

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

class SoilRaycaster;

/// Per-body choices.
struct TerrainBodySettings {
  bool deform = true;  ///< the body presses the terrain (false: it only feels the ground)
  /// A deforming body throws the soil it touches fast into the air (the terrain's
  /// Material::spray and TerrainSettings::spray; shore/terrain/spray.h).
  bool spray = true;
  bool enable_ccd = true;  ///< turn on Bullet's continuous collision for fast impacts
  /// With enable_ccd: Bullet's CCD motion threshold and swept-sphere radius, as shares of
  /// the thinnest side of the body's bounding box; each in (0, 1].
  double ccd_motion_share = 0.25;
  double ccd_sphere_share = 0.2;
  void validate() const;
};

/// How the terrain's contact with a body is solved (see shore/terrain/contact.h).
struct TerrainContactSettings {
  /// Columns per side of a contact block: the terrain's push is solved per block of
  /// block_columns x block_columns columns (1: per column, exact but slower), in [1, 64].
  int block_columns = 4;
  /// Projected Gauss-Seidel sweeps over the blocks per substep, warm-started, in [1, 1000]:
  /// at least these; while the last sweep still changed some block's speed by more than
  /// 1 mm/s the solve sweeps on, up to 4 times as many (a box landing on rigid-plastic soil
  /// otherwise keeps rolling).
  int iterations = 6;
  /// Sweeps for a body at rest, whose contact is kept from the last substep and whose solve
  /// starts from last substep's impulses (they already hold it), in [1, 1000].
  int resting_iterations = 2;
  /// Sub-cell coverage at the edges of a footprint: a body covering part of a column bears
  /// on that part only, so sinkage does not depend on where its edges fall.
  bool sub_cell_coverage = true;
  /// Cells, in [0, 2]. Between terrain steps (TerrainCouplingSettings::step_interval) a
  /// moving body's contact is kept from the substep before and follows the body (each
  /// block's capacity and elastic push change with the body's approach along its normal)
  /// until some block's point has moved this far since the contact was built; then, and
  /// after every terrain step, it is built afresh from the body's envelope. 0: built every
  /// substep.
  double follow_drift = 0.5;
  /// m/s, >= 0: a body slower than this is settling, and its contact is built afresh every
  /// substep (at rest-sized motions the columns it touches change from substep to substep).
  double follow_speed = 0.1;
  void validate() const;
};

struct TerrainCouplingSettings {
  TerrainTilesSettings tiles;
  TerrainContactSettings contact;
  /// Where this terrain is. Several Terrain objects (say sand, then mud) can lie side by
  /// side, each with its own coupling and region; put region edges on tile edges (multiples
  /// of the terrain's tile_columns * cell from its origin) so tiles meet exactly.
  Region region;
  /// m kept covered by tiles around every moving object's AABB, beyond twice its motion in a
  /// substep (its velocity's, or how far it moved since the last substep), > 0
  double cover_margin = 0.25;
  double max_speed = 500.0;  ///< m/s: a body faster than this (or with a non-finite pose) is skipped and counted
  /// A body the terrain holds that moves slower than rest_speed and turns slower than
  /// rest_spin is at rest: it presses nothing new. Both > 0.
  double rest_speed = 1e-3;  ///< m/s
  double rest_spin = 1e-2;   ///< rad/s
  /// Every object in the world that is not static gets ground under it (tiles), not only
  /// added bodies: other rigid bodies, kinematic bodies, ghost objects (character
  /// controllers' capsules), a raycast vehicle's chassis and so the rays of its wheels.
  bool cover_all_bodies = true;
  /// Lift a body whose lowest point fell below bedrock back onto the surface (counted).
  bool rescue_fallthrough = true;
  /// s, in [0, 0.125]: how often the terrain deforms. Imprints are pressed, the displaced
  /// soil moved and eroded, spray stepped and the tiles' heights pushed once per
  /// round(step_interval / substep) substeps (at least 1), with their summed time; the
  /// terrain's push on each body is still solved every substep, from the body's pose over
  /// the terrain as it stands. 0: every substep. The default deforms at 120 Hz.
  double step_interval = 1.0 / 120;
  /// Columns, in [0, 256]: the soil step works this far around a raycast wheel's rut
  /// (add_vehicle) for the soil it displaces and erodes (terrain::Imprint::margin; 0: the
  /// terrain's active_margin). A wheel's displaced soil lands within a column or two of its
  /// footprint and erosion moves it a column a pass: 2 gives the ruts, sinkage and pull of a
  /// large margin at a smaller soil step (docs/terrain.md, "A raycast wheel's soil region").
  int raycast_wheel_margin = 2;
  /// Broadphase filter bit of soft-soil tiles. Shore owns the normal contact of added
  /// bodies with soft soil, so this bit is cleared from their collision mask (and restored
  /// by remove_body); other bodies collide with the tiles through Bullet as with rigid
  /// ground. Pick a bit your own filters do not use. Rigid materials use StaticFilter.
  int terrain_filter_bit = 1 << 13;
  /// Where the terrain lies in the world (shore/bullet/ground_frame.h): the identity for a
  /// Z-up world, GroundFrame::y_up() for a Y-up one. region and everything the terrain
  /// reports are in the terrain's own coordinates; terrain_force in the world's.
  GroundFrame frame;
  void validate() const;
};

/// Counters and timings of the last substep and totals since creation.
struct TerrainCouplingStats {
  std::int64_t substeps = 0;
  std::int64_t skipped_bodies = 0;  ///< body-substeps skipped for a broken pose or an absurd speed (total)
  std::int64_t yields = 0;          ///< body-substeps in which the terrain yielded (total)
  std::int64_t rescues = 0;         ///< bodies lifted back above bedrock (total)
  /// Bodies dropped because the world no longer held them (removed or deleted without
  /// remove_body; total).
  std::int64_t lost_bodies = 0;
  std::int64_t vertices_pushed = 0;  ///< heightfield vertices written (total)
  std::int64_t terrain_steps = 0;    ///< substeps in which the terrain deformed (total; step_interval)
  /// Body-substeps solved on a contact kept from the substep before (total; follow_drift).
  std::int64_t contacts_followed = 0;
  /// J, total: work the coupled bodies did on the terrain, pressing and shearing it (the
  /// kinetic energy the terrain's impulses took from them).
  double plastic_work = 0.0;
  double shear_work = 0.0;  ///< J, total: the part of plastic_work done shearing the terrain
  // last substep, seconds of wall time
  double envelope_seconds = 0.0;
  double terrain_seconds = 0.0;
  double push_seconds = 0.0;
  double reaction_seconds = 0.0;
  int active_columns = 0;  ///< columns the terrain step worked on (0 in a substep without one)
  int erosion_passes = 0;
  int resting_bodies = 0;  ///< bodies at rest that kept their contact this substep (cheap)
};

/// The terrain's push on one body in the last substep (zero if it had no contact).
struct TerrainForce {
  btVector3 force{0, 0, 0};         ///< N, world coordinates
  btVector3 torque{0, 0, 0};        ///< N m about the body's centre of mass, world coordinates
  btVector3 normal_force{0, 0, 0};  ///< N, the part of force along the terrain's normals (the rest is shear)
  int contact_columns = 0;          ///< columns the body's underside touched
  bool yielded = false;             ///< the terrain could not stop the body's approach somewhere
};

class TerrainCoupling : public btActionInterface {
 public:
  /// Adds itself to world (world.addAction) and removes itself when destroyed. The terrain
  /// and world must outlive it (or call detach() first).
  TerrainCoupling(btDiscreteDynamicsWorld& world, terrain::Terrain& terrain, TerrainCouplingSettings settings = {});
  ~TerrainCoupling() override;
  TerrainCoupling(const TerrainCoupling&) = delete;
  TerrainCoupling& operator=(const TerrainCoupling&) = delete;

  /// The body presses the terrain (dynamic: the terrain pushes back; kinematic: by its
  /// shape alone). Tiles under it are created at once. Throws InvalidSetting for a null
  /// body, a dynamic body not yet in the world, (with deform) a shape that cannot be
  /// rasterized or has no area seen from below, after detach(), and for a body another
  /// terrain coupling of this world holds over an overlapping region. Adding a body again
  /// replaces its settings.
  void add_body(btRigidBody* body, TerrainBodySettings body_settings = {});
  /// Does nothing for a body not added (or removed already).
  void remove_body(const btCollisionObject* body);
  /// A btMultiBody's base or link (its collider), with add_body's choices: it presses and
  /// feels the terrain like a rigid body, and the terrain's impulses act on the whole
  /// multibody through its Jacobian at the link's centre of mass (enable_ccd does nothing:
  /// Bullet makes no continuous collision for links). The world must be a
  /// btMultiBodyDynamicsWorld holding the multibody and the collider. Throws InvalidSetting
  /// for a null link, another kind of world, a multibody or collider not in the world, a
  /// non-finite pose or joint velocity, the shape checks of add_body, after detach(), and
  /// for a link another terrain coupling of this world holds over an overlapping region
  /// or this one holds already (remove_body it first to change its settings). remove_body
  /// and terrain_force take links too. A link whose multibody later leaves the world while
  /// its collider stays, or whose joint velocities turn non-finite, is skipped each substep
  /// (stats().skipped_bodies).
  void add_link(btMultiBodyLinkCollider* link, TerrainBodySettings body_settings = {});
  /// A stock btRaycastVehicle whose wheels press and feel the terrain: each wheel on soft
  /// ground sinks as far as the columns need to carry its suspension force (its ray then
  /// finds the rut it pressed) and meets the columns' compaction resistance. `wheel_widths`
  /// (m, in (0, 10]) gives each wheel's width, in the vehicle's wheel order (Bullet's
  /// vehicle knows only the radius). Traction and side force stay Bullet's m_frictionSlip.
  /// Throws InvalidSetting for a null vehicle, one added already, a width count other
  /// than the wheel count or a width out of range. A vehicle whose chassis leaves the world
  /// is dropped at the next substep (stats().lost_bodies); remove_vehicle before deleting it.
  /// `raycaster`: the SoilRaycaster the vehicle was built with, if it was (null: a stock
  /// raycaster): its wheels then also rise onto soil that carries more than their load
  /// (shore/bullet/soil_raycaster.h). Throws InvalidSetting for a raycaster of another coupling.
  void add_vehicle(btRaycastVehicle* vehicle, std::span<const double> wheel_widths,
                   const SoilRaycaster* raycaster = nullptr);
  void remove_vehicle(const btRaycastVehicle* vehicle);
  /// N, the terrain's push on an added vehicle's wheel along its heading in the last
  /// substep (its compaction resistance: negative against forward motion); 0 for a wheel
  /// off this terrain, a bad index or a vehicle not added.
  [[nodiscard]] double wheel_push(const btRaycastVehicle* vehicle, int wheel) const;
  /// N, the terrain's push on the wheel across it in the last substep, along its axle's
  /// horizontal direction (positive along Bullet's m_wheelAxleWS as steered): the rut
  /// walls' push beyond what Bullet's suspension force along the ray's normal gives. Each
  /// loaded column pushes along its surface's normal, so a wheel drifting into the wall of
  /// a rut is pushed back into it; on an even surface it is zero. 0 for a wheel off this
  /// terrain, a bad index or a vehicle not added.
  [[nodiscard]] double wheel_side_push(const btRaycastVehicle* vehicle, int wheel) const;
  /// Takes the coupling out of its world: its tiles and itself (the action) are removed,
  /// the bodies are let go. After it the world may be destroyed before the coupling.
  void detach();

  void updateAction(btCollisionWorld* world, btScalar substep) override;
  /// Contact columns, terrain reaction vectors and tile outlines, as the drawer's debug mode
  /// bits ask (shore/bullet/debug_draw.h).
  void debugDraw(btIDebugDraw* drawer) override;

  [[nodiscard]] const TerrainCouplingStats& stats() const noexcept { return stats_; }
  /// The terrain's force and torque on an added body in the last substep (zero for others).
  [[nodiscard]] TerrainForce terrain_force(const btCollisionObject* body) const;
  [[nodiscard]] const TerrainCouplingSettings& settings() const noexcept { return settings_; }
  /// The added bodies' collision objects, in the order added.
  [[nodiscard]] std::vector<const btCollisionObject*> bodies() const;
  [[nodiscard]] btDiscreteDynamicsWorld& world() const noexcept { return world_; }
  [[nodiscard]] TerrainTiles& tiles() noexcept;
  [[nodiscard]] terrain::Terrain& terrain() noexcept { return terrain_; }

  /// The coupling's own state for a checkpoint (docs/checkpoints.md): per added body its
  /// envelope and the pose it was made at, and its contact's kept state; the tiles; the
  /// totals of stats(). Not the terrain (Terrain::save_bytes).
  [[nodiscard]] std::vector<unsigned char> save_state() const;
  /// Restores save_state's bytes into a coupling built the same way (the same bodies added
  /// in the same order, the same settings), after its terrain was restored; it takes the
  /// terrain's pending changes (the load's), so save between steps, not after editing the
  /// terrain by hand. FileError naming `source`, the coupling unchanged, for bytes of
  /// another version, truncated or corrupt ones, or another number or kind of bodies.
  void restore_state(std::span<const unsigned char> bytes, const std::string& source);

  struct Parts;  ///< internal: the bodies, tiles and clock (bullet/src/terrain_coupling_parts.h)

 private:
  btDiscreteDynamicsWorld& world_;
  terrain::Terrain& terrain_;
  TerrainCouplingSettings settings_;
  TerrainCouplingStats stats_;
  std::unique_ptr<Parts> parts_;
  bool detached_ = false;
};

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
