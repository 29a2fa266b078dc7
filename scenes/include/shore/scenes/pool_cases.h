#pragma once
// Bodies in a square pool of spring-mass water, each with its outside reference
// (Archimedes' drafts, the hydrostatic heave period, the drag law and a sinking ball's
// terminal velocity). Written once; used by the shore::bullet tests, the benchmarks and
// the water scenes (floaters, their drafts).

#include <cstdint>
#include <memory>
#include <vector>

#include <LinearMath/btQuaternion.h>
#include <LinearMath/btTransform.h>
#include <LinearMath/btVector3.h>

#include "shore/bullet/buoyancy.h"
#include "shore/water/surface.h"

class btRigidBody;

namespace shore::scenes {

class World;

/// The pool: nodes x nodes water at `cell` spacing, wave speed from `depth`, a rigid floor
/// at -depth, walls at the edges (vertical-only nodes). The surface rests at z = 0 and is
/// centred on the origin.
struct PoolSettings {
  int nodes = 64;              ///< per side
  double cell = 0.05;          ///< m
  double depth = 0.5;          ///< m (also sets the wave speed sqrt(g depth))
  double damping_time = 2.0;   ///< s, amplitude e-folding time
  bool vertical_only = true;   ///< the vertical-only surface (cheaper, larger stable steps)
  double substep = 1.0 / 240;  ///< s
  int threads = 1;
  int nodes_y = 0;              ///< nodes along y, 0: the same as along x (a square pool)
  bool sleep = true;            ///< SleepSettings::enabled of the surface
  int parallel_min_nodes = -1;  ///< the surface's; -1: its default (0 forks every substep)
  bullet::FluidSettings fluid;  ///< drag coefficients and samples per cell of the coupling
};

/// box: full extents; sphere: x = diameter; cylinder: x = diameter, y = length (axis
/// along y); hull: an octagonal prism (convex hull of 16 points), x = across the corners,
/// z = height, standing upright.
enum class FloaterShape { box, sphere, cylinder, hull };

struct Floater {
  FloaterShape shape = FloaterShape::box;
  btVector3 size{0.3f, 0.3f, 0.2f};  ///< m, see FloaterShape
  double density_ratio = 0.5;        ///< body density / water density
  btVector3 position{0, 0, 0};       ///< m, centre of mass at the start
  btQuaternion rotation = btQuaternion::getIdentity();
  btVector3 velocity{0, 0, 0};
};

/// Archimedes: the draft of a floater floating upright (box: bottom face down; sphere;
/// horizontal cylinder; prism hull: upright).
double archimedes_draft(const Floater& f);
/// The floater's volume (m^3).
double floater_volume(const Floater& f);

/// The height of a floater's bottom: the centre of its bottom face (box, hull: unbiased by a
/// small heel) or its centre less its radius (sphere, cylinder).
double bottom_of(const Floater& f, const btTransform& pose);

/// Adds the floater to the world: its shape, its mass (density_ratio times water's density
/// times its volume), pose and velocity; it never sleeps (hashes must not depend on it).
btRigidBody* add_floater(World& world, const Floater& f);

struct PoolRecord {
  double t = 0.0;
  std::vector<double> z;      ///< centre of mass heights, one per floater
  std::vector<double> tilt;   ///< angle between body z and world z (rad), one per floater
  double water_energy = 0.0;  ///< J, the surface's time-centred energy (waves)
};

struct PoolResult {
  std::vector<PoolRecord> records;  ///< every `record_every` substeps
  std::vector<double> final_draft;  ///< m, mean draft over the last second (bottom_of below the far-field level)
  std::vector<double> max_z;        ///< m, highest centre of mass reached after the start
  long nan_count = 0;               ///< non-finite values in the bodies and the water at the end
  std::int64_t substeps = 0;
  double wall_seconds = 0.0;
  double coupling_seconds = 0.0;            ///< Shore's coupling (buoyancy, displacement), total
  double water_seconds = 0.0;               ///< the surface's own steps, total
  std::uint64_t state_hash = 0;             ///< state_hash (state.h) of the water and the floaters at the end
  std::shared_ptr<water::Surface> surface;  ///< final water (pictures, ring checks)
};

struct PoolRun {
  PoolSettings pool;
  std::vector<Floater> floaters;
  double seconds = 5.0;
  int record_every = 4;
  int substeps_per_step = 1;  ///< Bullet substeps per stepSimulation call of 1/rate s
};

PoolResult run_pool(const PoolRun& run);

/// A floater towed at a constant velocity through still water (kinematic, at its
/// Archimedes draft below the rest level): the water's drag against the law
/// F = 1/2 rho C_d A |u| u + rho k A u, A the frontal area below the level (width times
/// the draft it tows at; a ball's wet circular segment).
struct TowRun {
  PoolSettings pool;
  Floater floater;
  double speed = 1.0;    ///< m/s, along +x
  double seconds = 2.5;  ///< towed; the force is averaged over the last second
  bool disturb = true;   ///< false: the floater makes no waves (no bow wave in its water level)
};
struct TowResult {
  double drag = 0.0;       ///< N, mean water force along -x over the last second
  double reference = 0.0;  ///< N, the law on the frontal area at the mean draft
  double area = 0.0;       ///< m^2, that frontal area
  double draft = 0.0;      ///< m, mean draft over the last second (far-field level minus the lowest point)
  double coupling_seconds = 0.0;
  std::int64_t substeps = 0;
  long nan_count = 0;
};
TowResult run_tow(const TowRun& run);

/// A dense ball released under water in a deep pool: its terminal velocity against the
/// balance of weight less buoyancy with the drag law on pi r^2.
struct SinkRun {
  PoolSettings pool;      ///< depth: the floor; the ball starts just under the surface
  double diameter = 0.1;  ///< m
  double density_ratio = 1.5;
  double seconds = 2.0;
};
struct SinkResult {
  double terminal = 0.0;   ///< m/s, the mean sinking speed between 40 % and 80 % of the depth
  double reference = 0.0;  ///< m/s, from (rho_b - rho) V g = 1/2 rho C_d A v^2 + rho k A v
  long nan_count = 0;
};
SinkResult run_sink(const SinkRun& run);

}  // namespace shore::scenes
