#pragma once
// The soil's half of a body's contact: where, in which direction and how hard the soil can
// push on a body lying on or moving through it, for an engine's contact solver (Shore's
// Bullet coupling solves it; see docs/terrain.md, "Soil contact").
//
// Bottom elements: every column the body's underside touches (lies within
// contact_tolerance of the column's top). The soil pushes at the body's surface above the
// column, along the normal of the underside (from the envelope's slopes), on the body's
// surface over the column: over the whole cell, or, at the edges of the footprint and when
// a SurfaceProbe is given, over the part the body covers (the plan area divided by the
// normal's vertical share, so the push has Bekker's vertical component: a wheel's rim
// carries W = integral of sigma b dx and resists with integral of sigma b dz, as Bekker's
// and Wong's formulas have it). At most it pushes with Bekker's
// yield pressure at the column's sinkage if pressed to the body (its plastic sinkage plus
// how far the body lies below its top), loosened by shear::loosening(j) of the shear
// displacement j the body has put into the column (a body pressed straight down remoulds
// nothing).
// Sheared along the surface, the column resists with Janosi-Hanamoto's stress
// (shore/terrain/shear.h), which the solver applies.
//
// Wall elements: where soil beside the footprint stands above the body's underside (the
// sides of a rut, a crater or the body's own sinkage hole), it pushes horizontally on the
// body's side. At most with the plastic work of pressing that soil down to the body's
// depth per unit of sideways travel: k z^(n+1) / (n + 1) per unit length of wall, z its
// height above the underside, k = k_c / b + k_phi (Bekker's compaction resistance, turned
// sideways). Walls carry no shear.
//
// Unloading (Material::unload_modulus A_u > 0): a column the body lies on or above, pressed
// before to plastic sinkage z, is elastic: it pushes with p_yield(z) - k_u g, k_u = A_u z,
// g how far the body's underside lies above its top, and counts as touched while that is
// positive. Columns the body presses into (below their top) stay rigid-plastic.

#include <cstdint>
#include <limits>
#include <vector>

#include "shore/core/vec3.h"

namespace shore::terrain {

/// The body's underside at any point, for sub-cell coverage at the edges of its footprint.
class SurfaceProbe {
 public:
  virtual ~SurfaceProbe() = default;
  /// Lowest point of the body on the vertical line through world (x, y), m; +infinity
  /// where the line misses the body.
  [[nodiscard]] virtual double lower_at(double x, double y) const = 0;
};

/// One place where the soil can push on the body.
struct ContactElement {
  Vec3 point;                 ///< m, world point the soil pushes at
  Vec3 normal{0, 0, 1};       ///< unit normal, from the soil into the body
  double area = 0.0;          ///< m^2 the soil pushes on
  double pressure = 0.0;      ///< Pa, the most it can push with; +infinity on bedrock
  std::int64_t i = 0, j = 0;  ///< the soil column
  /// Index into the envelope raster of the column whose shear displacement this element
  /// reads and moves (a fringe element shares its covered neighbour's); -1 for walls.
  std::int32_t raster_index = -1;
  bool wall = false;  ///< the side of a rut or crater (horizontal normal, no shear)
  // (Last, so states saved before these fields read as a prefix: docs/checkpoints.md.)
  /// Pa/m: how the push changes as the body moves along the normal, where the column is
  /// unloading elastically (Material::unload_modulus > 0 and the body at or above its top):
  /// it pushes with preload + stiffness x (the body's further approach), within
  /// [0, pressure]. +infinity: it holds rigidly whatever is asked, up to `pressure`
  /// (columns being pressed, walls, bedrock, rigid-plastic soil).
  double stiffness = std::numeric_limits<double>::infinity();
  double preload = 0.0;  ///< Pa, the elastic push at the body's present pose (when stiffness is finite)
  /// Pa/m: how fast `pressure` grows as the body presses further into the column: Bekker's
  /// dp/dz = n p / z where the column is pressed 2 cells or deeper, the secant over the next
  /// half cell above that (0 for walls and bedrock), so a solver may keep the patch for a
  /// substep while the body moves a little (bullet::TerrainContactSettings::follow_drift).
  double pressure_rate = 0.0;
};

/// The soil's side of one body's contact.
struct ContactPatch {
  std::vector<ContactElement> elements;  ///< bottom elements in raster order, then walls
  double patch_width = 0.0;              ///< m, Bekker's b: the smaller extent of the touching area
  double area = 0.0;                     ///< m^2 of the bottom elements, in plan
  int touching_columns = 0;              ///< covered columns the underside touches

  void clear() {
    elements.clear();
    patch_width = area = 0.0;
    touching_columns = 0;
  }
};

}  // namespace shore::terrain
