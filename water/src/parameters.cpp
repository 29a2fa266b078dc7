#include "shore/water/parameters.h"

#include <cmath>
#include <limits>

#include "shore/core/error.h"

namespace shore::water {

void LatticeParameters::validate() const {
  const Check c{"water.LatticeParameters"};
  c.positive("spacing", spacing);
  c.positive("mass", mass);
  c.positive("stiffness", stiffness);
  c.in_left_open("rest_ratio", rest_ratio, 0.0, 1.0);
  c.non_negative("damping", damping);
}

double LatticeParameters::wave_speed() const {
  return spacing * std::sqrt(3.0 * stiffness * (1.0 - rest_ratio) / mass);
}

double LatticeParameters::transverse_stiffness() const { return stiffness * (1.0 - rest_ratio); }

double LatticeParameters::damping_time() const {
  return damping > 0.0 ? 2.0 * mass / damping : std::numeric_limits<double>::infinity();
}

LatticeParameters LatticeParameters::paper() { return LatticeParameters{}; }

void PhysicalParameters::validate() const {
  const Check c{"water.PhysicalParameters"};
  c.positive("cell", cell);
  c.positive("depth", depth);
  c.positive("density", density);
  if (!(damping_time > 0.0)) throw InvalidSetting(c.name("damping_time"), detail::to_text(damping_time), "must be > 0");
  if (!(rest_ratio > 0.0 && rest_ratio < 1.0))
    throw InvalidSetting(c.name("rest_ratio"), detail::to_text(rest_ratio), "must be in (0, 1) (pre-tension)");
  c.positive("gravity", gravity);
  c.non_negative("wave_speed", wave_speed);
}

double PhysicalParameters::target_wave_speed() const {
  return wave_speed > 0.0 ? wave_speed : std::sqrt(gravity * depth);
}

LatticeParameters PhysicalParameters::to_lattice() const {
  validate();
  LatticeParameters p;
  p.spacing = cell;
  p.rest_ratio = rest_ratio;
  p.mass = density * cell * cell * depth;
  const double cw = target_wave_speed();
  const double cw2 = cw * cw;
  p.stiffness = cw2 * p.mass / (3.0 * cell * cell * (1.0 - rest_ratio));
  p.damping = std::isfinite(damping_time) ? 2.0 * p.mass / damping_time : 0.0;
  return p;
}

}  // namespace shore::water
