#pragma once
// Private: a spray particle's flight. Ballistic under gravity along -z with a linear air
// drag k (dv/dt = g - k v, in closed form), and landing: the path is sampled every half
// column of horizontal travel, and where it first passes below the soil top it is cut at
// the linear crossing of (z - soil top) between two samples; the particle lands on the
// column nearest that point. A path that leaves the spray's region, or a flight longer than
// max_flight, is lost.
//
// Two shortcuts that change no result:
//   - a flight whose path stays inside the region and above the highest column top under
//     its whole extent (SprayGround::top_bound) cannot land and is not sampled: z(t) has no
//     minimum inside a step (it is concave, or falls monotonically faster than terminal
//     speed), x(t) and y(t) are monotonic, so the endpoints bound every sample;
//   - the particles in flight at a step's start all fly the whole step: the drag factors of
//     their sample times depend only on the number of samples, and SampleClock keeps them.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "spray_ground.h"
#include "spray_state.h"

namespace shore::terrain {

struct FlightRules {
  FlightRules() = default;
  FlightRules(double g, double k, double longest)
      : gravity(g), drag(k), max_flight(longest), fall(k != 0.0 ? g / k : 0.0) {}
  double gravity = 9.81;     ///< m/s^2
  double drag = 0.0;         ///< 1/s
  double max_flight = 10.0;  ///< s
  double fall = 0.0;         ///< m/s, the terminal speed gravity / drag (with drag), divided once
};

/// A time into a flight with its drag factors: a = (1 - e^(-k t)) / k, e = e^(-k t).
struct FlightTime {
  double t = 0.0, a = 0.0, e = 1.0;
};

/// The sample times of flights lasting exactly `duration()` seconds, with their drag
/// factors, computed once per number of samples instead of once per particle (each needs a
/// det::exp). Scratch: the values are those fly() would compute itself.
class SampleClock {
 public:
  /// Keeps the rows while the drag, the duration and the cell stay the same.
  void reset(const FlightRules& rules, double duration, double cell);
  [[nodiscard]] double duration() const { return duration_; }
  /// Whether a flight with this horizontal velocity ends at end() whatever its number of
  /// samples (fly() times the last sample duration * n / n, which is the duration itself for
  /// every n below the first that rounds otherwise): decided on vx^2 + vy^2, no root.
  [[nodiscard]] bool ends_at_end(double vx, double vy) const { return vx * vx + vy * vy <= same_end_below_; }
  /// The drag factors at the whole duration.
  [[nodiscard]] const FlightTime& end() const { return end_; }
  /// The `samples` sample times (the m-th, 1..samples, at [m - 1]); null if samples >
  /// kMaxSamples.
  [[nodiscard]] const FlightTime* row(int samples);
  [[nodiscard]] std::size_t bytes() const;
  static constexpr int kMaxSamples = 64;
  static constexpr int kMostSamples = 4097;  ///< the most fly() takes

 private:
  double drag_ = 0.0, duration_ = -1.0, cell_ = 0.0;
  double same_end_below_ = 0.0;  ///< m^2/s^2, see ends_at_end
  FlightTime end_;
  std::vector<std::vector<FlightTime>> rows_;  ///< rows_[samples], filled on first use
};

struct FlightEnd {
  enum class Fate { flying, landed, lost } fate = Fate::flying;
  std::int64_t i = 0, j = 0;  ///< the column landed on
};

/// Moves the particle on by `duration` seconds (its state becomes the end of the flight,
/// or the landing point). `clock`, if given and of this duration, supplies the drag factors.
/// `ceiling`, if given, is an upper bound of every column top the flight can pass over
/// (else the ground is asked).
FlightEnd fly(Particle& p, double duration, const SprayGround& ground, const FlightRules& rules,
              SampleClock* clock = nullptr, double ceiling = std::numeric_limits<double>::infinity());

}  // namespace shore::terrain
