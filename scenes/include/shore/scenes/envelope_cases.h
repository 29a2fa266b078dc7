#pragma once
// Envelope rasterization against per-column ray casting, on the same columns: the cases
// shared by shore_bullet_bench and shore-bench.
//
// Ray casting is what a column-based terrain does without envelopes: one vertical ray per
// column, either through a btCollisionWorld holding the body (rayTest: broadphase, then the
// shape) or straight at the shape (btCollisionWorld::rayTestSingle).

#include <memory>
#include <string>
#include <vector>

#include <BulletCollision/CollisionShapes/btCollisionShape.h>
#include <LinearMath/btTransform.h>

namespace shore::scenes {

/// One body to rasterize: a shape at a pose, on a grid of the given cell.
struct EnvelopeCase {
  std::string name;
  std::shared_ptr<btCollisionShape> shape;  ///< owns any sub-objects it needs
  btTransform pose;
};

/// The standard cases: wheel (cylinder D 0.8 m, width 0.3 m, axle along y, slightly
/// yawed and cambered), sphere (D 0.5 m), box (0.6 x 0.4 x 0.3 m, tilted), convex hull
/// (96 points on a 0.6 x 0.4 x 0.3 m ellipsoid, tilted).
std::vector<EnvelopeCase> standard_envelope_cases();

struct EnvelopeCaseResult {
  std::string name;
  int columns = 0;              ///< columns in the window (each one gets one ray)
  int covered = 0;              ///< columns the body covers
  double envelope_us = 0;       ///< microseconds per rasterization (lower envelope)
  double ray_world_us = 0;      ///< microseconds for one btCollisionWorld::rayTest per column
  double ray_single_us = 0;     ///< microseconds for one rayTestSingle per column
  double speedup_world = 0;     ///< ray_world_us / envelope_us
  double speedup_single = 0;    ///< ray_single_us / envelope_us
  double mean_abs_diff_mm = 0;  ///< mean |envelope - ray| over columns both hit (ray error, mostly)
  int coverage_mismatch = 0;    ///< columns hit by one method and not the other
};

/// Times the three methods side by side (interleaved, `rounds` rounds, the median of each
/// kept) on a grid of `cell` metres.
EnvelopeCaseResult run_envelope_case(const EnvelopeCase& c, double cell, int rounds);

/// run_envelope_case over standard_envelope_cases().
std::vector<EnvelopeCaseResult> run_envelope_cases(double cell = 0.01, int rounds = 7);

}  // namespace shore::scenes
