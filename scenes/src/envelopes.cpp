#include "shore/scenes/envelopes.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "shore/bullet/envelope.h"

namespace shore::scenes {

BodyEnvelopes body_envelopes(std::span<const btRigidBody* const> bodies, const HeightGrid& frame) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  BodyEnvelopes e{HeightGrid(frame.nx, frame.ny, frame.cell, frame.x0, frame.y0, nan),
                  HeightGrid(frame.nx, frame.ny, frame.cell, frame.x0, frame.y0, nan)};
  const bullet::EnvelopeGrid grid{frame.x0, frame.y0, frame.cell};
  bullet::EnvelopeOptions options;
  options.upper = true;
  options.include_margin = false;
  bullet::EnvelopeRasterizer rasterizer(grid, options);
  EnvelopeRaster raster;
  for (const btRigidBody* b : bodies) {
    const btCollisionShape& shape = *b->getCollisionShape();
    if (!bullet::pose_rasterizable(b->getWorldTransform(), bullet::shape_reach(shape), grid)) continue;
    rasterizer.rasterize(shape, b->getWorldTransform(), raster);
    for (int jj = 0; jj < raster.ny; ++jj)
      for (int ii = 0; ii < raster.nx; ++ii) {
        const std::int64_t i = raster.i0 + ii, j = raster.j0 + jj;
        const std::size_t k = raster.index(i, j);
        if (i < 0 || j < 0 || i >= frame.nx || j >= frame.ny || !raster.covers(k)) continue;
        double& top = e.top.at(static_cast<int>(i), static_cast<int>(j));
        double& bottom = e.bottom.at(static_cast<int>(i), static_cast<int>(j));
        top = std::isfinite(top) ? std::max(top, raster.upper[k]) : raster.upper[k];
        bottom = std::isfinite(bottom) ? std::min(bottom, raster.lower[k]) : raster.lower[k];
      }
  }
  return e;
}

}  // namespace shore::scenes
