#include "contact_solver.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "shore/core/det_math.h"
#include "shore/core/floor_div.h"
#include "shore/terrain/shear.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace contact_detail {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Damping of the unloading spring, as a share of its block's critical damping. Undamped, a
// box settles into a rocking mode (columns lose and regain contact, resetting their shear)
// and creeps on slopes it should hold; soil's unloading-reloading loops dissipate (Wong).
// Measured on the 0.3 m box on sand slopes (docs/terrain.md, "Unloading"): 0 creeps at 25
// degrees and misses Coulomb by 14 % at 40; 0.2 to 0.3 hold and slide within 5 %; 1 slows
// the slides by 23-33 %.
constexpr double kDampingRatio = 0.3;
// The sweeps go on past TerrainContactSettings::iterations while the last one moved some
// row's speed by more than this (a millimetre a second: 4 micrometres a substep at 1/240 s,
// a twenty-fifth of the contact tolerance), up to kMostSweeps times as many.
constexpr double kSettledSpeed = 1e-3;
constexpr int kMostSweeps = 4;
constexpr std::int64_t kKeyOffset = std::int64_t{1} << 27;

/// Bottom elements are kind 0; walls 1 to 4 by the side they push from.
int kind_of(const terrain::ContactElement& e) {
  if (!e.wall) return 0;
  if (e.normal.x > 0.5) return 1;
  if (e.normal.x < -0.5) return 2;
  return e.normal.y > 0.5 ? 3 : 4;
}

double length(Vec3 a) { return std::sqrt(dot(a, a)); }

/// Share of the shear strength acting at shear displacement j: Janosi-Hanamoto's
/// mobilisation, in soil remoulded by the shear j_yield it took while it yielded (the
/// column's remould displacement, ContactMemory).
double mobilisation(const terrain::Material& m, double j, double j_yield) {
  return terrain::shear::mobilisation(m, j) * terrain::shear::strength_remoulding(m, j_yield);
}
Vec3 normalized(Vec3 a) {
  const double n = length(a);
  return n > 0.0 ? a * (1.0 / n) : Vec3{0, 0, 1};
}

/// The shear law of one palette entry, as a block's friction reads it.
struct ShearLaw {
  const terrain::Material* material = nullptr;
  double tan_phi = 0.0;
};

/// Sums of one block's elements while it is being gathered.
struct Tally {
  bool used = false;
  double weight = 0.0, area = 0.0, infinite = 0.0;  // capacity, area, count of bedrock elements
  Vec3 force, area_normal, infinite_normal;         // sum of w n, A n, n (bedrock)
  Vec3 weighted_point, area_point, infinite_point;  // sum of w p, A p, p (bedrock)
  double cohesion = 0.0, weight_mobilised = 0.0, area_mobilised = 0.0;
  double stiffness = 0.0, preload = 0.0;  // sums of k_u A and preload A over elastic elements
  double rate = 0.0;                      // sum of dp/dz A / n_z: capacity per metre of approach
  bool holds_rigidly = false;             // some element holds rigidly
  // Its materials: the first element's, and whether any other differs. A block of several
  // materials weighs each element's tan(phi) into the mean (the sums of w tan(phi) m and
  // A tan(phi) m); one of a single material multiplies its mean by tan(phi) once, as a
  // terrain of that material alone does, bit for bit.
  std::uint8_t material = 0;
  bool mixed = false;
  double weight_friction = 0.0, area_friction = 0.0;

