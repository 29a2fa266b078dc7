#include "spray_cling.h"

#include <algorithm>
#include <cmath>

#include "capacity_bytes.h"
#include "spray_random.h"

namespace shore::terrain {

namespace {
constexpr std::int64_t kKeyHalf = ClingKeys::kHalf;
}  // namespace

std::uint64_t key_part(double x, double cell) {
  const double q = x / cell;
  std::int64_t clamped = 0;
  if (std::abs(q) < 4.6e18) {  // floor without the library call: truncate, then step down below zero
    const auto t = static_cast<std::int64_t>(q);
    clamped = std::clamp(static_cast<double>(t) > q ? t - 1 : t, -kKeyHalf, kKeyHalf - 1);
  } else {
    clamped = static_cast<std::int64_t>(std::clamp(std::floor(q), -double(kKeyHalf), double(kKeyHalf - 1)));
  }
  return static_cast<std::uint64_t>(clamped + kKeyHalf);
}

std::uint64_t cling_key(const Vec3& b, double cell) {
  return key_part(b[0], cell) | (key_part(b[1], cell) << 21) | (key_part(b[2], cell) << 42);
}

namespace {

/// The draw that rounds a piece's number of particles (apart from the candidates' draws).
constexpr std::uint64_t kRounding = std::uint64_t{1} << 40;

ClingCell* find(std::vector<ClingCell>& cells, std::uint64_t key) {
  const auto at =
      std::lower_bound(cells.begin(), cells.end(), key, [](const ClingCell& c, std::uint64_t k) { return c.key < k; });
  return at != cells.end() && at->key == key ? &*at : nullptr;
}

constexpr std::uint64_t kKeyMask = (std::uint64_t{1} << 21) - 1;

}  // namespace

// Rows of (z, y) cubes over the keys' box, each pointing at its run of the sorted list; too
// sparse a box (more rows than 4 per piece) is searched by bisection instead.
void PieceIndex::build(const std::vector<ClingCell>& cells) {
  rows_ = 0;
  if (cells.empty()) return;
  std::uint64_t y0 = kKeyMask, y1 = 0;
  for (const ClingCell& c : cells) {
    const std::uint64_t y = (c.key >> 21) & kKeyMask;
    y0 = std::min(y0, y), y1 = std::max(y1, y);
  }
  z0_ = cells.front().key >> 42, y0_ = y0, ny_ = y1 - y0 + 1;
  const std::uint64_t rows = ((cells.back().key >> 42) - z0_ + 1) * ny_;
  if (rows > 4 * cells.size() + 64) return;
  start_.resize(rows + 1);
  // start_[r] = the first piece of a row >= r, in one pass: the list is sorted by key, so by
  // row too ((z, y) lead the key), and each entry is written once.
  std::uint64_t r = 0;
  for (std::size_t k = 0; k < cells.size(); ++k)
    for (const std::uint64_t last = row(cells[k].key); r <= last; ++r) start_[r] = static_cast<std::uint32_t>(k);
  for (; r <= rows; ++r) start_[r] = static_cast<std::uint32_t>(cells.size());
  rows_ = rows;
}

ClingCell* PieceIndex::find(std::vector<ClingCell>& cells, std::uint64_t key) const {
  if (rows_ == 0) return cells.empty() ? nullptr : shore::terrain::find(cells, key);
  const std::uint64_t z = key >> 42, y = (key >> 21) & kKeyMask;
  if (z < z0_ || y < y0_ || y - y0_ >= ny_) return nullptr;
  const std::uint64_t r = (z - z0_) * ny_ + (y - y0_);
  if (r >= rows_) return nullptr;
  for (std::uint32_t k = start_[r], end = start_[r + 1]; k < end; ++k)  // a row's few pieces, by x
    if (cells[k].key >= key) return cells[k].key == key ? &cells[k] : nullptr;
  return nullptr;
}

std::size_t PieceIndex::bytes() const { return capacity_bytes(start_); }

namespace {

/// The largest distance from the body's centre to a point of its envelope, squared.
double reach_squared(const Imprint& im, const SprayGround& g) {
  const EnvelopeRaster& env = *im.envelope;
  double most = 0.0;
  for (int y = 0; y < env.ny; ++y) {
    const double dy = g.y_of(env.j0 + y) - im.centre.y;
    for (int x = 0; x < env.nx; ++x) {
      const std::size_t k =
          static_cast<std::size_t>(y) * static_cast<std::size_t>(env.nx) + static_cast<std::size_t>(x);
      if (!env.covers(k)) continue;
      const double dx = g.x_of(env.i0 + x) - im.centre.x, dz = env.lower[k] - im.offset - im.centre.z;
      most = std::max(most, dx * dx + dy * dy + dz * dz);
    }
  }
  return most;
}

}  // namespace

// Every column the body touches: a piece moving fast enough over it is loaded (it will
// carry area x adhesion away when it leaves); a piece touching it slowly lays its soil back.
void Cling::touch(ClingingBody& body, const Imprint& im, const BodyMotion& m, const SprayGround& ground,
                  const ClingRules& rules, std::vector<Drop>& drops) {
  const EnvelopeRaster& env = *im.envelope;
  fresh_.clear();
  std::fill(std::begin(fresh_bits_), std::end(fresh_bits_), std::uint64_t{0});
  index_.build(body.cells);
  const ClingKeys keys(ground.cell());
  heights_.resize(env.lower.size());
  ground.heights({env.i0, env.j0, env.nx, env.ny}, heights_);
  for (int y = 0; y < env.ny; ++y)
    for (int x = 0; x < env.nx; ++x) {
      const std::size_t k =
          static_cast<std::size_t>(y) * static_cast<std::size_t>(env.nx) + static_cast<std::size_t>(x);
      if (!env.covers(k)) continue;
      const double e = env.lower[k] - im.offset;
      if (!(e <= heights_[k] + rules.tolerance)) continue;
      const std::int64_t i = env.i0 + x, j = env.j0 + y;
      const std::uint8_t index = rules.map() ? ground.material(i, j) : 0;
      const MaterialRules& mr = rules.of(index);
      const Vec3 p{ground.x_of(i), ground.y_of(j), e};
      const Vec3 r = m.to_body(p);
      const std::uint64_t key = keys.of(r);
      if (mr.min_speed.slower(m.velocity_at(p))) {
        if (ClingCell* c = piece(body, key); c != nullptr) set_down(*c, p, drops);
        continue;
      }
      ClingCell* found = piece(body, key);
      const double capacity = mr.capacity;
      if (found == nullptr) {
        if (capacity <= 0.0) continue;
        found = &add_fresh(key);
        found->material = index;
      } else if (found->material != index && capacity > 0.0) {  // a column of no adhesion leaves its soil
        set_down(*found, p, drops);                             // one material per piece: it lays its old soil here
        found->material = index;
      }
      ClingCell& c = *found;
      c.touched = rules.step;
      c.local.x = r[0], c.local.y = r[1], c.local.z = r[2];
      c.i = i, c.j = j;
      c.owed = 0.0;
      c.pending = std::max(0.0, capacity - c.volume);
    }
  merge_fresh(body);
}

ClingCell* Cling::piece(ClingingBody& body, std::uint64_t key) {
  if (ClingCell* c = index_.find(body.cells, key); c != nullptr) return c;
  if (!(fresh_bits_[fresh_word(key)] & fresh_bit(key))) return nullptr;
  for (ClingCell& c : fresh_)  // a few per step (a contact patch's worth on the first)
    if (c.key == key) return &c;
  return nullptr;
}

ClingCell& Cling::add_fresh(std::uint64_t key) {
  fresh_bits_[fresh_word(key)] |= fresh_bit(key);
  ClingCell& c = fresh_.emplace_back();
  c.key = key;
  return c;
}

void Cling::merge_fresh(ClingingBody& body) {
  if (fresh_.empty()) return;
  const auto by_key = [](const ClingCell& a, const ClingCell& b) { return a.key < b.key; };
  std::sort(fresh_.begin(), fresh_.end(), by_key);
  const auto old_size = static_cast<std::ptrdiff_t>(body.cells.size());
  body.cells.insert(body.cells.end(), fresh_.begin(), fresh_.end());
  std::inplace_merge(body.cells.begin(), body.cells.begin() + old_size, body.cells.end(), by_key);
  // A first contact fills a whole patch; later steps a few pieces: keep no patch-sized
  // scratch between steps.
  if (fresh_.capacity() > 64) std::vector<ClingCell>().swap(fresh_);
  fresh_.clear();
}

void Cling::set_down(ClingCell& c, const Vec3& p, std::vector<Drop>& drops) {
  if (c.volume > 0.0) {
    drops.push_back({p[0], p[1], c.volume});
    ++set_down_count;
  }
  c.volume = c.owed = c.pending = 0.0;
}

void Cling::shed(std::uint64_t body_key, ClingCell& c, const BodyMotion& m, const ClingRules& rules, Shed& out) {
  if (!(c.volume > 0.0)) return;
  const MaterialRules& mr = rules.of(c.material);
  const CounterRandom rnd = CounterRandom::of_piece(body_key, c.key);
  // Sumner's n = dv phi particles, rounded at random (up with the probability of the
  // fraction), so the number shed keeps its expected value however small dv is; what the
  // rounding sheds early or late is evened out by `owed` in the next steps.
  const double vp = mr.particle_volume;
  c.owed += std::max(0.0, c.volume - c.owed) * mr.shed_share;
  const double whole = particles_due(std::max(0.0, c.owed), vp, mr.inverse_particle_volume, rnd.uniform(kRounding, 0));
  // Most steps a piece sheds nothing (neither a whole particle nor its last half): it then
  // needs no more than this.
  if (!(0.0 < whole) && !(c.volume < 0.5 * vp)) return;
  emit(rnd, whole, c, m, rules, mr, out);
}

void Cling::emit(const CounterRandom& rnd, double whole, ClingCell& c, const BodyMotion& m, const ClingRules& rules,
                 const MaterialRules& mr, Shed& out) {
  // Where the piece is and how fast it moves, once for all its candidates.
  const Vec3 p = m.to_world(c.local), u = m.velocity_at(p);
  const double speed = length(u);
  const double half = 0.5 * rules.cell;
  const std::size_t piece = out.pieces.size();
  out.pieces.push_back({rnd, p, u, speed, half, mr.jitter * speed, c.material});
  std::uint64_t n = 0;
  // Inline (an attribute GCC and Clang read): a call per candidate cost as much as its body.
  auto one = [&](double volume) __attribute__((always_inline)) {
    const double flight = rules.dt * (1.0 - rnd.uniform(n, 0));  // created at a random time in the step
    const double x = p[0] - u[0] * flight + half * rnd.symmetric(n, 1);
    const double y = p[1] - u[1] * flight + half * rnd.symmetric(n, 2);
    // z and the velocity: drawn by launched() if it flies
    out.candidates.push_back({x, y, volume, flight, rnd.uniform(n, 7), n, piece});
    c.volume -= volume;
    ++n;
  };
  const double vp = mr.particle_volume;
  for (double k = 0.0; k < whole && c.volume > 0.0; k += 1.0) {
    one(std::min(vp, c.volume));
    c.owed -= vp;
  }
  if (c.volume > 0.0 && c.volume < 0.5 * vp) one(c.volume);  // less than half a particle is left: it goes too
  if (!(c.volume > 0.0)) c.volume = c.owed = 0.0;
}

bool Cling::can_start(const Imprint& im, const SprayGround& ground, const ClingRules& rules) {
  if (rules.most_capacity <= 0.0) return false;
  const double v =
      std::sqrt(im.velocity.x * im.velocity.x + im.velocity.y * im.velocity.y + im.velocity.z * im.velocity.z);
  const double spin =
      std::sqrt(im.angular_velocity.x * im.angular_velocity.x + im.angular_velocity.y * im.angular_velocity.y +
                im.angular_velocity.z * im.angular_velocity.z);
  return v + (spin > 0.0 ? spin * std::sqrt(reach_squared(im, ground)) : 0.0) >= rules.least_min_speed;
}

double Cling::step(ClingingBody& body, const Imprint& im, SprayGround& ground, const ClingRules& rules, Shed& out,
                   std::vector<Drop>& drops) {
  if (body.cells.empty() && !can_start(im, ground, rules)) return 0.0;
  const BodyMotion m(im);
  touch(body, im, m, ground, rules, drops);
  // The pieces not touched this step: on the soil (within half a column of its top) they
  // hold their soil, or set it down if they move slowly; off it, they have left the ground:
  // they carry their load away from the column they last touched, and shed.
  const double band = 0.5 * rules.cell + rules.tolerance;
  const double area = rules.cell * rules.cell;
  const std::uint64_t body_key = CounterRandom::body_key(rules.seed, static_cast<std::uint64_t>(rules.step), body.key);
  double picked = 0.0;
  for (ClingCell& c : body.cells) {
    if (c.touched == rules.step) continue;
    const Vec3 p = m.to_world(c.local);
    const double top = ground.height(ground.column_i(p[0]), ground.column_j(p[1]));
    if (p[2] <= top + band) {
      if (rules.of(c.material).min_speed.slower(m.velocity_at(p))) set_down(c, p, drops);
      continue;
    }
    if (c.pending > 0.0) {
      const double taken = ground.take(c.i, c.j, c.pending / area);
      c.volume += taken;
      picked += taken;
      c.pending = 0.0;
    }
    shed(body_key, c, m, rules, out);
  }
  std::erase_if(body.cells, [](const ClingCell& c) { return !(c.volume > 0.0) && !(c.pending > 0.0); });
  body.centre = m.c;
  body.orientation = m.q;
  return picked;
}

void Cling::set_all_down(const ClingingBody& body, std::vector<Drop>& drops) {
  const BodyMotion m(body.centre, body.orientation);
  for (const ClingCell& c : body.cells) {
    if (!(c.volume > 0.0)) continue;
    const Vec3 p = m.to_world(c.local);
    drops.push_back({p[0], p[1], c.volume});
  }
}

std::size_t Cling::bytes() const { return capacity_bytes(heights_, fresh_) + index_.bytes(); }

}  // namespace shore::terrain
