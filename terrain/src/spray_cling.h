#pragma once
// Private: Sumner's particle rule on one body's surface. The surface is cut into cubes of
// one column's side in the body's frame ("pieces"), found again step after step however
// the body turns. Each step:
//   touch     every column the body touches (its envelope within contact_tolerance of the
//             top) where the piece there moves at min_speed or more loads that piece: it
//             will hold area x adhesion (area = cell^2);
//   set down  a piece touching the soil slower than min_speed lays its soil back at once;
//   materials a piece holds one material, the one of the column it loads from; loading from
//             a column of another material (one that clings, adhesion > 0), it first
//             lays what it holds there (the tyre's sand pressed off into the mud it now
//             picks up); a column that holds nothing (a road) leaves its soil as it is.
//             What a piece loads, how fast it must move, and how it sheds (particle size,
//             half-life, jitter) are its material's;
//   leave     a piece that has left the ground (more than half a column above the soil top
//             below it) takes its load off the top of the column it last touched: soil is
//             carried away where the surface lifts from it, never from under a body that
//             still presses on it (which would open a gap under it and take its bearing);
//   shed      a piece off the ground sheds its soil with the half-life: what the decay owes
//             goes in whole particles of the material's volume (their number rounded up or
//             down at random, keeping its expected value), the rest at once when less than
//             half a particle is left. Each candidate starts at a random time in
//             the step, at a random point of a column-sized cube around its piece, with the
//             piece's velocity v + w x r plus jitter.
// Whether a candidate flies (Sumner's (|v + w x r| / s)^gamma test) is the caller's, who
// also lays the soil that is set down.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "shore/terrain/terrain.h"
#include "spray_ground.h"
#include "spray_motion.h"
#include "spray_random.h"
#include "spray_state.h"

namespace shore::terrain {

/// What one material and the step's time make of the rule.
struct MaterialRules {
  explicit MaterialRules(double least_speed = 0.0) : min_speed(least_speed) {}
  double capacity = 0.0;                 ///< m^3 a piece holds, adhesion x cell^2
  SpeedTest min_speed;                   ///< m/s, the material's min_speed
  double particle_volume = 0.0;          ///< m^3
  double inverse_particle_volume = 0.0;  ///< 1 / particle_volume
  double shed_share = 0.0;               ///< 1 - 2^(-dt / half_life): share of what clings that drops off this step
  double jitter = 0.0;
};

/// What the materials, the terrain and the step's time make of the rule.
struct ClingRules {
  double dt = 0.0;         ///< s
  double cell = 0.0;       ///< m, the column spacing (a piece is a cube of this side)
  double tolerance = 0.0;  ///< m, a column is touched when the body lies this close to its top
  MaterialRules one;       ///< entry 0's (the only one on a terrain with one material)
  /// Per palette index (a terrain with a map); empty (one material): `one` everywhere.
  std::vector<MaterialRules> by_index;
  [[nodiscard]] bool map() const { return !by_index.empty(); }
  /// The rules of palette index `index`.
  [[nodiscard]] const MaterialRules& of(std::uint8_t index) const { return by_index.empty() ? one : by_index[index]; }
  /// Whether a body can start to cling: the most any material holds (> 0) and the least
  /// speed any loads at.
  double most_capacity = 0.0;
  double least_min_speed = 0.0;
  std::uint64_t seed = 0;
  std::int64_t step = 0;
};

/// What a piece that sheds this step gives each of its candidates, kept once for them all.
struct ShedPiece {
  CounterRandom random;       ///< its numbers
  Vec3 position;              ///< m, where it is at the step's end
  Vec3 velocity;              ///< m/s, u = v + w x r
  double speed = 0.0;         ///< m/s, |u| (Sumner's |p0'|)
  double half = 0.0;          ///< m, half a column: the spread of its candidates' starts
  double jitter = 0.0;        ///< m/s, the spread of their velocities: jitter * speed
  std::uint8_t material = 0;  ///< its palette index
};

/// A particle a piece sheds, before Sumner's speed test. Most candidates do not fly (they
/// fail the test, or the spray holds its most particles) and are set down where they are:
/// their height and velocity, four of their eight random draws, are drawn only by
/// launched(), the same numbers as when drawn at once. What its piece gives it is in the
/// piece's ShedPiece, so that each candidate written and read is small.
struct Candidate {
  double x = 0.0, y = 0.0;  ///< m, where it starts (at its creation time)
  double volume = 0.0;      ///< m^3
  double flight = 0.0;      ///< s of the step left after its creation
  double chance = 0.0;      ///< the uniform number in [0, 1) its speed test must beat
  std::uint64_t index = 0;  ///< its number among its piece's candidates
  std::size_t piece = 0;    ///< its piece, in Shed::pieces