  /// Adds an element of the soil with cohesion c at mobilisation m; kMap: of palette entry
  /// `index` with tan(phi) tan_phi (a one-material terrain tracks no materials: no cost).
  template <bool kMap>
  void add(const terrain::ContactElement& e, double mobilisation, double c, std::uint8_t index, double tan_phi) {
    if constexpr (kMap) {
      if (!used) material = index;
      mixed = mixed || index != material;
    }
    used = true;
    const Vec3 p = e.point, n = e.normal;
    area += e.area;
    area_normal = area_normal + n * e.area;
    area_point = area_point + p * e.area;
    area_mobilised += e.area * mobilisation;
    if constexpr (kMap) area_friction += e.area * (tan_phi * mobilisation);
    if (!e.wall) cohesion += c * e.area * mobilisation;
    if (e.stiffness < kInf) {
      stiffness += e.stiffness * e.area;
      preload += e.preload * e.area;
    } else {
      holds_rigidly = true;
    }
    if (!(e.pressure < kInf)) {
      infinite += 1.0;
      infinite_normal = infinite_normal + n;
      infinite_point = infinite_point + p;
      return;
    }
    const double w = e.pressure * e.area;
    // Pressing a column further by dz along the vertical takes the body dz n_z along the normal.
    if (!e.wall && e.normal.z > 0.0) rate += e.pressure_rate * e.area / e.normal.z;
    weight += w;
    force = force + n * w;
    weighted_point = weighted_point + p * w;
    weight_mobilised += w * mobilisation;
    if constexpr (kMap) weight_friction += w * (tan_phi * mobilisation);
  }

  /// The block's friction coefficient from the sums of m and tan(phi) m over its elements,
  /// weighted to `total`; tan_phi: its material's (used when it has one).
  [[nodiscard]] double friction(double sum_m, double sum_friction, double total, double tan_phi) const {
    if (!(total > 0.0)) return 0.0;
    return mixed ? sum_friction / total : tan_phi * (sum_m / total);
  }

  [[nodiscard]] Block finish(std::uint64_t key, bool wall, double tan_phi) const {
    Block b;
    b.key = key;
    b.wall = wall;
    b.cohesion = cohesion;
    if (!holds_rigidly) b.stiffness = stiffness, b.preload = preload;
    if (infinite > 0.0) {  // bedrock bears anything: its elements decide where and which way
      b.capacity = kInf;
      b.point = infinite_point * (1.0 / infinite);
      b.normal = normalized(infinite_normal);
      b.friction = friction(area_mobilised, area_friction, area, tan_phi);
    } else if (weight > 0.0) {
      b.capacity = length(force);
      b.capacity_rate = rate;
      b.point = weighted_point * (1.0 / weight);
      b.normal = normalized(force);
      b.friction = friction(weight_mobilised, weight_friction, weight, tan_phi);
    } else {  // fresh soil: it bears nothing yet; the body's area decides
      b.capacity = 0.0;
      b.capacity_rate = rate;  // but will once pressed
      b.point = area > 0.0 ? area_point * (1.0 / area) : area_point;
      b.normal = normalized(area_normal);
      b.friction = friction(area_mobilised, area_friction, area, tan_phi);
    }
    return b;
  }
};

/// A block's key from its block coordinates and kind (rows of blocks, then columns, then
/// kind: the solve's fixed order).
std::uint64_t key_of(std::int64_t bx, std::int64_t by, int kind) {
  return (static_cast<std::uint64_t>(by + kKeyOffset) << 36) | (static_cast<std::uint64_t>(bx + kKeyOffset) << 8) |
         static_cast<std::uint64_t>(kind);
}

/// Two unit directions across the normal (a fixed choice, so results are reproducible).
void friction_directions(Block& b) {
  const Vec3 n = b.normal;
  const Vec3 axis = std::fabs(n.x) < 0.57 ? Vec3{1, 0, 0} : (std::fabs(n.y) < 0.57 ? Vec3{0, 1, 0} : Vec3{0, 0, 1});
  b.t1 = normalized(cross(n, axis));
  b.t2 = cross(n, b.t1);
}

}  // namespace

Vec3 SolverBody::apply_inv_inertia(Vec3 a) const {
  const auto& m = inv_inertia;
  return {m[0][0] * a.x + m[0][1] * a.y + m[0][2] * a.z, m[1][0] * a.x + m[1][1] * a.y + m[1][2] * a.z,
          m[2][0] * a.x + m[2][1] * a.y + m[2][2] * a.z};
}

double SolverBody::mobility_scale() const { return std::max({mobility[0][0], mobility[1][1], mobility[2][2]}); }

