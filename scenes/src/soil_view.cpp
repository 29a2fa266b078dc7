#include "shore/scenes/soil_view.h"

#include <algorithm>
#include <cmath>

#include "shore/scenes/spray_view.h"

namespace shore::scenes {

terrain::TerrainSettings soil_settings(const SceneOptions& o) {
  terrain::TerrainSettings s;
  s.cell = o.cell;
  s.material = terrain::Material::preset(o.material);
  s.threads = o.threads;
  return s;
}

HeightGrid grid_over(double x0, double y0, double x1, double y1, double cell) {
  const auto i0 = static_cast<std::int64_t>(std::floor(x0 / cell));
  const auto j0 = static_cast<std::int64_t>(std::floor(y0 / cell));
  const auto i1 = static_cast<std::int64_t>(std::ceil(x1 / cell));
  const auto j1 = static_cast<std::int64_t>(std::ceil(y1 / cell));
  return HeightGrid(static_cast<int>(i1 - i0 + 1), static_cast<int>(j1 - j0 + 1), cell, static_cast<double>(i0) * cell,
                    static_cast<double>(j0) * cell);
}

HeightGrid sample(const std::vector<Patch>& patches, const HeightGrid& frame, Field field, double outside) {
  HeightGrid g = frame;
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const double x = g.x(i), y = g.y(j);
      double v = outside;
      for (const Patch& p : patches) {
        if (!p.region.contains(x, y)) continue;
        const std::int64_t ci = p.soil->column_i(x), cj = p.soil->column_j(y);
        v = field == Field::height ? p.soil->height(ci, cj)
            : field == Field::base ? p.soil->base_height(ci, cj)
                                   : p.soil->sinkage(ci, cj);
        break;
      }
      g.at(i, j) = v;
    }
  return g;
}

double volume_drift_rel(const terrain::Terrain& soil) {
  const terrain::VolumeTotals v = soil.volume();
  const double drift = std::abs(v.total() - v.edited);
  const double moved = v.compacted + std::abs(v.ground);
  return drift / (moved > 0.0 ? moved : 1e-12);
}

double max_lowering(const HeightGrid& baseline, const HeightGrid& heights) {
  double m = 0.0;
  for (std::size_t k = 0; k < heights.z.size() && k < baseline.z.size(); ++k)
    if (std::isfinite(heights.z[k]) && std::isfinite(baseline.z[k])) m = std::max(m, baseline.z[k] - heights.z[k]);
  return m;
}

double max_of(const HeightGrid& g) {
  double m = 0.0;
  bool any = false;
  for (double v : g.z)
    if (std::isfinite(v)) {
      m = any ? std::max(m, v) : v;
      any = true;
    }
  return m;
}

double tilt_from_vertical(const btRigidBody& body, int axis) {
  const btVector3 a = body.getWorldTransform().getBasis().getColumn(axis);
  return std::acos(std::clamp(static_cast<double>(a.z()), -1.0, 1.0));
}

}  // namespace shore::scenes
