#pragma once
// Two-way coupling of Bullet rigid bodies with the deformable soil.
//
// Add it to an existing btDiscreteDynamicsWorld; it is a btActionInterface, so its work
// runs inside every internal substep of stepSimulation(dt, maxSubSteps, fixedStep), after
// the solver and integration and before the next substep's collision detection:
//
//   shore::terrain::Terrain soil(settings);
//   shore::bullet::TerrainCoupling ground(world, soil);   // adds itself to the world
//   ground.add_body(wheel);                                // this body deforms the soil
//   world.stepSimulation(1.0 / 60, 8, 1.0 / 240);
//
// What Shore does with added bodies:
// - Soft soil: Shore, not Bullet, makes their contact with the ground (Bullet does not
//   collide them with the soil tiles: see soil_filter_bit). Each substep the soil says
//   where and how hard it can push (terrain::Terrain::contact): along the underside's normal
//   under the body, at most Bekker's yield pressure times the substep; horizontally from
//   the walls of ruts and craters; and along the surface with Janosi-Hanamoto's shear,
//   which grows with each column's shear displacement. Shore then finds the impulses that
//   stop the body's approach and slip where the soil can, and lets the soil yield where it
//   cannot (SoilContactSettings); the soil never pulls. Then the soil is pressed where the
//   body went. Craters do not depend on the substep; columns on bedrock bear anything.
// - The soil deforms once per soil_interval (120 Hz by default), the contact is solved every
//   substep; between soil steps a moving body's contact follows it (follow_drift).
// - Rigid materials (Material::rigid): Bullet's ordinary heightfield contact.
// - Kinematic bodies press the soil geometrically; bodies at rest press nothing new but
//   keep eroding soil out from under them, and cost almost nothing (their contact is kept).
// - A body driven below bedrock in one substep is lifted back (counted in stats().rescues).
// - add_body() checks the body's shape once (InvalidSetting if it cannot be rasterized or
//   has no size); a body with a broken pose (non-finite, not a rotation, farther than 1e9 m
//   from the origin along an axis) or faster than max_speed is skipped for that substep and
//   counted in stats().skipped_bodies.
// Bodies that are not added collide with the soil's tiles through Bullet as with rigid ground.
//
// Lifetimes and misuse (issue 21; tests/bullet/test_coupling_misuse.cpp):
// - add_body of a body already added replaces its settings (it is added once);
//   remove_body of a body never added, or removed already, does nothing. A removed body
//   collides with the tiles through Bullet again.
// - Removing a body while it is in contact is fine: its contact state goes with it.
// - A body taken out of the world (removeRigidBody), or deleted, without remove_body is
//   noticed at the next substep by its address no longer being in the world (the coupling
//   never reads it) and dropped, counted in stats().lost_bodies. A new body allocated at
//   the deleted one's address before that substep would be taken for it: call
//   remove_body first, as Bullet wants constraints removed before their bodies.
// - A body's shape or its scaling changed after add_body is checked again at the next
//   substep; while the soil cannot take it, the body is skipped (skipped_bodies).
// - A body switched between kinematic and dynamic is treated as what it is at each substep
//   (a dynamic one gets the soil's contact instead of Bullet's tile contact).
// - A sleeping body is woken when the soil under it changes (an edit, or another body).
// - The world and the soil must outlive the coupling; to destroy the world first, call
//   detach() before (the destructor then touches nothing).
// - A body may be in several terrain couplings of one world only if their regions are
//   disjoint (soils side by side, as in the vehicle scene; regions that only share an edge
//   are disjoint): where two overlapped, both soils would push it. add_body of a body that
//   another terrain coupling of the same world holds, with a region overlapping this one's,
//   throws InvalidSetting naming the body (its address and shape) and both regions, and
//   changes nothing; remove_body it from the other first. Couplings of other worlds, and
//   detached ones, are not looked at. Being in a terrain coupling and a water coupling at
//   once is fine (a body on a beach: water_coupling.h).

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include <BulletDynamics/Dynamics/btActionInterface.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include "shore/bullet/config.h"
#include "shore/bullet/envelope.h"
#include "shore/bullet/terrain_tiles.h"
#include "shore/core/byte_io.h"
#include "shore/core/envelope.h"
#include "shore/terrain/terrain.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace soil_detail {
struct RigidBody;
struct SolveResult;
}  // namespace soil_detail

