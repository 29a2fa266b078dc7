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

FlightTime flight_time(double t, const FlightRules& r) {
  if (r.drag == 0.0) return {t, t, 1.0};
  const double a = drag_factor(r.drag, t);
  return {t, a, 1.0 - r.drag * a};
}

/// The particle's state after f.t seconds of free flight (inline: once or twice per particle
/// and step, and once per sample).
[[gnu::always_inline]] inline Particle advanced(const Particle& p, const FlightTime& f, const FlightRules& r) {
  Particle q = p;
  const double g = r.gravity, k = r.drag, t = f.t;
  if (k == 0.0) {
    q.position.x = p.position.x + p.velocity.x * t, q.position.y = p.position.y + p.velocity.y * t,
    q.position.z = p.position.z + p.velocity.z * t - 0.5 * g * t * t;
    q.velocity.z = p.velocity.z - g * t;
  } else {
    const double a = f.a, e = f.e;  // e = e^(-k t)
    const double fall = r.fall;     // terminal speed, g / k
    q.position.x = p.position.x + p.velocity.x * a, q.position.y = p.position.y + p.velocity.y * a;
    q.position.z = p.position.z + (p.velocity.z + fall) * a - fall * t;
    q.velocity.x = p.velocity.x * e, q.velocity.y = p.velocity.y * e, q.velocity.z = (p.velocity.z + fall) * e - fall;
  }
  q.age = p.age + t;
  return q;
}

/// How far above the soil top a flight point is (negative: below it).
double clearance(const Particle& q, const SprayGround& ground) {
  return q.position.z - ground.height(ground.column_i(q.position.x), ground.column_j(q.position.y));
}

/// Whether a path from `from` to `to` (both ends of one free flight, `from` inside the
/// region) stays inside the region and above every column top near its extent. The samples
/// between lie within the ends' box (x, y monotonic) and no lower than the lower end (z has
/// no interior minimum), up to rounding far below kSlack.
bool clear_of_ground(const Particle& from, const Particle& to, const SprayGround& ground, double ceiling) {
  constexpr double kSlack = 1e-9;  // m per m of coordinate (and 1e-9 m)
  const double sx = kSlack * (1.0 + std::abs(to.position.x)), sy = kSlack * (1.0 + std::abs(to.position.y));
  if (!ground.inside(to.position.x - sx, to.position.y - sy) || !ground.inside(to.position.x + sx, to.position.y + sy))
    return false;
  const double low = std::min(from.position.z, to.position.z) -
                     kSlack * (1.0 + std::max(std::abs(from.position.z), std::abs(to.position.z)));
  if (low > ceiling) return true;
  return low > ground.top_bound_over(std::min(from.position.x, to.position.x), std::min(from.position.y, to.position.y),
                                     std::max(from.position.x, to.position.x),
                                     std::max(from.position.y, to.position.y));
}

}  // namespace

void SampleClock::reset(const FlightRules& rules, double duration, double cell) {
  if (rules.drag == drag_ && duration == duration_ && cell == cell_) return;
  drag_ = rules.drag, duration_ = duration, cell_ = cell;
  for (std::vector<FlightTime>& row : rows_) row.clear();
  const FlightRules drag_only{0.0, drag_, 0.0};
  end_ = flight_time(duration_, drag_only);  // duration * 1 / 1
  // The first sample count whose last time duration * n / n is not the duration; fly()
  // samples at most 4097 times.
  int first_other = kMostSamples + 1;
  for (int n = 2; n <= kMostSamples; ++n)
    if (duration_ * static_cast<double>(n) / static_cast<double>(n) != duration_) {
      first_other = n;
      break;
    }
  // fly() takes ceil(travel / (cell / 2)) + 1 samples, travel = sqrt(vx^2 + vy^2) duration;
  // ceil(q) <= k for q <= k: the root and three roundings stay far inside the 2^-30 margin.
  const double k = static_cast<double>(first_other - 2), top = k * (0.5 * cell_) / duration_;
  same_end_below_ =
      first_other > kMostSamples ? std::numeric_limits<double>::infinity() : top * top * (1.0 - 0x1.0p-30);
}