void SolverBody::respond(Vec3 impulse, Vec3 angular, Vec3& dv, Vec3& dw) const {
  if (!articulated) {
    dv = impulse * inv_mass;
    dw = apply_inv_inertia(angular);
    return;
  }
  const double in[6] = {impulse.x, impulse.y, impulse.z, angular.x, angular.y, angular.z};
  double out[6] = {};
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) out[r] += mobility[r][c] * in[c];
  dv = {out[0], out[1], out[2]};
  dw = {out[3], out[4], out[5]};
}

void SolverBody::apply_impulse(Vec3 impulse, Vec3 at) {
  Vec3 dv, dw;
  respond(impulse, cross(at - com, impulse), dv, dw);
  v = v + dv;
  w = w + dw;
}

void gather_blocks(std::span<const terrain::ContactElement> elements, std::span<const terrain::Material> palette,
                   std::span<const std::uint8_t> material, std::span<const double> shear_displacement,
                   std::span<const double> remould_displacement, int block_columns, std::vector<Block>& blocks) {
  blocks.clear();
  if (elements.empty()) return;
  // Each palette entry's tan(phi), worked out on first use (kept per thread, no allocation
  // per call once grown).
  thread_local std::vector<ShearLaw> laws;
  laws.assign(palette.size(), ShearLaw{});
  auto law = [&](std::uint8_t index) -> const ShearLaw& {
    ShearLaw& l = laws[index];
    if (l.material == nullptr) l = {&palette[index], det::tan(palette[index].friction_angle)};
    return l;
  };
  const FloorDivider block_of(std::max(1, block_columns));
  std::int64_t bx0 = std::numeric_limits<std::int64_t>::max(), by0 = bx0;
  std::int64_t bx1 = std::numeric_limits<std::int64_t>::min(), by1 = bx1;
  for (const terrain::ContactElement& e : elements) {
    const std::int64_t bx = block_of(e.i), by = block_of(e.j);
    bx0 = std::min(bx0, bx), bx1 = std::max(bx1, bx);
    by0 = std::min(by0, by), by1 = std::max(by1, by);
  }
  const std::int64_t nbx = bx1 - bx0 + 1, nby = by1 - by0 + 1;
  constexpr int kKinds = 5;
  // The tallies of a window's blocks, dense; kept between calls (per thread) and handed back
  // cleared, so a call clears only the slots it used instead of the whole window.
  thread_local std::vector<Tally> tallies;
  if (tallies.size() < static_cast<std::size_t>(nbx * nby * kKinds))
    tallies.resize(static_cast<std::size_t>(nbx * nby * kKinds));
  auto slot = [&](std::int64_t bx, std::int64_t by, int kind) {
    return static_cast<std::size_t>(((by - by0) * nbx + (bx - bx0)) * kKinds + kind);
  };
  auto shear_of = [&](const terrain::ContactElement& e) {
    return (e.raster_index >= 0 && !shear_displacement.empty())
               ? shear_displacement[static_cast<std::size_t>(e.raster_index)]
               : 0.0;
  };
  auto remould_of = [&](const terrain::ContactElement& e) {
    return (e.raster_index >= 0 && !remould_displacement.empty())
               ? remould_displacement[static_cast<std::size_t>(e.raster_index)]
               : 0.0;
  };
  if (material.empty()) {
    const terrain::Material& m = *law(0).material;
    for (const terrain::ContactElement& e : elements)
      tallies[slot(block_of(e.i), block_of(e.j), kind_of(e))].add<false>(e, mobilisation(m, shear_of(e), remould_of(e)),
                                                                         m.cohesion, 0, 0.0);
  } else {
    for (std::size_t k = 0; k < elements.size(); ++k) {
      const terrain::ContactElement& e = elements[k];
      const ShearLaw& l = law(material[k]);
      tallies[slot(block_of(e.i), block_of(e.j), kind_of(e))].add<true>(
          e, mobilisation(*l.material, shear_of(e), remould_of(e)), l.material->cohesion, material[k], l.tan_phi);
    }
  }
  // In key order: rows of blocks, then columns, then kind.
  for (std::int64_t by = by0; by <= by1; ++by)
    for (std::int64_t bx = bx0; bx <= bx1; ++bx)
      for (int kind = 0; kind < kKinds; ++kind) {
        Tally& t = tallies[slot(bx, by, kind)];
        if (!t.used) continue;
        blocks.push_back(t.finish(key_of(bx, by, kind), kind != 0, laws[t.material].tan_phi));
        friction_directions(blocks.back());
        t = Tally{};
      }
}