/// Per-body choices.
struct BodySoilSettings {
  bool deform = true;  ///< the body presses the soil (false: it only feels the ground)
  /// A deforming body throws the soil it touches fast into the air (the soil's
  /// Material::spray and TerrainSettings::spray; shore/terrain/spray.h).
  bool spray = true;
  bool enable_ccd = true;  ///< turn on Bullet's continuous collision for fast impacts
  /// With enable_ccd: Bullet's CCD motion threshold and swept-sphere radius, as shares of
  /// the thinnest side of the body's bounding box; each in (0, 1].
  double ccd_motion_share = 0.25;
  double ccd_sphere_share = 0.2;
  void validate() const;
};

/// How the soil's contact with a body is solved (see shore/terrain/contact.h).
struct SoilContactSettings {
  /// Columns per side of a contact block: the soil's push is solved per block of
  /// block_columns x block_columns columns (1: per column, exact but slower), in [1, 64].
  int block_columns = 4;
  /// Projected Gauss-Seidel sweeps over the blocks per substep, warm-started, in [1, 1000].
  int iterations = 6;
  /// Sweeps for a body at rest, whose contact is kept from the last substep and whose solve
  /// starts from last substep's impulses (they already hold it), in [1, 1000].
  int resting_iterations = 2;
  /// Sub-cell coverage at the edges of a footprint: a body covering part of a column bears
  /// on that part only, so sinkage does not depend on where its edges fall.
  bool sub_cell_coverage = true;
  /// Cells. Between soil steps (TerrainCouplingSettings::soil_interval) a moving body's
  /// contact is kept from the substep before and follows the body: each block's capacity
  /// and elastic push change with the body's approach along its normal (Bekker's dp/dz).
  /// Kept while no block's point has moved further than follow_drift cells since the
  /// contact was built; then, and after every soil step, it is built afresh from the body's
  /// envelope. In [0, 2]; 0: built every substep.
  double follow_drift = 0.5;
  /// m/s: a body slower than this is settling, and its contact is built afresh every
  /// substep: at rest-sized motions the set of columns it touches changes from substep to
  /// substep (a plate settling in rigid-plastic mud rocks by 0.1 mm, more than
  /// TerrainSettings::contact_tolerance, and a kept contact let it creep 27 % deeper than
  /// Bekker's). >= 0.
  double follow_speed = 0.1;
  void validate() const;
};

struct TerrainCouplingSettings {
  TerrainTilesSettings tiles;
  SoilContactSettings contact;
  /// Where this soil is. Several Terrain objects (say sand, then mud) can lie side by side,
  /// each with its own coupling and region; put region edges on tile edges (multiples of
  /// the soil's tile_columns * cell from its origin) so tiles meet exactly.
  Region region;
  double cover_margin = 0.25;  ///< m kept covered by tiles around every dynamic body's AABB, > 0
  double max_speed = 500.0;    ///< m/s: a body faster than this (or with a non-finite pose) is skipped and counted
  /// A body the soil holds that moves slower than rest_speed and turns slower than
  /// rest_spin is at rest: it presses nothing new (pressing again would only re-press soil
  /// that slid back beside it). Both > 0.
  double rest_speed = 1e-3;  ///< m/s
  double rest_spin = 1e-2;   ///< rad/s
  /// Every dynamic body in the world gets ground under it (tiles), not only added ones.
  bool cover_all_bodies = true;
  /// Lift a body whose lowest point fell below bedrock back onto the surface (counted).
  bool rescue_fallthrough = true;
  /// s: how often the soil deforms. Bodies' imprints are pressed, the displaced soil moved
  /// and eroded, spray stepped and the tiles' heights pushed once per round(soil_interval /
  /// substep) substeps (at least 1), with their summed time; the soil's push on each body is
  /// still found and solved every substep, from the body's pose over the soil as it stands
  /// (a column the body has entered since bears its sinkage plus how deep the body lies below
  /// its top), so bearing, sinkage and resistance keep Bekker's law. In [0, 0.125]; 0: every
  /// substep. The default steps the soil at 120 Hz: every second substep at 1/240 s, every
  /// substep at 1/120 s and longer (docs/terrain.md, "Soil interval").
  double soil_interval = 1.0 / 120;
  /// Broadphase filter bit of soft-soil tiles. Shore owns the normal contact of added
  /// bodies with soft soil, so this bit is cleared from their collision mask (and restored
  /// by remove_body); other bodies collide with the tiles through Bullet as with rigid
  /// ground. Pick a bit your own filters do not use. Rigid materials use StaticFilter.
  int soil_filter_bit = 1 << 13;
  void validate() const;
};

