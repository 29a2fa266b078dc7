#include "shore/terrain/mesh_field.h"

#include <algorithm>

#include "shore/core/error.h"

namespace shore::terrain {

TerrainField::TerrainField(const Terrain& terrain, GridRect region) : terrain_(&terrain), region_(region) {
  const Check c{"terrain.TerrainField.region"};
  c.at_least("nx", region.nx, 2);
  c.at_least("ny", region.ny, 2);
  const TerrainSettings& s = terrain.settings();
  grid_.origin = {terrain.column_x(region.i0), terrain.column_y(region.j0), s.base_height};
  grid_.di = {s.cell, 0.0, 0.0};
  grid_.dj = {0.0, s.cell, 0.0};
  const auto* flat = dynamic_cast<const FlatHeight*>(s.base.get());
  if (!s.base || flat) {
    flat_ = grid_;
    if (flat) flat_->origin[2] = flat->height(0.0, 0.0);
  }
}

void TerrainField::positions(const GridRect& r, std::span<double> out) const {
  if (out.size() != 3 * r.size())
    throw InvalidSetting("terrain.TerrainField.positions(out).size", shore::detail::to_text(out.size()),
                         "must be 3 ni nj of the rectangle");
  std::vector<double> z(r.size());
  terrain_->heights({region_.i0 + r.i0, region_.j0 + r.j0, r.nx, r.ny}, z);
  std::size_t k = 0;
  for (std::int64_t j = r.j0; j < r.j0 + r.ny; ++j)
    for (std::int64_t i = r.i0; i < r.i0 + r.nx; ++i, ++k) {
      const Vec3 p = grid_.at(static_cast<double>(i), static_cast<double>(j));
      out[3 * k] = p[0];
      out[3 * k + 1] = p[1];
      out[3 * k + 2] = z[k];
    }
}

void TerrainField::take_changes(std::vector<GridRect>& out) {
  out.clear();
  const std::uint64_t now = terrain_->generation();
  if (first_ && !flat_) {
    out.push_back({0, 0, region_.nx, region_.ny});
  } else {
    for (const GridRect& c : terrain_->changed_since(first_ ? 0 : seen_)) {
      const GridRect common = intersection(c, region_);
      if (!common.empty()) out.push_back(common.shifted(-region_.i0, -region_.j0));
    }
  }
  first_ = false;
  seen_ = now;
}

}  // namespace shore::terrain
