#pragma once
// Helpers shared by the soil scenes (footprints, tracks, vehicle, impact): soil grids as
// pictures, bodies drawn over them, the volume and sinkage metrics, state hashes.

#include <cstdint>
#include <string>
#include <vector>

#include <btBulletDynamicsCommon.h>

#include "shore/bullet/terrain_coupling.h"
#include "shore/core/hash.h"
#include "shore/demo/height_grid.h"
#include "shore/demo/render.h"
#include "shore/terrain/terrain.h"

namespace shore::demo::soil_scene {

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

/// An empty grid (zeros) whose columns coincide with the soil columns (origin 0, spacing
/// cell) and cover the world rectangle [x0, x1] x [y0, y1].
HeightGrid grid_over(double x0, double y0, double x1, double y1, double cell);

/// `frame`'s columns filled with `field` of the patch that owns each column; `outside`
/// where no patch does (rigid ground). Reads only: untouched columns come from the base.
HeightGrid sample(const std::vector<Patch>& patches, const HeightGrid& frame, Field field, double outside = 0.0);

/// Upper and lower envelopes (NaN where no body) of the bodies' nominal solids over
/// `frame`'s columns, for the pictures.
struct BodyEnvelopes {
  HeightGrid top;
  HeightGrid bottom;
};
BodyEnvelopes body_envelopes(const std::vector<const btCollisionObject*>& bodies, const HeightGrid& frame);

/// |ground + compacted + airborne - edited| / (compacted + |ground|), or that numerator
/// over 1e-12 if nothing moved.
double volume_drift_rel(const terrain::Terrain& soil);

/// Largest baseline - heights (how far the ground was lowered), m; 0 if nowhere lowered.
double max_lowering(const HeightGrid& baseline, const HeightGrid& heights);

/// Largest value of a grid (NaN ignored); 0 for an empty grid.
double max_of(const HeightGrid& g);

/// Adds each body's transform and velocities to the hash.
void hash_bodies(StateHash& hash, const std::vector<const btRigidBody*>& bodies);
/// Non-finite values among the bodies' transforms and velocities.
long non_finite_bodies(const std::vector<const btRigidBody*>& bodies);

/// The oblique picture of one moment: relief coloured by deformation, bodies drawn.
Image oblique_frame(const HeightGrid& heights, const HeightGrid& baseline, const BodyEnvelopes* bodies,
                    double exaggeration, int min_pixels, const std::string& title, double deformation_scale = 0.0,
                    double elevation_deg = 35.0, bool legend = false);

/// Registers dynamic bodies with a soil coupling. Works around a pair-cache problem of
/// TerrainCoupling::add_body: it clears the soil filter bit from the body's collision mask
/// but keeps any broadphase pair the body already has with a soil tile (cleanProxyFromPairs
/// keeps the pair), so a body that overlapped a tile before add_body (a tile created by an
/// earlier add_body, or the body added to the world next to existing tiles) keeps Bullet's
/// rigid contact with it. Clearing the bit on every body first means no such pair is made.
void add_bodies(bullet::TerrainCoupling& coupling, const std::vector<btRigidBody*>& bodies, int soil_filter_bit);

/// "t = 1.25 s".
std::string time_label(double t);

/// Angle (rad) between a body's local axis `axis` (0 x, 1 y, 2 z) and the world vertical.
double tilt_from_vertical(const btRigidBody& body, int axis);

}  // namespace shore::demo::soil_scene
