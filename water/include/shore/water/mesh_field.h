#pragma once
// A water surface as a surface to mesh (shore/mesh/field.h): node (i, j) of the grid at its
// 3-D position, so a wave that leans or folds over keeps its shape in the mesh (errors are
// 3-D distances; in vertical-only mode the surface is a height field). The base plane is
// the surface at rest; changes are found by comparing the nodes' displacements with the
// ones the previous take_changes saw (one pass over the grid).
//
//   shore::water::SurfaceField water(pond);
//   shore::mesh::ChunkedMesh mesh;
//   mesh.update(water, &camera);   // each frame, after the physics steps

#include <cstdint>
#include <optional>
#include <vector>

#include "shore/mesh/field.h"
#include "shore/water/surface.h"

namespace shore::water {

class SurfaceField final : public mesh::Field {
 public:
  /// The surface must outlive the field.
  explicit SurfaceField(const Surface& surface);

  [[nodiscard]] std::int64_t ni() const override { return surface_->nx(); }
  [[nodiscard]] std::int64_t nj() const override { return surface_->ny(); }
  [[nodiscard]] bool height_field() const override { return surface_->mode() == SurfaceMode::vertical_only; }
  void positions(const GridRect& r, std::span<double> out) const override;
  [[nodiscard]] std::optional<mesh::BasePlane> base() const override { return rest_; }
  /// Blocks of nodes (their changed nodes' bounding box) whose displacement differs from
  /// what the previous call saw (the first call: from rest).
  void take_changes(std::vector<GridRect>& out) override;

 private:
  /// Node (i, j)'s rest position, as the surface places it.
  [[nodiscard]] Eigen::Vector3d rest_at(int i, int j) const;

  const Surface* surface_;
  mesh::BasePlane rest_;
  std::vector<double> seen_;  ///< ux, uy, uz per node as last reported (3-D), or uz
};

}  // namespace shore::water
