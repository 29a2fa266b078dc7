// The extremes of the settings ranges: see shore/scenes/extreme_cases.h.
#include "shore/scenes/extreme_cases.h"

#include <algorithm>
#include <cmath>

namespace shore::scenes {
namespace {

constexpr double kGravity = 9.81;

ExtremeCase sphere(std::string name, std::string what, const terrain::Material& m, double cell, double substep,
                   double diameter, double mass, double height, double seconds) {
  ExtremeCase c;
  c.name = std::move(name);
  c.what = std::move(what);
  c.sphere_case.run.material = m;
  c.sphere_case.run.cell = cell;
  c.sphere_case.run.substep = substep;
  c.sphere_case.diameter = diameter;
  c.sphere_case.mass = mass;
  c.sphere_case.height = height;
  c.sphere_case.seconds = seconds;
  return c;
}

/// A square plate of `mass` on snow, its weight ramped in (the quasi-static reference).
ExtremeCase plate_on_snow(std::string name, std::string what, double cell, double width, double mass) {
  ExtremeCase c;
  c.name = std::move(name);
  c.what = std::move(what);
  c.plate = true;
  c.plate_case.run.material = terrain::Material::snow();
  c.plate_case.run.cell = cell;
  c.plate_case.width = width;
  c.plate_case.pressure = mass * kGravity / (width * width);
  c.plate_case.ramp_seconds = 1.0;
  c.plate_case.settle_seconds = 1.0;
  return c;
}

}  // namespace

std::vector<ExtremeCase> extreme_cases(bool smoke) {
  const terrain::Material sand = terrain::Material::sand(), mud = terrain::Material::mud();
  const double coarse = smoke ? 0.02 : 0.01;  // m, the cell of cases that do not vary it
  // 50 m/s at the surface: dropped from v^2 / 2g, falling for v / g.
  const double impact = 50.0, drop = impact * impact / (2 * kGravity), fall = impact / kGravity;
  return {
      sphere("substep_1_30", "10 kg ball (0.2 m) dropped 1 m onto sand, 1/30 s substeps", sand, coarse, 1.0 / 30, 0.2,
             10.0, 1.0, 1.5),
      sphere("substep_1_2000", "10 kg ball (0.2 m) dropped 1 m onto sand, 1/2000 s substeps", sand, coarse, 1.0 / 2000,
             0.2, 10.0, 1.0, smoke ? 0.8 : 1.5),
      sphere("cell_2mm", "2 kg ball (0.1 m) dropped 0.5 m onto sand, 2 mm cells", sand, 0.002, 1.0 / 240, 0.1, 2.0, 0.5,
             smoke ? 0.8 : 1.5),
      sphere("cell_20cm", "500 kg ball (1 m) dropped 1 m onto sand, 20 cm cells", sand, 0.2, 1.0 / 240, 1.0, 500.0, 1.0,
             1.5),
      plate_on_snow("snow_50g", "0.05 kg plate (5 cm) on snow, weight ramped in", smoke ? 0.01 : 0.005, 0.05, 0.05),
      plate_on_snow("snow_50t", "50 t plate (2 m) on snow, weight ramped in", smoke ? 0.1 : 0.04, 2.0, 50e3),
      sphere("mud_50mps", "10 kg ball (0.2 m) into mud at 50 m/s", mud, coarse, 1.0 / 240, 0.2, 10.0, drop,
             fall + (smoke ? 0.3 : 1.0)),
  };
}

ExtremeResult run_extreme(const ExtremeCase& c) {
  ExtremeResult r;
  bool soil_finite = true;
  int substep = 0;
  auto watch = [&](const terrain::Terrain& soil, const bullet::TerrainCoupling&) {
    if (++substep % 10 == 0 && !std::isfinite(soil.volume().total())) soil_finite = false;
  };
  RunStats stats;
  if (c.plate) {
    PlateCase pc = c.plate_case;
    pc.run.after_substep = watch;
    const PlateResult p = run_plate(pc);
    r.sinkage = p.sinkage;
    r.reference = p.reference;
    r.soil_depth = pc.run.material.soil_depth;
    stats = p.stats;
  } else {
    SphereDropCase sc = c.sphere_case;
    sc.run.after_substep = watch;
    const SphereDropResult s = run_sphere_drop(sc);
    r.sinkage = s.depth;
    r.reference = s.reference;
    r.soil_depth = sc.run.material.soil_depth;
    stats = s.stats;
  }
  r.reference = std::min(r.reference, r.soil_depth);
  r.finite = std::isfinite(r.sinkage) && soil_finite;
  r.rescues = stats.rescues;
  r.wall_seconds = stats.wall_seconds;
  return r;
}

}  // namespace shore::scenes
