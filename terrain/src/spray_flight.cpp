#include "spray_flight.h"

#include <algorithm>
#include <cmath>

#include "shore/core/det_math.h"

namespace shore::terrain {

namespace {

/// (1 - e^(-k t)) / k, the distance factor of a dragged flight (t when k = 0), without the
/// cancellation of 1 - e^(-k t) for small k t.
double drag_factor(double k, double t) {
  const double x = k * t;
  if (x < 1e-3) return t * (1.0 - x * (0.5 - x * (1.0 / 6.0 - x / 24.0)));
  return (1.0 - det::exp(-x)) / k;
}

/// The particle's state after t seconds of free flight.
Particle advanced(const Particle& p, double t, const FlightRules& r) {
  Particle q = p;
  const double g = r.gravity, k = r.drag;
  if (k == 0.0) {
    q.x = p.x + p.vx * t, q.y = p.y + p.vy * t, q.z = p.z + p.vz * t - 0.5 * g * t * t;
    q.vz = p.vz - g * t;
  } else {
    const double a = drag_factor(k, t), e = 1.0 - k * a;  // e = e^(-k t)
    const double fall = g / k;                            // terminal speed
    q.x = p.x + p.vx * a, q.y = p.y + p.vy * a;
    q.z = p.z + (p.vz + fall) * a - fall * t;
    q.vx = p.vx * e, q.vy = p.vy * e, q.vz = (p.vz + fall) * e - fall;
  }
  q.age = p.age + t;
  return q;
}

/// How far above the soil top a flight point is (negative: below it).
double clearance(const Particle& q, const SprayGround& ground) {
  return q.z - ground.height(ground.column_i(q.x), ground.column_j(q.y));
}

}  // namespace

FlightEnd fly(Particle& p, double duration, const SprayGround& ground, const FlightRules& rules) {
  FlightEnd end;
  // Samples every half column of horizontal travel (the horizontal speed only falls).
  const double travel = std::sqrt(p.vx * p.vx + p.vy * p.vy) * duration;
  const int samples = static_cast<int>(std::min(4096.0, std::ceil(travel / (0.5 * ground.cell())))) + 1;
  Particle before = p;
  double above = clearance(p, ground);
  if (!ground.inside(p.x, p.y)) {
    end.fate = FlightEnd::Fate::lost;
    return end;
  }
  if (!(above > 0.0)) {  // starts in the soil: lands where it is
    end = {FlightEnd::Fate::landed, ground.column_i(p.x), ground.column_j(p.y)};
    return end;
  }
  for (int m = 1; m <= samples; ++m) {
    const double t = duration * static_cast<double>(m) / static_cast<double>(samples);
    const Particle now = advanced(p, t, rules);
    if (!ground.inside(now.x, now.y)) {
      p = now;
      end.fate = FlightEnd::Fate::lost;
      return end;
    }
    const double h = clearance(now, ground);
    if (!(h > 0.0)) {
      const double t0 = duration * static_cast<double>(m - 1) / static_cast<double>(samples);
      const double cut = t0 + (t - t0) * (above / (above - h));
      const Particle at = advanced(p, cut, rules);
      p = at;
      end = {FlightEnd::Fate::landed, ground.column_i(at.x), ground.column_j(at.y)};
      return end;
    }
    before = now;
    above = h;
  }
  p = before;
  if (p.age > rules.max_flight) end.fate = FlightEnd::Fate::lost;
  return end;
}

}  // namespace shore::terrain
