#pragma once

#include <cmath>
#include <utility>
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

/// "t = 1.25 s".
std::string time_label(double t);

/// Frames of a run spread evenly over its substeps (3 in smoke runs, 6 otherwise), each
/// labelled with its time: the filmstrip of a scene.
struct FilmSchedule {
  int substeps = 1;
  int frames = 6;
  int next = 0;  ///< index of the next frame to take
  std::vector<Image> images;
  std::vector<std::string> labels;

  FilmSchedule(int run_substeps, bool smoke) : substeps(run_substeps), frames(smoke ? 3 : 6) {}
  /// True if substep k (0: the start) is when the next frame is due.
  [[nodiscard]] bool due(int k) const {
    return next < frames && k == static_cast<int>(std::lround(double(substeps) * next / (frames - 1)));
  }
  void add(Image image, double t) {
    images.push_back(std::move(image));
    labels.push_back(time_label(t));
    ++next;
  }
  /// If substep k's frame is due, adds the oblique relief of the patches over `frame`
  /// (heights exaggerated 2x, coloured by lowering from `baseline`) with the bodies drawn.
  void capture_soil(int k, double t, const std::vector<Patch>& patches, const HeightGrid& frame,
                    const HeightGrid& baseline, const std::vector<const btCollisionObject*>& bodies, int min_pixels);
};

/// Angle (rad) between a body's local axis `axis` (0 x, 1 y, 2 z) and the world vertical.
double tilt_from_vertical(const btRigidBody& body, int axis);

}  // namespace shore::demo::soil_scene
