#pragma once
// A rectangle of a Terrain's columns as a surface to mesh (shore/mesh/field.h): node (i, j)
// is column (region.i0 + i, region.j0 + j) at its height. Changes come from the terrain's
// change generations (Terrain::changed_since), so any number of meshes can follow one
// terrain, alongside the Bullet coupling's take_changed. Over flat ground (no base source,
// or a FlatHeight) untouched columns are never read: a 1 km field costs its touched tiles.
//
//   shore::terrain::TerrainField ground(soil, {i0, j0, nx, ny});
//   shore::mesh::ChunkedMesh mesh;
//   mesh.update(ground, &camera);   // each frame, after the physics steps

#include <cstdint>
#include <optional>

#include "shore/mesh/field.h"
#include "shore/terrain/terrain.h"

namespace shore::terrain {

class TerrainField final : public mesh::Field {
 public:
  /// The columns of region (nx, ny >= 2; throws InvalidSetting otherwise). The terrain must
  /// outlive the field.
  TerrainField(const Terrain& terrain, GridRect region);

  [[nodiscard]] std::int64_t ni() const override { return region_.nx; }
  [[nodiscard]] std::int64_t nj() const override { return region_.ny; }
  [[nodiscard]] bool height_field() const override { return true; }
  void positions(const GridRect& r, std::span<double> out) const override;
  [[nodiscard]] std::optional<mesh::BasePlane> base() const override { return flat_; }
  /// First call: every changed column (and the whole region over a base source that is not
  /// flat); then what changed since the previous call.
  void take_changes(std::vector<GridRect>& out) override;

  [[nodiscard]] const GridRect& region() const noexcept { return region_; }

 private:
  const Terrain* terrain_;
  GridRect region_;
  mesh::BasePlane grid_;                 ///< x, y of the nodes (z: base height, if flat)
  std::optional<mesh::BasePlane> flat_;  ///< untouched ground, when it is flat
  bool first_ = true;
  std::uint64_t seen_ = 0;  ///< the terrain's generation the last changes were taken at
  std::vector<double> row_;
};

}  // namespace shore::terrain
