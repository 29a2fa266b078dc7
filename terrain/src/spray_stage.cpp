#include "spray_stage.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <utility>

#include "capacity_bytes.h"
#include "shore/core/det_math.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace shore::terrain {

void Spray::step(TileStore& store, const TerrainSettings& s, std::span<const Material> palette,
                 std::span<const Imprint> imprints, double dt, StepReport& report) {
  SprayGround ground(store, s, palette, &untiled_tops_, &tiled_tops_);
  const FlightRules rules{s.spray.gravity, s.material.spray.drag, s.spray.max_flight};
  set_materials(s, palette);
  fly_all(ground, rules, dt, report);
  cling_all(ground, s, palette, rules, imprints, dt, report);
  ++state.step;
}

// A terrain with one material keeps no indices and one set of rules (its particles and
// pieces are all entry 0's); with a map every particle has its index, and each palette
// entry its flight rules and sample clock.
void Spray::set_materials(const TerrainSettings& s, std::span<const Material> palette) {
  flight_by_index_.clear();
  if (palette.size() <= 1) {
    std::vector<std::uint8_t>().swap(state.particle_materials);  // all 0: the set_palette checks
    return;
  }
  state.particle_materials.resize(state.particles.size(), 0);  // a palette set since: what flies is entry 0's
  for (const Material& m : palette) flight_by_index_.emplace_back(s.spray.gravity, m.spray.drag, s.spray.max_flight);
  if (clocks_.size() < palette.size()) clocks_.resize(palette.size());
}

void Spray::fly_all(SprayGround& ground, const FlightRules& rules, double dt, StepReport& report) {
  clock_.reset(rules, dt, ground.cell());
  for (std::size_t m = 0; m < flight_by_index_.size(); ++m) clocks_[m].reset(flight_by_index_[m], dt, ground.cell());
  cover_flights(ground, dt);
  if (flight_by_index_.empty())
    fly_each<false>(ground, rules, dt, report);
  else
    fly_each<true>(ground, rules, dt, report);
}

// kMap false: one material, the loop as it was before maps (no index read or moved).
template <bool kMap>
void Spray::fly_each(SprayGround& ground, const FlightRules& rules, double dt, StepReport& report) {
  std::vector<std::uint8_t>& materials = state.particle_materials;
  std::size_t kept = 0;
  for (std::size_t k = 0; k < state.particles.size(); ++k) {  // oldest first; landings raise columns in this order
    Particle& p = state.particles[k];  // moved in place (kept <= k: no particle still to fly is overwritten)
    std::uint8_t index = 0;
    if constexpr (kMap) index = materials[k];
    // the ceiling as raised by the landings so far
    const FlightEnd end = fly(p, dt, ground, kMap ? flight_by_index_[index] : rules, kMap ? &clocks_[index] : &clock_,
                              ground.ceiling(state.particles.size()));
    if (end.fate != FlightEnd::Fate::flying) {
      land(ground, p, end, report);
    } else if (kept++ != k) {
      state.particles[kept - 1] = p;
      if constexpr (kMap) materials[kept - 1] = index;
    }
  }
  state.particles.resize(kept);
  if constexpr (kMap) materials.resize(kept);
}

// The box every particle's path this step lies in (the horizontal speed only falls).
void Spray::cover_flights(SprayGround& ground, double dt) const {
  if (state.particles.empty()) return;
  double x0 = state.particles[0].position.x, x1 = x0, y0 = state.particles[0].position.y, y1 = y0;
#if defined(__SSE2__)
  // x and y side by side, the same operations: _mm_min_pd(v, m) is v < m ? v : m, as
  // std::min(m, v); _mm_max_pd(v, m) is v > m ? v : m, as std::max(m, v); clearing the
  // sign bit is std::abs.
  static_assert(offsetof(Vec3, y) == offsetof(Vec3, x) + sizeof(double));
  const __m128d magnitude = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffff)), step = _mm_set1_pd(dt);
  __m128d low = _mm_set_pd(y0, x0), high = low;
  for (const Particle& p : state.particles) {
    const __m128d at = _mm_loadu_pd(&p.position.x),
                  reach = _mm_mul_pd(_mm_and_pd(_mm_loadu_pd(&p.velocity.x), magnitude), step);
    low = _mm_min_pd(_mm_sub_pd(at, reach), low);
    high = _mm_max_pd(_mm_add_pd(at, reach), high);
  }
  double lo[2], hi[2];
  _mm_storeu_pd(lo, low), _mm_storeu_pd(hi, high);
  x0 = lo[0], y0 = lo[1], x1 = hi[0], y1 = hi[1];
