#pragma once
// Internal: what a TerrainCoupling keeps besides its settings and statistics, and the
// stages of its substep (docs/ARCHITECTURE.md, "One substep"). The stages are defined by
// job: the substep's orchestration and each body's path through it in terrain_coupling.cpp,
// bodies' lifetimes in terrain_coupling_bodies.cpp, the checkpoint in
// terrain_coupling_state.cpp.

#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>

#include "body_registry.h"
#include "coupled_body.h"
#include "raycast_wheels.h"
#include "shore/bullet/envelope.h"
#include "shore/bullet/terrain_coupling.h"
#include "shore/bullet/terrain_tiles.h"
#include "shore/terrain/terrain.h"
#include "step_clock.h"
#include "terrain_body.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

struct TerrainCoupling::Parts {
  using Entry = coupling_detail::BodyRegistry<coupling_detail::TerrainBody>::Entry;

  Parts(btDiscreteDynamicsWorld& world, terrain::Terrain& terrain, const TerrainCouplingSettings& settings,
        TerrainCouplingStats& stats);

  btDiscreteDynamicsWorld& world;
  terrain::Terrain& terrain;
  const TerrainCouplingSettings& settings;
  TerrainCouplingStats& stats;
  coupling_detail::BodyRegistry<coupling_detail::TerrainBody> bodies;
  coupling_detail::RaycastWheels wheels;  ///< the wheels of added btRaycastVehicles
  TerrainTiles tiles;
  EnvelopeRasterizer rasterizer;
  coupling_detail::StepClock clock;
  std::vector<terrain::Imprint> imprints;  ///< this substep's, one per body that presses
  std::vector<double> base_scratch;        ///< untouched ground under an envelope
  bool rigid = false;                      ///< rigid material: Bullet's heightfield contact
  /// The ground's frame is not the world's (settings.frame): world poses and points are
  /// taken into ground coordinates by to_ground before the terrain reads them.
  bool framed = false;
  btTransform to_ground = btTransform::getIdentity();

  /// Where cover_bodies last covered each moving object: its bounding box's centre (ground
  /// coordinates) and the pass that saw it. How far an object moved in a substep, for those
  /// Bullet knows no velocity of (ghost objects, bodies moved by hand).
  struct CoveredAt {
    btVector3 centre;
    std::uint64_t pass = 0;
  };
  std::unordered_map<const btCollisionObject*, CoveredAt> covered_at;
  std::uint64_t cover_pass = 0;  ///< cover_bodies' calls so far

  // ---- the substep (terrain_coupling.cpp) ----
  /// Ground under every object that moves (settings.cover_all_bodies) or every added body:
  /// its bounding box grown by cover_margin and twice its motion in a substep (its speed's,
  /// or the distance it moved since the last substep, whichever is more).
  void cover_bodies(double h);
  /// A world point or pose in the ground's coordinates.
  [[nodiscard]] btVector3 in_ground(const btVector3& world_point) const {
    return framed ? to_ground(world_point) : world_point;
  }
  [[nodiscard]] btTransform in_ground(const btTransform& world_pose) const {
    return framed ? to_ground * world_pose : world_pose;
  }
  /// A ghost object (a character controller's capsule, a trigger) that collides with static
  /// objects collides with soft tiles too: their group is terrain_filter_bit, which the
  /// filters a game copies from Bullet's demos leave out.
  void show_soft_tiles(btCollisionObject& object);
  /// A point on this coupling's ground (a raycast wheel's contact: Bullet's vehicle does
  /// not say what its ray hit).
  [[nodiscard]] bool on_terrain(const btVector3& world_point) const;
  /// One body's path through the substep, in two parts: sanity and its contact's push
  /// (serve_push), then, once every body's push is solved, its envelope made or kept and
  /// its imprint (serve_press).
  void serve_push(Entry& e, double h);
  void serve_press(Entry& e, double h, bool deforms);
  void solve_contact(Entry& e, double h);
  /// The links of one multibody, each solved once as a body of its own (one after another,
  /// each taking the others' pushes as they then were), solved again in turn, alternately
  /// backward and forward, each taking out its own last push first: block Gauss-Seidel over
  /// the multibody's links, so none keeps the share of the load it took by being first.
  void solve_links_together(double h);
  /// Advances each solved body's contact memory (its columns' shear) with its final solve.
  void advance_memories(double h);
  void step_terrain();
  /// The terrain's changes into the tiles; bodies over them woken; fallen bodies rescued.
  void push_changes();

  // ---- envelopes (terrain_coupling.cpp) ----
  void rasterize(Entry& e);
  /// What the body presses in a substep the terrain steps: its envelope, or, if it moved
  /// farther than a quarter of its footprint along its travel since the terrain last
  /// stepped, its envelope swept from there (the union of the envelopes at up to 16 poses
  /// along the way, the last its present one).
  [[nodiscard]] const EnvelopeRaster& pressed(Entry& e);
  [[nodiscard]] bool can_rasterize(const Entry& e) const;
  [[nodiscard]] bool needs_envelope(const Entry& e, double h) const;
  [[nodiscard]] bool drifted(const Entry& e) const;
  [[nodiscard]] bool overlaps_region(const coupling_detail::CoupledBody& body) const;
  void clip_to_region(EnvelopeRaster& envelope) const;

  // ---- bodies (terrain_coupling_bodies.cpp) ----
  /// Throws InvalidSetting (`what`: the call; `kind`: "body" or "link") if another terrain
  /// coupling of this world holds the object over an overlapping region.
  void refuse_if_held_elsewhere(const TerrainCoupling& self, const btCollisionObject& object, const char* what,
                                const char* kind) const;
  /// The coupling's record of an object joining with these settings; a deforming shape is
  /// checked once here (InvalidSetting if it cannot be rasterized).
  [[nodiscard]] coupling_detail::TerrainBody record_for(const btCollisionObject& object,
                                                        const TerrainBodySettings& body_settings) const;
  /// A checked body joins: (owned: its soil contact is Shore's) its filter bit taken, its
  /// envelope made and tiles put under it.
  void enroll(std::unique_ptr<coupling_detail::CoupledBody> coupled, coupling_detail::TerrainBody record, bool owned);
  [[nodiscard]] bool sane(const coupling_detail::CoupledBody& body) const;
  /// A dynamic deforming body does not collide with soft tiles through Bullet (it may have
  /// been switched from kinematic since it was added).
  void own_terrain_contact(coupling_detail::CoupledBody& body);
  void take_filter_bit(coupling_detail::CoupledBody& body);
};

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
