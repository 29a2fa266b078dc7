#pragma once
// Soils as the meshes and metrics of the soil scenes see them: sampled into grids, their
// volume and sinkage measures.

#include <string>
#include <vector>

#include <BulletDynamics/Dynamics/btRigidBody.h>

#include "shore/bullet/terrain_tiles.h"
#include "shore/scenes/height_grid.h"
#include "shore/scenes/image.h"
#include "shore/scenes/scene.h"
#include "shore/terrain/terrain.h"

namespace shore::scenes {

/// A soil and the world rectangle it owns (several soils may lie side by side).
struct Patch {
  const terrain::Terrain* soil = nullptr;
  bullet::Region region;  ///< default: everywhere
};

/// Which per-column value of the soil to sample.
enum class Field {
  height,   ///< collision surface, m
  base,     ///< untouched ground, m
  sinkage,  ///< plastic sinkage, m
};

/// The soil a scene's options ask for: their cell, material preset and threads (the rest
/// TerrainSettings' defaults).
terrain::TerrainSettings soil_settings(const SceneOptions& options);

/// An empty grid (zeros) whose columns coincide with the soil columns (origin 0, spacing
/// cell) and cover the world rectangle [x0, x1] x [y0, y1].
HeightGrid grid_over(double x0, double y0, double x1, double y1, double cell);

/// `frame`'s columns filled with `field` of the patch that owns each column; `outside`
/// where no patch does (rigid ground). Reads only: untouched columns come from the base.
HeightGrid sample(const std::vector<Patch>& patches, const HeightGrid& frame, Field field, double outside = 0.0);

/// |ground + compacted + airborne - edited| / (compacted + |ground|), or that numerator
/// over 1e-12 if nothing moved.
double volume_drift_rel(const terrain::Terrain& soil);

/// Largest baseline - heights (how far the ground was lowered), m; 0 if nowhere lowered.
double max_lowering(const HeightGrid& baseline, const HeightGrid& heights);

/// Largest value of a grid (NaN ignored); 0 for an empty grid.
double max_of(const HeightGrid& g);

/// Angle (rad) between a body's local axis `axis` (0 x, 1 y, 2 z) and the world vertical.
double tilt_from_vertical(const btRigidBody& body, int axis);

}  // namespace shore::scenes