/// Counters and timings of the last substep and totals since creation.
struct TerrainCouplingStats {
  std::int64_t substeps = 0;
  std::int64_t skipped_bodies = 0;  ///< body-substeps skipped for a broken pose or an absurd speed (total)
  std::int64_t yields = 0;          ///< body-substeps in which the soil yielded (total)
  std::int64_t rescues = 0;         ///< bodies lifted back above bedrock (total)
  /// Bodies dropped because the world no longer held them (removed or deleted without
  /// remove_body; total).
  std::int64_t lost_bodies = 0;
  std::int64_t vertices_pushed = 0;  ///< heightfield vertices written (total)
  std::int64_t soil_steps = 0;       ///< substeps in which the soil deformed (total; soil_interval)
  /// Body-substeps solved on a contact kept from the substep before (total; follow_drift).
  std::int64_t contacts_followed = 0;
  /// J, total: work the coupled bodies did on the soil, pressing and shearing it (the
  /// kinetic energy the soil's impulses took from them).
  double plastic_work = 0.0;
  double shear_work = 0.0;  ///< J, total: the part of plastic_work done shearing the soil
  // last substep, seconds of wall time
  double envelope_seconds = 0.0;
  double terrain_seconds = 0.0;
  double push_seconds = 0.0;
  double reaction_seconds = 0.0;
  int active_columns = 0;  ///< columns the soil step worked on (0 in a substep without one)
  int erosion_passes = 0;
  int resting_bodies = 0;  ///< bodies at rest that kept their contact this substep (cheap)
};

/// The soil's push on one body in the last substep (zero if it had no contact).
struct SoilForce {
  btVector3 force{0, 0, 0};         ///< N, world frame
  btVector3 torque{0, 0, 0};        ///< N m about the body's centre of mass
  btVector3 normal_force{0, 0, 0};  ///< N, the part of force along the soil's normals (the rest is shear)
  int contact_columns = 0;          ///< columns the body's underside touched
  bool yielded = false;             ///< the soil could not stop the body's approach somewhere
};

class TerrainCoupling : public btActionInterface {
 public:
  /// Adds itself to world (world.addAction) and removes itself when destroyed. The soil
  /// and world must outlive it.
  TerrainCoupling(btDiscreteDynamicsWorld& world, terrain::Terrain& soil, TerrainCouplingSettings settings = {});
  ~TerrainCoupling() override;
  TerrainCoupling(const TerrainCoupling&) = delete;
  TerrainCoupling& operator=(const TerrainCoupling&) = delete;

  /// The body presses the soil (dynamic: by the momentum rule; kinematic: geometrically).
  /// Tiles under it are created at once. Throws InvalidSetting for a null body, a dynamic
  /// body not yet in the world, or (with deform) a shape that cannot be rasterized.
  /// Adding a body again replaces its settings. Throws InvalidSetting after detach(), and
  /// for a body another terrain coupling of this world holds over an overlapping region.
  void add_body(btRigidBody* body, BodySoilSettings body_settings = {});
  /// Does nothing for a body not added (or removed already).
  void remove_body(btRigidBody* body);
  /// Takes the coupling out of its world: its tiles and itself (the action) are removed,
  /// the bodies are let go. After it the world may be destroyed before the coupling.
  void detach();

  void updateAction(btCollisionWorld* world, btScalar substep) override;
  /// Contact columns, soil reaction vectors and tile outlines, as the drawer's debug mode
  /// bits ask (shore/bullet/debug_draw.h).
  void debugDraw(btIDebugDraw* drawer) override;

  [[nodiscard]] const TerrainCouplingStats& stats() const noexcept { return stats_; }
  /// The soil's force and torque on an added body in the last substep (zero for others).
  [[nodiscard]] SoilForce soil_force(const btRigidBody* body) const;
  [[nodiscard]] const TerrainCouplingSettings& settings() const noexcept { return settings_; }
  /// The added bodies, in the order added.
  [[nodiscard]] std::vector<btRigidBody*> bodies() const;
  [[nodiscard]] btDiscreteDynamicsWorld& world() const noexcept { return world_; }
  [[nodiscard]] TerrainTiles& tiles() noexcept { return tiles_; }
  [[nodiscard]] terrain::Terrain& soil() noexcept { return soil_; }

  /// The coupling's own state for a checkpoint (docs/checkpoints.md): per added body its
  /// envelope and the pose it was made at, and the soil contact's kept state (blocks and
  /// their impulses, patch, shear displacement and its length, last force, rest); the tiles (which exist, their
  /// bounds and heights); the totals of stats(). Not the soil (Terrain::save_bytes).
  [[nodiscard]] std::vector<unsigned char> save_state() const;
  /// Restores save_state's bytes into a coupling built the same way (the same bodies added
  /// in the same order, the same settings), after its soil was restored; it takes the
  /// soil's pending changes (the load's), so save between steps, not after editing the
  /// soil by hand (such an edit would not wake bodies at rest after the restore). FileError naming
  /// `source`, the coupling unchanged, for bytes of another version, truncated or corrupt
  /// ones, or another number or kind of bodies.
  void restore_state(std::span<const unsigned char> bytes, const std::string& source);