const FlightTime* SampleClock::row(int samples) {
  if (samples > kMaxSamples) return nullptr;
  if (rows_.size() <= static_cast<std::size_t>(samples)) rows_.resize(static_cast<std::size_t>(samples) + 1);
  std::vector<FlightTime>& row = rows_[static_cast<std::size_t>(samples)];
  if (row.empty()) {
    const FlightRules rules{0.0, drag_, 0.0};
    for (int n = 1; n <= samples; ++n)  // the times fly() computes
      row.push_back(flight_time(duration_ * static_cast<double>(n) / static_cast<double>(samples), rules));
  }
  return row.data();
}

std::size_t SampleClock::bytes() const {
  std::size_t b = rows_.capacity() * sizeof(std::vector<FlightTime>);
  for (const std::vector<FlightTime>& row : rows_) b += row.capacity() * sizeof(FlightTime);
  return b;
}

namespace {

/// The samples a flight takes, every half column of horizontal travel (the horizontal speed
/// only falls), and their drag factors if the clock keeps them (else null: computed each).
struct Sampling {
  int samples = 0;
  const FlightTime* clocked = nullptr;
};

/// `clock`: the clock of this flight's duration, or null.
Sampling count_samples(const Particle& p, double duration, const SprayGround& ground, SampleClock* clock) {
  const double travel = std::sqrt(p.velocity.x * p.velocity.x + p.velocity.y * p.velocity.y) * duration;
  const int samples = static_cast<int>(std::min(4096.0, std::ceil(travel / (0.5 * ground.cell())))) + 1;
  return {samples, clock != nullptr ? clock->row(samples) : nullptr};
}

/// The m-th sample time (1..samples) of a flight of `duration` seconds.
FlightTime sample_time(const Sampling& s, int m, double duration, const FlightRules& rules) {
  if (s.clocked != nullptr) return s.clocked[m - 1];
  return flight_time(duration * static_cast<double>(m) / static_cast<double>(s.samples), rules);
}

/// A flight that may land: its path sampled against the ground, from p (inside the region)
/// to `last` (its state at the last sample). Out of fly() so that the flights that cannot
/// land (most of them) pay for none of it.
FlightEnd sampled(Particle& p, const Particle& last, double duration, const Sampling& s, const SprayGround& ground,
                  const FlightRules& rules) {
  FlightEnd end;
  Particle before = p;
  double above = clearance(p, ground);
  if (!(above > 0.0)) {  // starts in the soil: lands where it is
    end = {FlightEnd::Fate::landed, ground.column_i(p.position.x), ground.column_j(p.position.y)};
    return end;
  }
  for (int m = 1; m <= s.samples; ++m) {
    const FlightTime at = sample_time(s, m, duration, rules);
    const Particle now = m == s.samples ? last : advanced(p, at, rules);
    if (!ground.inside(now.position.x, now.position.y)) {
      p = now;
      end.fate = FlightEnd::Fate::lost;
      return end;
    }
    const double h = clearance(now, ground);
    if (!(h > 0.0)) {
      const double t0 = duration * static_cast<double>(m - 1) / static_cast<double>(s.samples);
      const double cut = t0 + (at.t - t0) * (above / (above - h));
      p = advanced(p, flight_time(cut, rules), rules);
      end = {FlightEnd::Fate::landed, ground.column_i(p.position.x), ground.column_j(p.position.y)};
      return end;
    }
    before = now;
    above = h;
  }
  p = before;
  if (p.age > rules.max_flight) end.fate = FlightEnd::Fate::lost;
  return end;
}

}  // namespace

FlightEnd fly(Particle& p, double duration, const SprayGround& ground, const FlightRules& rules, SampleClock* clock,
              double ceiling) {
  FlightEnd end;
  if (!ground.inside(p.position.x, p.position.y)) {
    end.fate = FlightEnd::Fate::lost;
    return end;
  }
  SampleClock* const here = clock != nullptr && clock->duration() == duration ? clock : nullptr;
  // The samples are counted only once the flight may land, where the end of the flight does
  // not depend on them.
  const bool known_end = here != nullptr && here->ends_at_end(p.velocity.x, p.velocity.y);
  Sampling s;
  if (!known_end) s = count_samples(p, duration, ground, here);
  const Particle last = advanced(p, known_end ? here->end() : sample_time(s, s.samples, duration, rules), rules);
  if (clear_of_ground(p, last, ground, ceiling)) {  // cannot land this time: what the samples would all find
    p = last;
    if (p.age > rules.max_flight) end.fate = FlightEnd::Fate::lost;
    return end;
  }
  if (known_end) s = count_samples(p, duration, ground, here);
  return sampled(p, last, duration, s, ground, rules);
}

}  // namespace shore::terrain
