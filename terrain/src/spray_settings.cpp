// The checks and derived values of the spray parameters (shore/terrain/spray.h).
#include <numbers>

#include "shore/core/error.h"
#include "shore/terrain/spray.h"

namespace shore::terrain {

void SprayMaterial::validate(const Check& c) const {
  c.non_negative("adhesion", adhesion);
  c.positive("half_life", half_life);
  c.positive("speed_scale", speed_scale);
  c.positive("exponent", exponent);
  c.positive("particle_size", particle_size);
  c.non_negative("min_speed", min_speed);
  c.in_closed("jitter", jitter, 0.0, 1.0);
  c.non_negative("drag", drag);
}

double SprayMaterial::particle_volume() const {
  return std::numbers::pi / 6.0 * particle_size * particle_size * particle_size;
}

void SpraySettings::validate(const Check& c) const {
  c.at_least("max_particles", max_particles, 0);
  c.positive("gravity", gravity);
  c.positive("max_flight", max_flight);
  // Infinite bounds are allowed (everywhere); NaN and empty ranges are not.
  if (!(x_min < x_max))
    throw InvalidSetting(c.name("x_min / x_max"), detail::to_text(x_min) + " / " + detail::to_text(x_max),
                         "must satisfy x_min < x_max (infinite allowed)");
  if (!(y_min < y_max))
    throw InvalidSetting(c.name("y_min / y_max"), detail::to_text(y_min) + " / " + detail::to_text(y_max),
                         "must satisfy y_min < y_max (infinite allowed)");
}

}  // namespace shore::terrain