std::uint64_t block_key(const terrain::ContactElement& e, int block_columns) {
  const FloorDivider block_of(std::max(1, block_columns));
  return key_of(block_of(e.i), block_of(e.j), kind_of(e));
}

double utilisation(const Block& b, double h) {
  if (!(b.capacity < kInf)) return 1.0;
  return b.capacity * h > 0.0 ? std::clamp(b.normal_impulse / (b.capacity * h), 0.0, 1.0) : 1.0;
}

double follow_body(std::span<Block> blocks, const SolverBody& body, double h) {
  double largest = 0.0;
  for (Block& b : blocks) {
    const Vec3 d = body.point_velocity(b.point) * h;
    largest = std::max(largest, length(d));
    // The point stays where the soil is: moving it with the body's material (a ball's spin
    // carries its surface around) would lengthen the lever of a stiff push and throw the
    // body out (measured on the stiffest soil).
    const double approach = -dot(d, b.normal), deepest = b.deepest;
    b.approach += approach;
    b.deepest = std::max(b.deepest, b.approach);
    if (b.capacity < kInf) b.capacity += b.capacity_rate * (b.deepest - deepest);
    if (b.stiffness < kInf) b.preload = std::clamp(b.preload + b.stiffness * approach, 0.0, b.capacity);
  }
  return largest;
}

double largest_point_speed(std::span<const Block> blocks, const SolverBody& body) {
  double largest = 0.0;
  for (const Block& b : blocks) largest = std::max(largest, length(body.point_velocity(b.point)));
  return largest;
}

void warm_start(std::span<const Block> previous, std::span<Block> blocks) {
  std::size_t p = 0;
  for (Block& b : blocks) {
    while (p < previous.size() && previous[p].key < b.key) ++p;
    if (p == previous.size()) return;
    if (previous[p].key != b.key) continue;
    const Block& o = previous[p];
    b.normal_impulse = o.normal_impulse;
    const Vec3 friction = o.t1 * o.t1_impulse + o.t2 * o.t2_impulse;  // re-expressed in this block's directions
    b.t1_impulse = dot(friction, b.t1);
    b.t2_impulse = dot(friction, b.t2);
  }
}

namespace {

/// The most block b's shear rows may push in one substep, at normal impulse `normal`.
double friction_limit(const Block& b, double normal, double h) { return b.cohesion * h + b.friction * normal; }

/// One row of a block (its normal or a friction direction u at the block's point, arm r from
/// the centre of mass), as the sweeps use it: the row's speed is u . v + (r x u) . w, and a
/// unit impulse along it changes v by u / m and w by I^-1 (r x u). Computed once per substep,
/// so a sweep costs a few products per row instead of the point's velocity and the impulse's
/// moment each time.
struct Row {
  Vec3 u, arm, turn;  // direction, r x u, I^-1 (r x u)
  Vec3 lin;           // articulated bodies: the change of v per unit impulse (turn: of w)