 private:
  struct BodyContact;  // the soil contact's state kept between substeps (terrain_coupling.cpp)
  // A contact's bytes in a checkpoint: next to BodyContact, so a new field is saved too.
  static void save_contact(const BodyContact& c, ByteWriter& w);
  static void restore_contact(ByteReader& r, BodyContact& c, std::size_t envelope_columns, std::uint32_t version);
  static void check_contact(const ByteReader& r, const BodyContact& c, std::size_t envelope_columns);
  struct Body {
    Body();
    ~Body();
    Body(Body&&) noexcept;
    Body& operator=(Body&&) noexcept;
    btRigidBody* body = nullptr;
    BodySoilSettings settings;
    EnvelopeRaster envelope;  // at envelope_pose: this substep's imprint, the next one's contact
    btTransform envelope_pose;
    bool pressed = true;          // the soil has stepped with the envelope since it was made (soil_interval)
    bool envelope_fresh = false;  // made since the body's contact was built (follow_drift)
    double reach = 0.0;           // m, from check_rasterizable
    // The shape and scaling reach was found for; shape_fits: the soil can take it.
    const btCollisionShape* shape = nullptr;
    btVector3 scaling{1, 1, 1};
    bool shape_fits = true;
    bool seen_in_world = false;  // the world held the body once (lost when it no longer does)
    std::unique_ptr<BodyContact> contact;
  };
  [[nodiscard]] bool holds(const btRigidBody* body) const;
  /// Throws InvalidSetting if another coupling of this world holds the body and its region
  /// overlaps this one's.
  void refuse_overlapping_coupling(const btRigidBody& body) const;
  bool body_is_sane(const btRigidBody& body) const;
  /// Checks a deforming body's shape again if it or its scaling changed since add_body.
  bool shape_still_fits(Body& b) const;
  /// A dynamic deforming body must not collide with soft tiles through Bullet (it may have
  /// been switched from kinematic).
  void own_tile_contact(Body& b);
  /// The cheap per-substep test that rasterizing the body at its pose cannot fail.
  bool can_rasterize(const Body& b) const;
  void cover_bodies(double substep);
  void rasterize(Body& b);
  [[nodiscard]] bool overlaps_region(const btRigidBody& body) const;
  void drop_tile_pairs(btBroadphaseProxy* proxy);
  void clip_to_region(EnvelopeRaster& env) const;
  /// The soil's push on one dynamic body (shore/terrain/contact.h); returns true if the
  /// soil yielded somewhere.
  bool react(Body& b, double substep);
  /// A body at rest held by last substep's soil impulse; false if that no longer holds it.
  bool hold_at_rest(Body& b, double substep);
  /// Builds the body's contact blocks from the soil at its envelope.
  void gather_contact(Body& b);
  void limit_to_carried(Body& b);
  void stop_sway(const btRigidBody& body, soil_detail::RigidBody& rb, soil_detail::SolveResult& r) const;
  /// What each touching column keeps for the next substep: its shear displacement and, where
  /// it unloads elastically, the pressure it carried.
  void advance_memory(Body& b, const soil_detail::RigidBody& rb, double h);
  /// True if the body has moved away from the pose its envelope was made at.
  [[nodiscard]] bool drifted(const Body& b) const;
  void rescue_fallen_bodies();
  void keep_above_bedrock(Body& b);
  void wake_bodies_over(const std::vector<GridRect>& changed);
  /// Whether the body needs a fresh envelope at the end of this substep though the soil does
  /// not step: it has no contact to follow, or its contact has drifted too far.
  [[nodiscard]] bool needs_envelope(const Body& b, double substep) const;
  /// Advances the soil's clock by one substep; true when the soil steps in it.
  bool soil_due(double substep);
  /// Steps the soil with this substep's imprints and the time since its last step.
  void step_soil();

  std::vector<double> base_scratch_;  // untouched ground under an envelope

  btDiscreteDynamicsWorld& world_;
  terrain::Terrain& soil_;
  TerrainCouplingSettings settings_;
  TerrainTiles tiles_;
  EnvelopeRasterizer rasterizer_;
  std::vector<Body> bodies_;
  std::vector<terrain::Imprint> imprints_;
  TerrainCouplingStats stats_;
  // The soil's clock (soil_interval): substeps and seconds since its last step.
  int substeps_since_soil_ = 0;
  double time_since_soil_ = 0.0;
  bool rigid_ = false;
  bool detached_ = false;
};

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
