#include "shore/water/surface_settings.h"

#include "shore/water/surface.h"

#include "shore/core/error.h"

namespace shore::water {

void GuardSettings::validate() const {
  const Check c{"water.GuardSettings"};
  c.in_left_open("safety", safety, 0.0, 1.0);
  c.at_least("max_substeps", max_substeps, 1);
  c.positive("max_disturbance_spacings", max_disturbance_spacings);
}

void OpenBoundarySettings::validate() const {
  const Check c{"water.OpenBoundarySettings"};
  c.at_least("width", width, 2);
  c.in_left_open("strength", strength, 0.0, 64.0);
}

void SleepSettings::validate() const {
  const Check c{"water.SleepSettings"};
  if (tile < 8 || tile > 256 || (tile & (tile - 1)) != 0)
    throw InvalidSetting(c.name("tile"), detail::to_text(tile), "must be a power of two in [8, 256]");
  c.non_negative("height", height);
  c.non_negative("velocity", velocity);
  c.at_least("calm_substeps", calm_substeps, 1);
}

void SurfaceSettings::validate() const {
  const Check c{"water.SurfaceSettings"};
  c.at_least("nx", nx, 3);
  c.at_least("ny", ny, 3);
  // Heights are stored as float displacements and indices as 32-bit triangle indices.
  if (static_cast<long long>(nx) * ny > (1LL << 31))
    throw InvalidSetting(c.name("nx*ny"), detail::to_text(static_cast<long long>(nx) * ny), "must be <= 2^31");
  c.finite("origin_x", origin_x);
  c.finite("origin_y", origin_y);
  c.finite("rest_height", rest_height);
  c.positive("density", density);
  c.at_least("threads", threads, 0);
  c.at_least("parallel_min_nodes", parallel_min_nodes, 0);
  c.in_closed("boundary", static_cast<int>(boundary), 0, 3);
  c.in_closed("mode", static_cast<int>(mode), 0, 1);
  c.in_closed("kernel", static_cast<int>(kernel), 0, 4);
  if (kernel == KernelChoice::avx2 && !Surface::kernel_available(KernelChoice::avx2))
    throw InvalidSetting(c.name("kernel"), "avx2",
                         "needs a build with the AVX2 kernel (SHORE_WATER_NO_AVX2=OFF, x86-64) and a CPU with AVX2 "
                         "and FMA; use automatic or generic here");
  if (kernel == KernelChoice::avx512 && !Surface::kernel_available(KernelChoice::avx512))
    throw InvalidSetting(c.name("kernel"), "avx512",
                         "needs a build with the AVX2 and AVX-512 kernels (SHORE_WATER_NO_AVX2=OFF, x86-64) and a CPU "
                         "with AVX-512 F, VL, DQ and BW; use automatic or generic here");
  lattice.validate();
  guard.validate();
  sleep.validate();
  open.validate();
  if (boundary == Boundary::open && (2 * open.width >= nx || 2 * open.width >= ny))
    throw InvalidSetting(c.name("open.width"), detail::to_text(open.width),
                         "must leave water between the layers: 2 * width < nx (" + detail::to_text(nx) +
                             ") and < ny (" + detail::to_text(ny) + ")");
}

SurfaceSettings SurfaceSettings::paper() {
  SurfaceSettings s;
  s.nx = 50;
  s.ny = 50;
  s.lattice = LatticeParameters::paper();
  return s;
}

SurfaceSettings SurfaceSettings::physical(const PhysicalParameters& p, int nx, int ny) {
  SurfaceSettings s;
  s.nx = nx;
  s.ny = ny;
  s.lattice = p.to_lattice();
  s.density = p.density;
  return s;
}

}  // namespace shore::water
