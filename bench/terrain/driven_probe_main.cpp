// shore_driven_probe: the validation matrix's driven wheel (D 0.6 m, b 0.15 m) on one soil,
// its material or coupling overridden, against Wong and Reece at their own sinkage and at the
// model's, for taking a miss apart (docs/terrain.md, "Validation matrix").
//   shore_driven_probe soil-part slip [key=value ...]
// A negative slip -D runs the matrix's towed wheel of diameter D (b 0.3 m) instead, against
// Bekker's front-arc integral. Keys: c (Pa), phi_deg, K (m), remould_ratio,
// remould_shear_ratio, remould_length (m), unload_modulus (Pa/m), follow_drift (cells),
// block (columns), iterations, substep (s), cell (m), load (N; default the matrix's driven load).
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>

#include "shore/scenes/soil_cases.h"
#include "shore/scenes/validation_matrix.h"
#include "shore/scenes/wong_reece.h"
#include "shore/terrain/bekker.h"

namespace sc = shore::scenes;

namespace {

/// The load under which Wong and Reece's wheel sinks z, by bisection.
double load_at_sinkage(sc::WongReeceWheel w, double slip, double z) {
  double lo = 1e-3, hi = 100 * w.load;
  for (int it = 0; it < 80; ++it) {
    w.load = 0.5 * (lo + hi);
    (sc::wong_reece(w, slip).sinkage < z ? lo : hi) = w.load;
  }
  return w.load;
}

/// Applies one key=value; false for an unknown key.
bool override(const std::string& key, double v, shore::terrain::Material& m, sc::SoilRun& run, double& load) {
  if (key == "c")
    m.cohesion = v;
  else if (key == "phi_deg")
    m.friction_angle = v * std::numbers::pi / 180;
  else if (key == "K")
    m.shear_modulus = v;
  else if (key == "remould_ratio")
    m.remould_ratio = v;
  else if (key == "remould_shear_ratio")
    m.remould_shear_ratio = v;
  else if (key == "remould_length")
    m.remould_length = v;
  else if (key == "unload_modulus")
    m.unload_modulus = v;
  else if (key == "follow_drift")
    run.coupling.contact.follow_drift = v;
  else if (key == "block")
    run.coupling.contact.block_columns = int(v);
  else if (key == "iterations")
    run.coupling.contact.iterations = int(v);
  else if (key == "substep")
    run.substep = v;
  else if (key == "cell")
    run.terrain.cell = v;
  else if (key == "load")
    load = v;
  else
    return false;
  return true;
}

void towed(const std::string& name, const sc::SoilRun& run, double diameter, double load) {
  sc::WheelCase t;
  t.run = run;
  t.diameter = diameter, t.width = 0.3, t.load = load, t.towed = true;
  const sc::WheelResult w = sc::run_wheel(t);
  const double z =
      shore::terrain::bekker::wheel_sinkage_rolling_integral(run.terrain.material, load, diameter, t.width);
  std::printf("%s towed D %.2f m, %.0f N: sinkage %.5f (integral %.5f, %+.1f %%)\n", name.c_str(), diameter, load,
              w.sinkage, z, 100 * (w.sinkage / z - 1));
}

void driven(const std::string& name, const sc::SoilRun& run, double slip, double load) {
  sc::DrivenWheelCase d;
  d.run = run;
  d.diameter = 0.6, d.width = 0.15, d.load = load, d.slip = slip;
  const sc::DrivenWheelResult r = sc::run_driven_wheel(d);
  sc::WongReeceWheel w;
  w.radius = 0.3, w.width = 0.15, w.load = load, w.soil = run.terrain.material;
  const sc::WongReeceResult ref = sc::wong_reece(w, slip);
  sc::WongReeceWheel same = w;  // Wong and Reece's wheel at the model's sinkage
  same.load = load_at_sinkage(w, slip, r.sinkage);
  const double same_torque = sc::wong_reece(same, slip).torque;
  std::printf(
      "%s slip %.2f: model z %.4f T %.2f pull %.1f R %.1f | WR z %.4f T %.2f pull %.1f R %.1f | "
      "WR at model z: T %.2f (model %+.1f %%), load %.0f\n",
      name.c_str(), slip, r.sinkage, r.torque, r.drawbar_pull, r.resistance, ref.sinkage, ref.torque, ref.drawbar_pull,
      ref.resistance, same_torque, 100 * (r.torque / same_torque - 1), same.load);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return std::printf("usage: shore_driven_probe soil-part slip [key=value ...]\n"), 1;
  const std::string soil = argv[1];
  const double slip = std::atof(argv[2]);
  for (const sc::MatrixSoil& s : sc::matrix_soils()) {
    if (s.name.find(soil) == std::string::npos) continue;
    sc::SoilRun run;
    shore::terrain::Material m = s.material;
    double load = s.driven_load;
    for (int k = 3; k < argc; ++k) {
      const std::string a = argv[k];
      const auto eq = a.find('=');
      if (eq == std::string::npos || !override(a.substr(0, eq), std::atof(a.c_str() + eq + 1), m, run, load))
        return std::printf("unknown setting %s\n", a.c_str()), 1;
    }
    run.terrain.material = m;
    if (slip < 0)
      towed(s.name, run, -slip, load);
    else
      driven(s.name, run, slip, load);
  }
  return 0;
}
