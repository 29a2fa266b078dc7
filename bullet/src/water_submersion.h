#pragma once
// Internal: where a body sits in the water: the water plane fitted around it, its parts'
// frames, and what of it lies below the plane.

#include <vector>

#include <LinearMath/btTransform.h>

#include "envelope_internal.h"
#include "shore/bullet/envelope.h"
#include "shore/core/grid_rect.h"
#include "shore/water/surface.h"
#include "water_forces.h"
#include "water_shape.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace water_detail {

/// The nodes under the world box, padded by `pad` nodes, clamped to the grid.
GridRect window_under(const water::Surface& s, const btVector3& lo, const btVector3& hi, int pad);
/// The least-squares plane through the heights `z` of the window's nodes outside `inner`
/// (the nodes under the body's bounding box): the level the body sits in, free of the
/// surface under the body itself, which its own displacement raises. Also the mean vertical
/// velocity `vz` there.
WaterPlane fit_plane(const water::Surface& s, const GridRect& win, const GridRect& inner, const std::vector<double>& z,
                     const std::vector<double>& vz);
/// Frames of the parts at the body's pose, and the polyhedra's world face planes.
void part_frames(const WaterShape& shape, const envelope_detail::Frame& body,
                 std::vector<envelope_detail::Frame>& frames, std::vector<WorldPlanes>& planes);
/// A part's frame as a Bullet transform (for the rasterizer).
btTransform to_transform(const envelope_detail::Frame& f);
/// The analytic parts below the plane.
void submerge(const WaterShape& shape, const std::vector<envelope_detail::Frame>& frames, const WaterPlane& plane,
              Submerged& wet);
/// Meshes: the wet length of every sub-sample column under the plane, into volume and
/// first moment.
void submerge_sampled(const WaterShape& shape, const std::vector<envelope_detail::Frame>& frames,
                      const WaterPlane& plane, EnvelopeRasterizer& rasterizer, double& volume, Vec3& moment);

}  // namespace water_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
