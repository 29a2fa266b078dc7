// shore_driven_probe: the matrix's driven wheel on one soil with its material overridden,
// against Wong and Reece at their own sinkage and at the model's (the torque's causes
// taken apart). shore_driven_probe soil slip [key=value ...]
// keys: c, phi_deg, K, remould_ratio, remould_shear_ratio, remould_length, unload_modulus
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>

#include "shore/scenes/soil_cases.h"
#include "shore/scenes/validation_matrix.h"
#include "shore/scenes/wong_reece.h"

namespace sc = shore::scenes;

namespace {
/// Wong and Reece at a given sinkage: the load whose sinkage it is, by bisection.
sc::WongReeceResult at_sinkage(sc::WongReeceWheel w, double slip, double z) {
  double lo = 1e-3, hi = 100 * w.load;
  for (int it = 0; it < 80; ++it) {
    w.load = 0.5 * (lo + hi);
    (sc::wong_reece(w, slip).sinkage < z ? lo : hi) = w.load;
  }
  return sc::wong_reece(w, slip);
}
}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return std::printf("usage: shore_driven_probe soil slip [key=value ...]\n"), 1;
  const std::string soil = argv[1];
  const double slip = std::atof(argv[2]);
  for (const sc::MatrixSoil& s : sc::matrix_soils()) {
    if (s.name.find(soil) == std::string::npos) continue;
    shore::terrain::Material m = s.material;
    sc::DrivenWheelCase d;
    for (int k = 3; k < argc; ++k) {
      const std::string a = argv[k];
      const auto eq = a.find('=');
      const std::string key = a.substr(0, eq);
      const double v = std::atof(a.c_str() + eq + 1);
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
        d.run.coupling.contact.follow_drift = v;
      else if (key == "block")
        d.run.coupling.contact.block_columns = int(v);
      else if (key == "iterations")
        d.run.coupling.contact.iterations = int(v);
      else if (key == "substep")
        d.run.substep = v;
      else if (key == "cell")
        d.run.terrain.cell = v;
      else
        return std::printf("unknown key %s\n", key.c_str()), 1;
    }
    d.run.terrain.material = m;
    d.diameter = 0.6, d.width = 0.15, d.load = s.driven_load, d.slip = slip;
    const sc::DrivenWheelResult r = sc::run_driven_wheel(d);
    sc::WongReeceWheel w;
    w.radius = 0.3, w.width = 0.15, w.load = s.driven_load, w.soil = m;
    const sc::WongReeceResult ref = sc::wong_reece(w, slip), same = at_sinkage(w, slip, r.sinkage);
    sc::WongReeceWheel f = w;
    f.front_only = true;
    const sc::WongReeceResult front = at_sinkage(f, slip, r.sinkage);
    std::printf(
        "%s slip %.2f: model z %.4f T %.2f pull %.1f R %.1f | WR z %.4f T %.2f pull %.1f R %.1f | "
        "WR at model z: T %.2f (%+.1f %%) load %.0f | front-only at model z: T %.2f load %.0f\n",
        s.name.c_str(), slip, r.sinkage, r.torque, r.drawbar_pull, r.resistance, ref.sinkage, ref.torque,
        ref.drawbar_pull, ref.resistance, same.torque, 100 * (r.torque / same.torque - 1),
        0.0 +
            [&] {
              sc::WongReeceWheel q = w;
              (void)q;
              return 0.0;
            }() +
            0 * same.torque +
            [&] {
              double lo = 1e-3, hi = 100 * w.load;
              sc::WongReeceWheel q = w;
              for (int it = 0; it < 80; ++it) {
                q.load = 0.5 * (lo + hi);
                (sc::wong_reece(q, slip).sinkage < r.sinkage ? lo : hi) = q.load;
              }
              return q.load;
            }(),
        front.torque,
        [&] {
          double lo = 1e-3, hi = 100 * w.load;
          sc::WongReeceWheel q = f;
          for (int it = 0; it < 80; ++it) {
            q.load = 0.5 * (lo + hi);
            (sc::wong_reece(q, slip).sinkage < r.sinkage ? lo : hi) = q.load;
          }
          return q.load;
        }());
  }
  return 0;
}