  void set(const SolverBody& body, Vec3 r, Vec3 dir) {
    u = dir;
    arm = cross(r, dir);
    if (body.articulated) {
      body.respond(u, arm, lin, turn);
      return;
    }
    turn = body.apply_inv_inertia(arm);
  }
  [[nodiscard]] double speed(const SolverBody& body) const { return dot(u, body.v) + dot(arm, body.w); }
  void push(SolverBody& body, double impulse) const {
    if (body.articulated)
      body.v = body.v + lin * impulse;
    else
      body.v = body.v + u * (impulse * body.inv_mass);
    body.w = body.w + turn * impulse;
  }
  /// The effective mass along the row, kg: 1 / (1/m + (r x u) . I^-1 (r x u)); articulated,
  /// 1 / ((u, r x u) . mobility (u, r x u)).
  [[nodiscard]] double mass(const SolverBody& body) const {
    if (body.articulated) {  // a direction the joints lock (rounding aside) takes no impulse
      const double k = dot(u, lin) + dot(arm, turn);
      return k > 1e-9 * body.mobility_scale() ? 1.0 / k : 0.0;
    }
    const double k = body.inv_mass + dot(arm, turn);
    return k > 0.0 ? 1.0 / k : 0.0;
  }
};

/// A block's three rows: its normal and its two friction directions.
struct BlockRows {
  Row n, t1, t2;
};

void clamp_warm_start(SolverBody& body, std::span<Block> blocks, double h) {
  for (Block& b : blocks) {
    b.normal_impulse = std::clamp(b.normal_impulse, 0.0, b.capacity * h);
    if (b.wall) b.t1_impulse = b.t2_impulse = 0.0;
    const double limit = friction_limit(b, b.normal_impulse, h);
    const double size = std::sqrt(b.t1_impulse * b.t1_impulse + b.t2_impulse * b.t2_impulse);
    if (size > limit) {
      const double scale = limit > 0.0 ? limit / size : 0.0;
      b.t1_impulse *= scale, b.t2_impulse *= scale;
    }
    body.apply_impulse(b.normal * b.normal_impulse + b.t1 * b.t1_impulse + b.t2 * b.t2_impulse, b.point);
  }
}

/// The block's normal impulse for the body's present approach: the rigid row stops the
/// approach; the spring row pushes with h (preload - stiffness h u_end), u_end the normal
/// speed once the new impulse acts (implicit, so stable at any stiffness).
double wanted_normal_impulse(const Block& b, double u, double h) {
  if (!(b.stiffness < kInf)) return b.normal_impulse - u * b.mass_n;
  const double u_free = u - (b.mass_n > 0.0 ? b.normal_impulse / b.mass_n : 0.0);
  const double kh2 = b.stiffness * h * h + kDampingRatio * 2.0 * std::sqrt(b.stiffness * b.mass_n) * h;
  return b.mass_n > 0.0 ? (h * b.preload - kh2 * u_free) / (1.0 + kh2 / b.mass_n) : h * b.preload;
}

/// Returns the change of the row's speed it made, m/s.
double normal_row(SolverBody& body, Block& b, const Row& row, double h) {
  double next = std::clamp(wanted_normal_impulse(b, row.speed(body), h), 0.0, b.capacity * h);
  if (body.articulated && b.mass_n == 0.0) next = 0.0;  // locked: it would push nothing
  const double change = next - b.normal_impulse;
  row.push(body, change);
  b.normal_impulse = next;
  return b.mass_n > 0.0 ? std::fabs(change) / b.mass_n : 0.0;
}

/// Returns the larger change of the two rows' speeds it made, m/s.
double friction_rows(SolverBody& body, Block& b, const BlockRows& rows, double h) {
  if (b.wall) return 0.0;
  double n1 = b.t1_impulse - rows.t1.speed(body) * b.mass_t1;
  double n2 = b.t2_impulse - rows.t2.speed(body) * b.mass_t2;
  if (body.articulated) {  // a locked direction spends none of the friction limit
    if (b.mass_t1 == 0.0) n1 = 0.0;
    if (b.mass_t2 == 0.0) n2 = 0.0;
  }
  const double limit = friction_limit(b, b.normal_impulse, h);
  const double size = std::sqrt(n1 * n1 + n2 * n2);
  if (size > limit) {
    const double scale = limit > 0.0 ? limit / size : 0.0;
    n1 *= scale, n2 *= scale;
  }
  const double change1 = n1 - b.t1_impulse, change2 = n2 - b.t2_impulse;
  rows.t1.push(body, change1);
  rows.t2.push(body, change2);
  b.t1_impulse = n1, b.t2_impulse = n2;
  return std::max(b.mass_t1 > 0.0 ? std::fabs(change1) / b.mass_t1 : 0.0,
                  b.mass_t2 > 0.0 ? std::fabs(change2) / b.mass_t2 : 0.0);
}

/// Rigid bottom rows of finite, non-zero capacity that can move the body.
bool shares_common_push(const Block& b) {
  return !b.wall && b.stiffness == kInf && b.capacity < kInf && b.capacity > 0.0 && b.mass_n != 0.0;
}

/// The blocks' common push: their rigid bottom rows pushed together, each in proportion to
/// its capacity, until the capacity-weighted approach over them stops (within each block's
/// capacity). Gauss-Seidel alone converges slowly on rows this alike (a ball's blocks all
/// push nearly along one direction): the first rows solved take the whole impact along
/// their own tilted normals, and the sweeps leave the body a sideways speed and a spin no
/// push of the soil gave it (a ball dropped on the stiffest soil rolled off its pit). The
/// sweeps then share the push out among the blocks.
void common_push(SolverBody& body, std::span<Block> blocks, std::span<const BlockRows> rows, double h) {
  double total = 0.0, approach = 0.0;
  Vec3 impulse, angular;
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    const Block& b = blocks[k];
    if (!shares_common_push(b)) continue;
    total += b.capacity;
    approach += b.capacity * rows[k].n.speed(body);
    impulse = impulse + rows[k].n.u * b.capacity;
    angular = angular + rows[k].n.arm * b.capacity;
  }
  if (!(total > 0.0) || !(approach < 0.0)) return;
  // The change of each row's speed per unit of the common push (capacity-weighted).
  Vec3 dv, dw;
  body.respond(impulse, angular, dv, dw);
  double response = 0.0, most = kInf;
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    const Block& b = blocks[k];
    if (!shares_common_push(b)) continue;
    response += b.capacity * (dot(rows[k].n.u, dv) + dot(rows[k].n.arm, dw));
    most = std::min(most, std::max(0.0, b.capacity * h - b.normal_impulse) / b.capacity);
  }
  if (!(response > 0.0)) return;
  const double push = std::min(-approach / response, most);  // per newton of capacity
  if (!(push > 0.0)) return;
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    Block& b = blocks[k];
    if (!shares_common_push(b)) continue;
    b.normal_impulse += push * b.capacity;
  }
  body.v = body.v + dv * push;
  body.w = body.w + dw * push;
}

