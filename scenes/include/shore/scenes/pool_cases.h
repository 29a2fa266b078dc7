#pragma once
// Bodies in a square pool of spring-mass water, each with its outside reference
// (Archimedes' drafts, the hydrostatic heave period). Written once; used by the
// shore::bullet tests, the benchmarks and the water scenes (floaters, their drafts).

#include <cstdint>
#include <memory>
#include <vector>

#include <LinearMath/btQuaternion.h>
#include <LinearMath/btVector3.h>

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
};

enum class FloaterShape { box, sphere, cylinder };

struct Floater {
  FloaterShape shape = FloaterShape::box;
  btVector3 size{
      0.3f, 0.3f,
      0.2f};  ///< m: box full extents; sphere: x = diameter; cylinder: x = diameter, y = length (axis along y)
  double density_ratio = 0.5;   ///< body density / water density
  btVector3 position{0, 0, 0};  ///< m, centre of mass at the start
  btQuaternion rotation = btQuaternion::getIdentity();
  btVector3 velocity{0, 0, 0};
};

/// Archimedes: the draft of a floater floating upright (box: bottom face down; sphere;
/// horizontal cylinder).
double archimedes_draft(const Floater& f);

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
  std::vector<double> final_draft;  ///< m, mean draft over the last second (bottom below the far-field level)
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

}  // namespace shore::scenes
