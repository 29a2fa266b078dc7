#pragma once
// Private: a spray particle's flight. Ballistic under gravity along -z with a linear air
// drag k (dv/dt = g - k v, in closed form), and landing: the path is sampled every half
// column of horizontal travel, and where it first passes below the soil top it is cut at
// the linear crossing of (z - soil top) between two samples; the particle lands on the
// column nearest that point. A path that leaves the spray's region, or a flight longer than
// max_flight, is lost.

#include <cstdint>

#include "spray_ground.h"
#include "spray_state.h"

namespace shore::terrain {

struct FlightRules {
  double gravity = 9.81;     ///< m/s^2
  double drag = 0.0;         ///< 1/s
  double max_flight = 10.0;  ///< s
};

struct FlightEnd {
  enum class Fate { flying, landed, lost } fate = Fate::flying;
  std::int64_t i = 0, j = 0;  ///< the column landed on
};

/// Moves the particle on by `duration` seconds (its state becomes the end of the flight,
/// or the landing point).
FlightEnd fly(Particle& p, double duration, const SprayGround& ground, const FlightRules& rules);

}  // namespace shore::terrain
