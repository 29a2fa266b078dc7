#include "shore/terrain/material.h"

#include <numbers>

#include "shore/core/error.h"

namespace shore::terrain {

void Material::validate() const {
  const Check c{"terrain.Material(" + name + ")"};
  constexpr double half_pi = std::numbers::pi / 2;
  c.in_left_open("theta_stop", theta_stop, 0.0, half_pi);
  c.in_left_open("theta_in", theta_in, 0.0, half_pi);
  c.in_left_open("theta_out", theta_out, 0.0, half_pi);
  c.in_closed("sigma", sigma, 0.0, 1.0);
  c.in_closed("alpha", alpha, 0.0, 1.0);
  if (!(bekker_n > 0.0 && bekker_n < 3.0))
    throw InvalidSetting(c.name("bekker_n"), detail::to_text(bekker_n), "must be in (0, 3)");
  c.non_negative("bekker_kc", bekker_kc);
  c.non_negative("bekker_kphi", bekker_kphi);
  if (!(bekker_kc + bekker_kphi > 0.0))
    throw InvalidSetting(c.name("bekker_kc + bekker_kphi"), detail::to_text(bekker_kc + bekker_kphi),
                         "must be > 0 (the soil must bear something)");
  c.non_negative("cohesion", cohesion);
  if (!(friction_angle >= 0.0 && friction_angle < half_pi))
    throw InvalidSetting(c.name("friction_angle"), detail::to_text(friction_angle), "must be in [0, pi/2) rad");
  c.positive("shear_modulus", shear_modulus);
  if (!(remould_ratio >= 0.0 && remould_ratio < 1.0))
    throw InvalidSetting(c.name("remould_ratio"), detail::to_text(remould_ratio), "must be in [0, 1)");
  if (!(remould_shear_ratio >= 0.0 && remould_shear_ratio < 1.0))
    throw InvalidSetting(c.name("remould_shear_ratio"), detail::to_text(remould_shear_ratio), "must be in [0, 1)");
  c.positive("remould_length", remould_length);
  c.non_negative("unload_modulus", unload_modulus);
  c.non_negative("friction", friction);
  c.positive("soil_depth", soil_depth);
  spray.validate(Check{c.name("spray")});
}

Material Material::sand() { return Material{}; }

Material Material::mud() {
  Material m;
  m.name = "mud";
  m.theta_stop = 1.1;
  m.sigma = 0.2;
  m.theta_in = 1.57;
  m.theta_out = 1.1;
  m.alpha = 0.41;
  m.bekker_n = 0.7;
  m.bekker_kc = 16.03e3;
  m.bekker_kphi = 1262.53e3;
  m.cohesion = 2.07e3;
  m.friction_angle = 10.0 * std::numbers::pi / 180.0;
  m.shear_modulus = 0.01;
  m.unload_modulus = 0.0;  // rigid-plastic: see Material::unload_modulus
  m.friction = 0.4;
  m.spray.adhesion = 0.004;
  m.spray.half_life = 0.3;
  m.spray.speed_scale = 6.0;
  m.spray.exponent = 2.0;
  m.spray.particle_size = 0.012;
  m.spray.min_speed = 0.5;
  m.spray.jitter = 0.3;
  m.spray.drag = 0.3;
  return m;
}

Material Material::snow() {
  Material m;
  m.name = "snow";
  m.theta_stop = 1.57;
  m.sigma = 0.2;
  m.theta_in = 1.57;
  m.theta_out = 1.57;
  m.alpha = 0.0;
  m.bekker_n = 1.6;
  m.bekker_kc = 4.37e3;
  m.bekker_kphi = 196.72e3;
  m.cohesion = 1.03e3;
  m.friction_angle = 19.7 * std::numbers::pi / 180.0;
  m.shear_modulus = 0.025;
  m.unload_modulus = 0.0;  // rigid-plastic: see Material::unload_modulus
  m.friction = 0.2;
  m.spray.adhesion = 0.002;
  m.spray.half_life = 0.1;
  m.spray.speed_scale = 4.0;
  m.spray.exponent = 2.0;
  m.spray.particle_size = 0.008;
  m.spray.min_speed = 0.3;
  m.spray.jitter = 0.3;
  m.spray.drag = 2.5;
  return m;
}

Material Material::rigid_ground() {
  Material m;
  m.name = "rigid";
  m.rigid = true;
  m.friction = 0.8;
  m.spray.adhesion = 0.0;
  return m;
}

Material Material::preset(const std::string& preset_name) {
  if (preset_name == "sand") return sand();
  if (preset_name == "mud") return mud();
  if (preset_name == "snow") return snow();
  if (preset_name == "rigid") return rigid_ground();
  throw InvalidSetting("terrain.Material.preset", preset_name, "must be one of sand, mud, snow, rigid");
}

}  // namespace shore::terrain