#else
  for (const Particle& p : state.particles) {
    const double dx = std::abs(p.velocity.x) * dt, dy = std::abs(p.velocity.y) * dt;
    x0 = std::min(x0, p.position.x - dx), x1 = std::max(x1, p.position.x + dx);
    y0 = std::min(y0, p.position.y - dy), y1 = std::max(y1, p.position.y + dy);
  }
#endif
  ground.cover(x0, y0, x1, y1);
}

void Spray::land(SprayGround& ground, const Particle& p, const FlightEnd& end, StepReport& report) {
  if (end.fate == FlightEnd::Fate::landed) {
    ground.lay(end.i, end.j, p.volume);
    ++state.counts.landed;
    ++report.particles_landed;
  } else {
    state.lost += p.volume;
    ++state.counts.lost;
    ++report.particles_lost;
  }
}

void Spray::drop(SprayGround& ground, const Drop& d) {
  if (ground.inside(d.x, d.y))
    ground.lay(ground.column_i(d.x), ground.column_j(d.y), d.volume);
  else
    state.lost += d.volume;
}

void Spray::set_gone_down(SprayGround& ground, const ClingingBody& body) {
  Cling::set_all_down(body, drops_);
  state.counts.set_down += static_cast<std::int64_t>(drops_.size());
  for (const Drop& d : drops_) drop(ground, d);
  drops_.clear();
}

namespace {
MaterialRules material_rules(const SprayMaterial& m, double cell, double dt) {
  MaterialRules r(m.min_speed);
  r.capacity = m.adhesion * cell * cell;
  r.particle_volume = m.particle_volume();
  r.inverse_particle_volume = 1.0 / r.particle_volume;
  r.shed_share = 1.0 - det::exp(-std::numbers::ln2 * dt / m.half_life);
  r.jitter = m.jitter;
  return r;
}

/// What the settings make of the cling rule for a step of dt seconds, the step'th.
ClingRules cling_rules(const TerrainSettings& s, std::span<const Material> palette, double dt, std::int64_t step) {
  ClingRules r;
  r.dt = dt;
  r.cell = s.cell;
  r.tolerance = s.contact_tolerance;
  r.one = material_rules(s.material.spray, s.cell, dt);
  r.most_capacity = r.one.capacity, r.least_min_speed = s.material.spray.min_speed;
  // A map: a piece loads, sheds and throws by the material it holds.
  if (palette.size() > 1)
    for (const Material& entry : palette) {
      r.by_index.push_back(material_rules(entry.spray, s.cell, dt));
      r.most_capacity = std::max(r.most_capacity, r.by_index.back().capacity);
      r.least_min_speed = std::min(r.least_min_speed, entry.spray.min_speed);
    }
  r.seed = s.spray.seed;
  r.step = step;
  return r;
}
}  // namespace