  /// The particle as it flies (`from`: its piece): its height and velocity drawn.
  [[nodiscard]] Particle launched(const ShedPiece& from) const {
    Particle s;
    s.position.x = x, s.position.y = y;
    s.volume = volume;
    const double z_before = from.position[2] - from.velocity[2] * flight;  // its height before the spread
    s.position.z = z_before + from.half * from.random.symmetric(index, 3);
    s.velocity.x = from.velocity[0] + from.jitter * from.random.symmetric(index, 4);
    s.velocity.y = from.velocity[1] + from.jitter * from.random.symmetric(index, 5);
    s.velocity.z = from.velocity[2] + from.jitter * from.random.symmetric(index, 6);
    return s;
  }
};

/// The candidates of a body's step, in order, and the pieces they come from.
struct Shed {
  std::vector<ShedPiece> pieces;
  std::vector<Candidate> candidates;
  void clear() { pieces.clear(), candidates.clear(); }
};

/// Soil that goes straight down onto the column below a point (set down, or a candidate
/// that does not fly).
struct Drop {
  double x = 0.0, y = 0.0, volume = 0.0;
};

/// Where a body's pieces are in its sorted list, without a search: the keys' (z, y) rows
/// over the box they span, each with the start of its run in the list (a few pieces, in
/// order of x). Built once a step for the list as it stands; a list too sparse for rows
/// (more than 4 per piece) is bisected instead.
class PieceIndex {
 public:
  void build(const std::vector<ClingCell>& cells);
  /// The piece of this key in `cells` (the list it was built for), or null.
  [[nodiscard]] ClingCell* find(std::vector<ClingCell>& cells, std::uint64_t key) const;
  [[nodiscard]] std::size_t bytes() const;

 private:
  [[nodiscard]] std::uint64_t row(std::uint64_t key) const {
    return ((key >> 42) - z0_) * ny_ + (((key >> 21) & ((std::uint64_t{1} << 21) - 1)) - y0_);
  }
  std::uint64_t z0_ = 0, y0_ = 0, ny_ = 0, rows_ = 0;  ///< rows_ 0: bisect
  std::vector<std::uint32_t> start_;                   ///< rows_ + 1 entries
};

class Cling {
 public:
  /// One body's step: touch, set down, leave and shed (candidates and drops appended in a
  /// fixed order). Returns the m^3 picked up (carried away from the ground). A body with no clinging soil that cannot
  /// move at min_speed anywhere under its envelope costs one pass over the envelope.
  double step(ClingingBody& body, const Imprint& im, SprayGround& ground, const ClingRules& rules, Shed& out,
              std::vector<Drop>& drops);
  /// Whether some point of the body's envelope moves at min_speed or more (|v| + |w| times
  /// its reach from the centre): if not, a body holding no soil has nothing to do.
  static bool can_start(const Imprint& im, const SprayGround& ground, const ClingRules& rules);
  /// A body gone from the step (at rest, removed, spray off): all its soil is set down
  /// below its pieces, where it was last seen.
  static void set_all_down(const ClingingBody& body, std::vector<Drop>& drops);
  [[nodiscard]] std::size_t bytes() const;
  std::int64_t set_down_count = 0;  ///< pieces set down, in all

