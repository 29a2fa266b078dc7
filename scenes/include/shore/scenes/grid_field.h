#pragma once
// A HeightGrid as a surface to mesh (shore/mesh/field.h): column (i, j) at its height, a
// NaN height a hole. The grid is read whole on the first update (it has no base plane) and
// never changes afterwards; it must outlive the field.

#include "shore/mesh/field.h"
#include "shore/scenes/height_grid.h"

namespace shore::scenes {

class HeightGridField final : public mesh::Field {
 public:
  explicit HeightGridField(const HeightGrid& grid) : grid_(&grid) {}
  [[nodiscard]] std::int64_t ni() const override { return grid_->nx; }
  [[nodiscard]] std::int64_t nj() const override { return grid_->ny; }
  [[nodiscard]] bool height_field() const override { return true; }
  void positions(const shore::GridRect& r, std::span<double> out) const override;
  void take_changes(std::vector<shore::GridRect>& out) override;

 private:
  const HeightGrid* grid_;
  bool first_ = true;
};

}  // namespace shore::scenes
