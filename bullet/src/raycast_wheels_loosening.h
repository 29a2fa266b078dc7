#pragma once
// Internal: the soil under a slipping raycast wheel bears less where the rim has sheared it
// (shear::loosening), each strip of the rim by its own shear displacement. Along the rim j
// grows from 0 where the soil meets it to its largest at the bottom (Wong and Reece's
// j(theta), RimShear), so the columns near the bottom bear less than their sinkage's Bekker
// pressure and those near the entry bear fully: the normal stress peaks ahead of the bottom,
// as Wong and Reece measured it, and the wheel meets more compaction resistance, the more
// the more it slips. A wheel that rolls free shears its soil by a few mm and hardly changes.

#include <vector>

#include <LinearMath/btVector3.h>

#include "raycast_traction.h"
#include "raycast_wheel_grid.h"
#include "shore/core/envelope.h"
#include "shore/core/grid_rect.h"
#include "shore/terrain/material.h"
#include "shore/terrain/terrain.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

class RimLoosening {
 public:
  /// Weighs each column `envelope` covers (the wheel's bearing part, on a grid of `cell` m)
  /// by the bearing left in soil sheared by `shear` at its strip's rim angle,
  /// shear::remoulding(m, j): the rim cut into strips one cell long along `forward` (the
  /// ground's coordinates), each at the angle of its centre, as the rim's shear takes them.
  /// `from_centre` holds the envelope's columns' offsets from the wheel's centre.
  void build(double cell, const EnvelopeRaster& envelope, const ColumnOffsets& from_centre, const btVector3& forward,
             double radius, const RimShear& shear, const terrain::Material& m);
  /// N, what the columns of `bearing` (within the built rect) carry loosened.
  [[nodiscard]] double capacity(const terrain::Bearing& bearing) const;
  /// `bearing` loosened into `out`: each column's force and the capacity times its weight.
  void apply(const terrain::Bearing& bearing, terrain::Bearing& out) const;

 private:
  [[nodiscard]] double weight(const terrain::ColumnForce& c) const { return weight_[rect_.index(c.i, c.j)]; }
  /// The strips' rim angles, kept while the radius and the cell stay.
  void angles(double radius, double cell);
  GridRect rect_;
  std::vector<double> weight_;   ///< per covered column of rect_, row-major (others unread)
  std::vector<double> strip_;    ///< per strip along the heading: its weight
  std::vector<double> theta_;    ///< per strip: its centre's rim angle, rad
  std::vector<double> along_x_;  ///< scratch: per column along x, its offset's part along the heading
  std::vector<double> along_y_;  ///< scratch: the same per row along y
  double radius_ = 0.0, cell_ = 0.0;
  int half_ = 0;  ///< strips -half_..half_
};

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