 private:
  void touch(ClingingBody& body, const Imprint& im, const BodyMotion& m, const SprayGround& ground,
             const ClingRules& rules, std::vector<Drop>& drops);
  /// The piece's soil straight down below p, at once; the piece then holds nothing.
  void set_down(ClingCell& c, const Vec3& p, std::vector<Drop>& drops);
  /// `body_key`: CounterRandom::body_key of the body's (seed, step, body).
  void shed(std::uint64_t body_key, ClingCell& cell, const BodyMotion& m, const ClingRules& rules, Shed& out);
  /// The candidates of a piece that sheds this step: `whole` particles, and the rest if less
  /// than half a particle is left.
  static void emit(const CounterRandom& rnd, double whole, ClingCell& c, const BodyMotion& m, const ClingRules& rules,
                   const MaterialRules& mr, Shed& out);
  /// The piece of this key, among the body's pieces or those first touched this step.
  ClingCell* piece(ClingingBody& body, std::uint64_t key);
  /// Puts the pieces first touched this step into the body's list, which stays sorted by key.
  void merge_fresh(ClingingBody& body);
  /// A piece first touched this step, noted in fresh_ and in fresh_bits_.
  ClingCell& add_fresh(std::uint64_t key);
  /// fresh_bits_'s place for a key, 0 to 255: the low bits of its three axes' parts, mixed.
  static std::size_t fresh_slot(std::uint64_t key) { return (key ^ (key >> 21) ^ (key >> 42)) & 255; }
  static std::size_t fresh_word(std::uint64_t key) { return fresh_slot(key) >> 6; }
  static std::uint64_t fresh_bit(std::uint64_t key) { return std::uint64_t{1} << (fresh_slot(key) & 63); }
  std::vector<double> heights_;  ///< soil tops under the envelope
  PieceIndex index_;             ///< of the body's pieces, during touch
  /// Pieces first touched in this step's touch, merged into the body's sorted list at its
  /// end: one pass over the list instead of an insertion (and a shift of the list) each.
  /// The list comes out the same as with the insertions: sorted by key, keys unique.
  std::vector<ClingCell> fresh_;
  /// A bit set for each key in fresh_ (fresh_bit, fresh_word): a key whose bit is clear is
  /// not there, and most keys asked are not (a column's piece is in the body's list, or
  /// nowhere), so they skip the scan of fresh_.
  std::uint64_t fresh_bits_[4] = {0, 0, 0, 0};
};

/// The cube of the body frame a point lies in, packed in 64 bits (21 per axis).
std::uint64_t cling_key(const Vec3& body_point, double cell);

/// floor(owed / vp + u) (owed >= 0, u in [0, 1)), with owed * inverse (inverse = 1 / vp)
/// where that floors the same: the product lies within 3 ulps of the quotient and the sum
/// rounds monotonically, so a sum farther than 2^-44 (1 + sum) from every integer floors as
/// the quotient's would. Closer, the division decides.
inline double particles_due(double owed, double vp, double inverse, double u) {
  const double near = owed * inverse + u;
  if (near < 0x1.0p40) {
    const double whole = static_cast<double>(static_cast<std::int64_t>(near));  // floor: near >= 0
    const double rest = near - whole;                                           // exact
    if (std::min(rest, 1.0 - rest) > 0x1.0p-44 * (1.0 + near)) return whole;
  }
  return std::floor(owed / vp + u);
}

/// cling_key for one cell size, the same keys with a multiplication for most divisions.
struct ClingKeys {
  explicit ClingKeys(double cell_size) : cell(cell_size), inverse_cell(1.0 / cell_size) {}
  [[nodiscard]] std::uint64_t of(const Vec3& b) const { return part(b[0]) | (part(b[1]) << 21) | (part(b[2]) << 42); }
  [[nodiscard]] std::uint64_t part(double x) const;
  double cell, inverse_cell;
  static constexpr std::int64_t kHalf = std::int64_t{1} << 20;
};

/// floor(x / cell), clamped to the key's 21 bits, as cling_key makes it.
std::uint64_t key_part(double x, double cell);

// The same part by a multiplication where it gives the same integer: x * (1 / cell) lies
// within 3 ulps of x / cell, and floor (then the clamp) is monotonic with steps only at
// integers, so a product farther than 2^-44 |q| from every integer floors as the quotient
// does. Closer, or far out (|q| >= 2^40, clamped anyway), the division decides.
inline std::uint64_t ClingKeys::part(double x) const {
  const double q = x * inverse_cell;
  if (std::abs(q) < 0x1.0p40) {
    auto t = static_cast<std::int64_t>(q);
    if (static_cast<double>(t) > q) --t;             // floor
    const double rest = q - static_cast<double>(t);  // in [0, 1], exact but for q in (-1, 0)
    if (std::min(rest, 1.0 - rest) > 0x1.0p-44 * std::abs(q))
      return static_cast<std::uint64_t>(std::clamp(t, -kHalf, kHalf - 1) + kHalf);
  }
  return key_part(x, cell);
}

}  // namespace shore::terrain
