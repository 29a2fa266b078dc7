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
  c.sphere_case.run.terrain.material = m;
  c.sphere_case.run.terrain.cell = cell;
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
  c.plate_case.run.terrain.material = terrain::Material::snow();
  c.plate_case.run.terrain.cell = cell;
  c.plate_case.width = width;
  c.plate_case.pressure = mass * kGravity / (width * width);
  c.plate_case.ramp_seconds = 1.0;
  c.plate_case.settle_seconds = 1.0;
  return c;
}

/// Sand with one edit: a material at an edge of its allowed ranges (Material::validate).
template <class Edit>
terrain::Material sand_with(std::string name, Edit edit) {
  terrain::Material m = terrain::Material::sand();
  m.name = std::move(name);
  edit(m);
  return m;
}

/// The 10 kg ball dropped 1 m onto each material at its edges: Bekker's exponent near 0 and
/// near 3, soil as soft and as stiff as allowed, vertical walls that never slump with
/// everything displaced to the rim, nothing displaced and no angle of repose to speak of,
/// and shear strength near its limits (friction angle near pi/2, 1 MPa cohesion).
void add_material_edges(std::vector<ExtremeCase>& out, double cell) {
  constexpr double half_pi = 1.5707963267948966;
  const terrain::Material edges[] = {
      sand_with("n_0_05", [](terrain::Material& m) { m.bekker_n = 0.05; }),
      sand_with("n_2_95", [](terrain::Material& m) { m.bekker_n = 2.95; }),
      sand_with("softest", [](terrain::Material& m) { m.bekker_kc = 0.0, m.bekker_kphi = 1e3; }),
      sand_with("stiffest", [](terrain::Material& m) { m.bekker_kc = 0.0, m.bekker_kphi = 1e12; }),
      sand_with("vertical_walls",
                [&](terrain::Material& m) {
                  m.theta_stop = m.theta_in = m.theta_out = half_pi, m.alpha = 1.0, m.sigma = 1.0;
                }),
      sand_with(
          "flowing",
          [](terrain::Material& m) { m.theta_stop = m.theta_in = m.theta_out = 1e-3, m.alpha = 0.0, m.sigma = 0.0; }),
      sand_with("strongest_shear", [](terrain::Material& m) { m.friction_angle = 1.55, m.cohesion = 1e6; }),
  };
  for (const terrain::Material& m : edges)
    out.push_back(sphere("material_" + m.name, "10 kg ball (0.2 m) dropped 1 m onto sand with " + m.name, m, cell,
                         1.0 / 240, 0.2, 10.0, 1.0, 1.5));
}

}  // namespace

std::vector<ExtremeCase> extreme_cases(bool smoke) {
  const terrain::Material sand = terrain::Material::sand(), mud = terrain::Material::mud();
  const double coarse = smoke ? 0.02 : 0.01;  // m, the cell of cases that do not vary it
  // 50 m/s at the surface: dropped from v^2 / 2g, falling for v / g.
  const double impact = 50.0, drop = impact * impact / (2 * kGravity), fall = impact / kGravity;
  std::vector<ExtremeCase> cases{
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
  add_material_edges(cases, coarse);
  return cases;
}

ExtremeResult run_extreme(const ExtremeCase& c) {
  ExtremeResult r;
  bool soil_finite = true;
  int substep = 0;
  auto watch = [&](const terrain::Terrain& soil, const bullet::TerrainCoupling&) {
    if (++substep % 10 == 0 && !std::isfinite(soil.volume().total())) soil_finite = false;
  };
  // Either case, watched; its sinkage, reference and run statistics.
  auto run = [&](auto soil_case, auto runner, auto sinkage_of, auto deepest_of) {
    soil_case.run.after_substep = watch;
    const auto result = runner(soil_case);
    r.sinkage = sinkage_of(result);
    r.deepest = deepest_of(result);
    r.reference = std::min(result.reference, soil_case.run.terrain.material.soil_depth);
    r.soil_depth = soil_case.run.terrain.material.soil_depth;
    r.rescues = result.stats.rescues;
    r.wall_seconds = result.stats.wall_seconds;
  };
  if (c.plate) {
    auto sinkage = [](const PlateResult& p) { return p.sinkage; };
    run(c.plate_case, run_plate, sinkage, sinkage);
  } else {
    run(
        c.sphere_case, run_sphere_drop, [](const SphereDropResult& s) { return s.depth; },
        [](const SphereDropResult& s) { return s.max_depth; });
  }
  r.finite = std::isfinite(r.sinkage) && soil_finite;
  return r;
}

}  // namespace shore::scenes
