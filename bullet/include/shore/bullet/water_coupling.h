#pragma once
// Two-way coupling of Bullet rigid bodies with the spring-mass water surface.
//
//   shore::water::Surface pond(settings);
//   shore::bullet::WaterCoupling water(world, pond);   // adds itself; steps the water
//   water.add_body(box);
//
// Water to body: buoyancy from the submerged length of each sample column (lower and
// upper envelopes against the live water height, 4 x 4 samples per water cell), acting
// at the centre of buoyancy, plus linear and quadratic drag per sample against the
// water's vertical velocity; applied as impulses each substep (buoyancy.h).
//
// Body to water: the swept displacement. The node heights form a surface that passes
// through bodies (the body hides it). Each substep, for every node, ds = s(new pose) -
// s(old pose) is the change of the body's submerged length in that node's cell, both
// taken at the current water height; ds is smoothed with a volume-conserving [1 2 1]/4
// kernel (smoothing_passes) and displacement_gain * ds is added to the same nodes'
// heights. The swept change, not the total, keeps the water's own motion from feeding
// back into itself; tracking starts from the pose at add_body, so the first substep does
// not dump the whole submerged volume. A body sliding sideways makes a wake.
//
// add_body() checks the body's shape once (InvalidSetting if it cannot be rasterized); a
// body with a broken pose or faster than max_speed is skipped for that substep and
// counted in stats().skipped_bodies.

#include <cstdint>
#include <vector>

#include <BulletDynamics/Dynamics/btActionInterface.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include "shore/bullet/buoyancy.h"
#include "shore/bullet/config.h"
#include "shore/bullet/envelope.h"
#include "shore/core/envelope.h"
#include "shore/water/surface.h"

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
  void validate() const;
};

struct WaterCouplingStats {
  std::int64_t substeps = 0;
  std::int64_t skipped_bodies = 0;
  int water_substeps = 0;         ///< internal substeps the surface took in the last substep
  double coupling_seconds = 0.0;  ///< last substep: envelopes, buoyancy, displacement
  double water_seconds = 0.0;     ///< last substep: the surface's own step
  double displaced_volume = 0.0;  ///< m^3 added to the water in total (signed)
};

class WaterCoupling : public btActionInterface {
 public:
  WaterCoupling(btDiscreteDynamicsWorld& world, water::Surface& surface, WaterCouplingSettings settings = {});
  ~WaterCoupling() override;
  WaterCoupling(const WaterCoupling&) = delete;
  WaterCoupling& operator=(const WaterCoupling&) = delete;

  /// The body floats and disturbs the water. disturb = false: it floats without making waves.
  /// Throws InvalidSetting for a null body or a shape that cannot be rasterized.
  void add_body(btRigidBody* body, bool disturb = true);
  void remove_body(btRigidBody* body);

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
  /// The added bodies, in the order added.
  [[nodiscard]] std::vector<btRigidBody*> bodies() const;
  /// Submerged volume of a body in the last substep (m^3), 0 if unknown.
  [[nodiscard]] double submerged_volume(const btRigidBody* body) const;

 private:
  /// Envelopes on a sample grid anchored at the body's centre of mass (samples at
  /// com +- (k + 1/2) cell), so a point-symmetric body is sampled symmetrically and its
  /// centre of buoyancy has no sampling bias (a world-fixed grid shifted it by up to half a
  /// sample: enough to hold a box heeled at 0.05 rad).
  struct Sampled {
    EnvelopeRaster raster;
    double origin_x = 0.0, origin_y = 0.0;  // world position of sample (0, 0)
  };
  struct Body {
    btRigidBody* body = nullptr;
    bool disturb = true;
    Sampled previous;  // envelopes at the last substep's pose
    Sampled current;
    double submerged = 0.0;
    double reach = 0.0;  // m, from check_rasterizable
  };
  bool body_is_sane(const btRigidBody& body) const;
  /// The cheap per-substep test that rasterizing the body at its pose cannot fail.
  bool can_rasterize(const Body& b) const;
  void rasterize(const btRigidBody& body, Sampled& out) const;
  void displace(Body& b);

  btDiscreteDynamicsWorld& world_;
  water::Surface& surface_;
  WaterCouplingSettings settings_;
  double sample_cell_ = 0.0;
  WaterSampler sampler_;
  std::vector<Body> bodies_;
  std::vector<double> scratch_, lengths_old_, lengths_new_;
  WaterCouplingStats stats_;
};

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
