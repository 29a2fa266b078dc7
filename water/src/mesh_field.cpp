#include "shore/water/mesh_field.h"

#include <algorithm>

#include "shore/core/error.h"

namespace shore::water {
namespace {

constexpr int kBlock = 16;  // nodes per side of the blocks changes are reported in

}  // namespace

SurfaceField::SurfaceField(const Surface& surface) : surface_(&surface) {
  const SurfaceSettings& s = surface.settings();
  rest_.origin = {s.origin_x, s.origin_y, s.rest_height};
  rest_.di = {surface.spacing(), 0.0, 0.0};
  rest_.dj = {0.0, surface.spacing(), 0.0};
  const std::size_t per_node = surface.mode() == SurfaceMode::full_3d ? 3 : 1;
  seen_.assign(per_node * surface.node_count(), 0.0f);  // at rest
}

void SurfaceField::positions(const mesh::NodeRect& r, std::span<double> out) const {
  if (out.size() != static_cast<std::size_t>(3 * r.ni * r.nj))
    throw InvalidSetting("water.SurfaceField.positions(out).size", shore::detail::to_text(out.size()),
                         "must be 3 ni nj of the rectangle");
  const Surface::View v = surface_->view();
  const bool full = !v.ux.empty();
  const std::size_t nx = static_cast<std::size_t>(surface_->nx());
  std::size_t k = 0;
  for (std::int64_t j = r.j0; j < r.j0 + r.nj; ++j)
    for (std::int64_t i = r.i0; i < r.i0 + r.ni; ++i, ++k) {
      const std::size_t n = static_cast<std::size_t>(j) * nx + static_cast<std::size_t>(i);
      const std::array<double, 3> p = rest_.at(static_cast<double>(i), static_cast<double>(j));
      out[3 * k] = p[0] + (full ? static_cast<double>(v.ux[n]) : 0.0);
      out[3 * k + 1] = p[1] + (full ? static_cast<double>(v.uy[n]) : 0.0);
      out[3 * k + 2] = p[2] + static_cast<double>(v.uz[n]);
    }
}

void SurfaceField::take_changes(std::vector<mesh::NodeRect>& out) {
  out.clear();
  const Surface::View v = surface_->view();
  const bool full = !v.ux.empty();
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
            moved = v.ux[n] != seen_[3 * n] || v.uy[n] != seen_[3 * n + 1] || v.uz[n] != seen_[3 * n + 2];
            seen_[3 * n] = v.ux[n], seen_[3 * n + 1] = v.uy[n], seen_[3 * n + 2] = v.uz[n];
          } else {
            moved = v.uz[n] != seen_[n];
            seen_[n] = v.uz[n];
          }
          if (!moved) continue;
          i0 = std::min(i0, i), j0 = std::min(j0, j), i1 = std::max(i1, i), j1 = std::max(j1, j);
        }
      if (i1 >= i0) out.push_back({i0, j0, i1 - i0 + 1, j1 - j0 + 1});
    }
}

}  // namespace shore::water