/// One sweep over the rows, forward or backward: alternating the order keeps Gauss-Seidel
/// from favouring the blocks solved first (a box would settle tilted toward them). Returns
/// the largest change of a row's speed it made, m/s.
double sweep(SolverBody& body, std::span<Block> blocks, std::span<const BlockRows> rows, double h, bool backward) {
  const std::size_t n = blocks.size();
  double largest = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t at = backward ? n - 1 - k : k;
    largest = std::max(largest, normal_row(body, blocks[at], rows[at].n, h));
  }
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t at = backward ? n - 1 - k : k;
    largest = std::max(largest, friction_rows(body, blocks[at], rows[at], h));
  }
  return largest;
}

/// The sweeps: settings.iterations of them, then more while the last one still changed some
/// row's speed by more than kSettledSpeed, up to kMostSweeps times as many. Six sweeps alone
/// stopped the landing of a box on rigid-plastic soil unsettled and left it rolling at up
/// to 0.2 rad/s; the roll lifted one side of its base out of contact, and those columns
/// came back with their shear restarted (docs/terrain.md, "Validation matrix", "The
/// rocking box").
void sweeps(SolverBody& body, std::span<Block> blocks, std::span<const BlockRows> rows, double h,
            const SolverSettings& settings) {
  const int least = settings.iterations, most = settings.keep_masses ? least : least * kMostSweeps;
  for (int it = 0; it < most; ++it) {
    const double change = sweep(body, blocks, rows, h, it % 2 == 1);
    // Past the least, only after a backward sweep: stopping after a forward one would favour
    // the blocks solved first, as one-way sweeps do.
    if (it + 1 >= least && it % 2 == 1 && change <= kSettledSpeed) return;
  }
}