// Bodies by key (the imprints' order never matters), merged with the bodies soil clung to
// last step: a body missing from this step sets its soil down. A body stepped every n-th
// step (Imprint::cling_every) is kept as it is on the others, and stepped over the time
// since its last clinging step (ClingingBody::stepped), whatever its cadence was meanwhile:
// exponential shedding then sheds over any sequence of cadences what it sheds step by step.
void Spray::cling_all(SprayGround& ground, const TerrainSettings& s, std::span<const Material> palette,
                      const FlightRules& rules, std::span<const Imprint> imprints, double dt, StepReport& report) {
  const ClingRules r = cling_rules(s, palette, dt, state.step);
  rules_over_.clear();
  auto sprays = [&](const Imprint& im) { return im.spray && !im.hold; };
  if (state.bodies.empty() && std::none_of(imprints.begin(), imprints.end(), [&](const Imprint& im) {
        return sprays(im) && Cling::can_start(im, ground, r);
      }))
    return;  // nothing clings and nothing moves fast enough to start: no work, no memory
  order_.clear();
  for (std::size_t k = 0; k < imprints.size(); ++k)
    if (sprays(imprints[k])) order_.push_back(k);
  std::sort(order_.begin(), order_.end(),
            [&](std::size_t a, std::size_t b) { return imprints[a].key < imprints[b].key; });
  next_bodies_.clear();
  std::vector<ClingingBody>& old = state.bodies;
  std::size_t b = 0;
  const std::int64_t set_down_before = cling_.set_down_count;
  for (const std::size_t k : order_) {
    const Imprint& im = imprints[k];
    for (; b < old.size() && old[b].key < im.key; ++b) set_gone_down(ground, old[b]);
    ClingingBody body;
    body.key = im.key;
    if (b < old.size() && old[b].key == im.key) body = std::move(old[b++]);
    if (state.step % im.cling_every != 0) {  // not its step: kept as it is
      if (!body.cells.empty()) next_bodies_.push_back(std::move(body));
      continue;
    }
    // A body new to the step holds nothing to shed: the step's own rules.
    const std::int64_t elapsed = body.cells.empty() ? 1 : state.step - body.stepped;
    const double picked =
        cling_.step(body, im, ground, elapsed == 1 ? r : rules_over(s, palette, dt, elapsed), shed_, drops_);
    body.stepped = state.step;
    report.picked_volume += picked;
    state.counts.picked_volume += picked;
    settle(ground, s, palette, rules, report);
    if (!body.cells.empty()) next_bodies_.push_back(std::move(body));
  }
  for (; b < old.size(); ++b) set_gone_down(ground, old[b]);
  old.swap(next_bodies_);
  state.counts.set_down += cling_.set_down_count - set_down_before;
}

const ClingRules& Spray::rules_over(const TerrainSettings& s, std::span<const Material> palette, double dt,
                                    std::int64_t elapsed) {
  for (const auto& [steps, made] : rules_over_)
    if (steps == elapsed) return made;
  return rules_over_.emplace_back(elapsed, cling_rules(s, palette, dt * static_cast<double>(elapsed), state.step))
      .second;
}

// Sumner's test: a candidate flies where (speed / s)^gamma exceeds its uniform number.
void Spray::settle(SprayGround& ground, const TerrainSettings& s, std::span<const Material> palette,
                   const FlightRules& rules, StepReport& report) {
  for (const Drop& d : drops_) drop(ground, d);
  drops_.clear();
  const bool map = !flight_by_index_.empty();
  // A piece's candidates come one after another: its material and speed ratio once for them.
  std::size_t last = shed_.pieces.size();
  const SprayMaterial* m = nullptr;
  double ratio = 0.0;
  for (const Candidate& c : shed_.candidates) {
    const ShedPiece& piece = shed_.pieces[c.piece];
    if (c.piece != last) {
      last = c.piece;
      m = map ? &palette[piece.material].spray : &s.material.spray;
      ratio = piece.speed / m->speed_scale;
    }
    const bool flies = ratio >= 1.0 || det::pow(ratio, m->exponent) > c.chance;
    if (!flies || state.particles.size() >= static_cast<std::size_t>(s.spray.max_particles)) {
      ++(flies ? state.counts.limited : state.counts.clumps);
      drop(ground, {c.x, c.y, c.volume});
      continue;
    }
    Particle p = c.launched(piece);
    ++state.counts.created;
    ++report.particles_created;
    const FlightEnd end = fly(p, c.flight, ground, flight_rules(rules, piece.material));
    if (end.fate == FlightEnd::Fate::flying) {
      state.particles.push_back(p);
      if (map) state.particle_materials.push_back(piece.material);
    } else {
      land(ground, p, end, report);
    }
  }
  shed_.clear();
}

std::size_t Spray::bytes() const {
  std::size_t clocks = capacity_bytes(clocks_, flight_by_index_);
  for (const SampleClock& c : clocks_) clocks += c.bytes();
  std::size_t rules = capacity_bytes(rules_over_);
  for (const auto& [steps, made] : rules_over_) rules += capacity_bytes(made.by_index);
  return state.bytes() + cling_.bytes() + clock_.bytes() + clocks + rules +
         capacity_bytes(shed_.pieces, shed_.candidates, drops_, order_, next_bodies_);
}

}  // namespace shore::terrain
