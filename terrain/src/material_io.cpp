// One material in the saved terrain state's byte layout (material_io.h).

#include "material_io.h"

#include <cstdint>
#include <string>

#include "spray_io.h"

namespace shore::terrain {

/// A material's name, soil, bearing and shear fields, in the file's order (its spray and
/// unload_modulus follow, with the terrain's spray settings between them in the header).
void write_material_fields(Writer& w, const Material& m) {
  w.put(static_cast<std::uint32_t>(m.name.size()));
  for (char c : m.name) w.put(c);
  for (double v : {m.theta_stop, m.sigma, m.theta_in, m.theta_out, m.alpha, m.bekker_n, m.bekker_kc, m.bekker_kphi,
                   m.friction, m.soil_depth})
    w.put(v);
  w.put(static_cast<std::uint8_t>(m.rigid ? 1 : 0));
  for (double v :
       {m.cohesion, m.friction_angle, m.shear_modulus, m.remould_ratio, m.remould_shear_ratio, m.remould_length})
    w.put(v);
}

void write_material(Writer& w, const Material& m) {
  write_material_fields(w, m);
  write_spray_material(w, m.spray);
  w.put(m.unload_modulus);
}

Material read_material(Reader& r) {
  Material m;
  const auto name_size = r.get<std::uint32_t>("palette");
  if (name_size > 4096) r.fail("palette material name of " + std::to_string(name_size) + " bytes (corrupt)");
  m.name = r.get_string(name_size, "palette");
  for (double* v : {&m.theta_stop, &m.sigma, &m.theta_in, &m.theta_out, &m.alpha, &m.bekker_n, &m.bekker_kc,
                    &m.bekker_kphi, &m.friction, &m.soil_depth})
    *v = r.get<double>("palette");
  m.rigid = r.get<std::uint8_t>("palette") != 0;
  for (double* v :
       {&m.cohesion, &m.friction_angle, &m.shear_modulus, &m.remould_ratio, &m.remould_shear_ratio, &m.remould_length})
    *v = r.get<double>("palette");
  SprayMaterial& p = m.spray;
  for (double* v :
       {&p.adhesion, &p.half_life, &p.speed_scale, &p.exponent, &p.particle_size, &p.min_speed, &p.jitter, &p.drag})
    *v = r.get<double>("palette");
  m.unload_modulus = r.get<double>("palette");
  return m;
}

}  // namespace shore::terrain
