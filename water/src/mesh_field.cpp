#include "shore/water/mesh_field.h"

#include <algorithm>

#include "shore/core/error.h"

namespace shore::water {
namespace {

constexpr int kBlock = 16;  // nodes per side of the blocks changes are reported in

}  // namespace

Eigen::Vector3d SurfaceField::rest_at(int i, int j) const {
  return {surface_->node_x(i), surface_->node_y(j), rest_.origin[2]};
}

SurfaceField::SurfaceField(const Surface& surface) : surface_(&surface) {
  const SurfaceSettings& s = surface.settings();
  rest_.origin = {s.origin_x, s.origin_y, s.rest_height};
  rest_.di = {surface.spacing(), 0.0, 0.0};
  rest_.dj = {0.0, surface.spacing(), 0.0};
  const std::size_t per_node = surface.mode() == SurfaceMode::full_3d ? 3 : 1;
  seen_.assign(per_node * surface.node_count(), 0.0);  // at rest
}

void SurfaceField::positions(const GridRect& r, std::span<double> out) const {
  if (out.size() != 3 * r.size())
    throw InvalidSetting("water.SurfaceField.positions(out).size", shore::detail::to_text(out.size()),
                         "must be 3 ni nj of the rectangle");
  std::size_t k = 0;
  for (std::int64_t j = r.j0; j < r.j0 + r.ny; ++j)
    for (std::int64_t i = r.i0; i < r.i0 + r.nx; ++i, ++k) {
      const Eigen::Vector3d p = surface_->position(static_cast<int>(i), static_cast<int>(j));
      out[3 * k] = p.x(), out[3 * k + 1] = p.y(), out[3 * k + 2] = p.z();
    }
}

void SurfaceField::take_changes(std::vector<GridRect>& out) {
  out.clear();
  const bool full = surface_->mode() == SurfaceMode::full_3d;
  const int nx = surface_->nx(), ny = surface_->ny();
  for (int bj = 0; bj < ny; bj += kBlock)
    for (int bi = 0; bi < nx; bi += kBlock) {
      int i0 = nx, j0 = ny, i1 = -1, j1 = -1;
      for (int j = bj; j < std::min(bj + kBlock, ny); ++j)
        for (int i = bi; i < std::min(bi + kBlock, nx); ++i) {
          const std::size_t n =
              static_cast<std::size_t>(j) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(i);
          bool moved = false;
          if (full) {
            const Eigen::Vector3d u = surface_->position(i, j) - rest_at(i, j);
            moved = u.x() != seen_[3 * n] || u.y() != seen_[3 * n + 1] || u.z() != seen_[3 * n + 2];
            seen_[3 * n] = u.x(), seen_[3 * n + 1] = u.y(), seen_[3 * n + 2] = u.z();
          } else {
            const double uz = surface_->height(i, j) - rest_.origin[2];
            moved = uz != seen_[n];
            seen_[n] = uz;
          }
          if (!moved) continue;
          i0 = std::min(i0, i), j0 = std::min(j0, j), i1 = std::max(i1, i), j1 = std::max(j1, j);
        }
      if (i1 >= i0) out.push_back({i0, j0, i1 - i0 + 1, j1 - j0 + 1});
    }
}

}  // namespace shore::water