/// Turns an articulated body's block's friction directions, within the tangent plane, to
/// the principal axes of its mobility there (the stored friction impulse kept as a vector).
/// A joint can lock one tangent direction (a wheel on an axle cannot slide sideways): along
/// directions that mix it with a free one, each row would spend the friction limit on
/// impulses that move nothing. Along the principal axes the locked row takes none.
void align_tangents(const SolverBody& body, Block& b) {
  const Vec3 r = b.point - body.com;
  Vec3 l1, a1, l2, a2;
  body.respond(b.t1, cross(r, b.t1), l1, a1);
  body.respond(b.t2, cross(r, b.t2), l2, a2);
  const double k11 = dot(b.t1, l1) + dot(cross(r, b.t1), a1);
  const double k22 = dot(b.t2, l2) + dot(cross(r, b.t2), a2);
  const double k12 = dot(b.t2, l1) + dot(cross(r, b.t2), a1);
  const double angle = 0.5 * std::atan2(2.0 * k12, k11 - k22);
  const double c = std::cos(angle), sn = std::sin(angle);
  const Vec3 friction = b.t1 * b.t1_impulse + b.t2 * b.t2_impulse;
  const Vec3 t1 = b.t1 * c + b.t2 * sn, t2 = b.t2 * c - b.t1 * sn;
  b.t1 = t1, b.t2 = t2;
  b.t1_impulse = dot(friction, t1), b.t2_impulse = dot(friction, t2);
}

}  // namespace

SolveResult solve(SolverBody& body, const SolverBody& start, std::span<Block> blocks, double h,
                  const SolverSettings& settings) {
  SolveResult out;
  if (blocks.empty()) return out;
  thread_local std::vector<BlockRows> rows;  // kept between calls: no allocation per substep
  rows.resize(blocks.size());
  if (body.articulated && !settings.keep_masses)
    for (Block& b : blocks)
      if (!b.wall) align_tangents(body, b);
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    Block& b = blocks[k];
    const Vec3 r = b.point - body.com;
    rows[k].n.set(body, r, b.normal);
    rows[k].t1.set(body, r, b.t1);
    rows[k].t2.set(body, r, b.t2);
    if (!settings.keep_masses) {
      b.mass_n = rows[k].n.mass(body);
      b.mass_t1 = rows[k].t1.mass(body);
      b.mass_t2 = rows[k].t2.mass(body);
    }
    const Vec3 pv = start.point_velocity(b.point);
    b.start_n = dot(pv, b.normal), b.start_t1 = dot(pv, b.t1), b.start_t2 = dot(pv, b.t2);
  }
  clamp_warm_start(body, blocks, h);
  common_push(body, blocks, rows, h);
  sweeps(body, blocks, rows, h, settings);
  // Work on the soil: each impulse times the mean velocity along it over the substep, from
  // the start of the substep (before the engine's forces) to its end. It is the kinetic
  // energy the soil takes, exact for any substep whether the soil yields or holds an impact,
  // and zero for a body at rest (the gravity kick it cancels carried no real energy).
  for (const Block& b : blocks) {
    const Vec3 pv = body.point_velocity(b.point);
    const double un = dot(pv, b.normal), u1 = dot(pv, b.t1), u2 = dot(pv, b.t2);
    const bool at_capacity = b.normal_impulse >= b.capacity * h * (1.0 - 1e-9);
    const double limit = b.wall ? 0.0 : friction_limit(b, b.normal_impulse, h);
    const double friction = std::sqrt(b.t1_impulse * b.t1_impulse + b.t2_impulse * b.t2_impulse);
    const bool sliding = !b.wall && friction >= limit * (1.0 - 1e-9) && friction > 0.0;
    const double pressing = -0.5 * b.normal_impulse * (b.start_n + un);
    const double shear = -0.5 * (b.t1_impulse * (b.start_t1 + u1) + b.t2_impulse * (b.start_t2 + u2));
    out.work += pressing + shear;
    out.shear_work += shear;
    const Vec3 impulse = b.normal * b.normal_impulse + b.t1 * b.t1_impulse + b.t2 * b.t2_impulse;
    out.normal_impulse = out.normal_impulse + b.normal * b.normal_impulse;
    out.impulse = out.impulse + impulse;
    out.angular_impulse = out.angular_impulse + cross(b.point - body.com, impulse);
    if (at_capacity && un < -1e-6) out.yielded = true;
    if (un < -1e-4) out.stuck = false;
    if (sliding && std::sqrt(u1 * u1 + u2 * u2) > 1e-4) out.stuck = false;
  }
  if (out.yielded) out.stuck = false;
  return out;
}

}  // namespace contact_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
