#pragma once
// Internal: the soil's impulses on one rigid body in one substep.
//
// The soil's contact elements (terrain::Terrain::contact) are gathered into blocks of
// block_columns x block_columns columns (walls apart, by side). Each block is one contact
// row along its capacity-weighted normal, bounded by what its columns can push in one
// substep (capacity x h), plus two friction rows bounded by Janosi-Hanamoto's shear
// strength of its columns at the block's normal impulse. The rigid bottom rows first push
// together, each in proportion to its capacity, until their capacity-weighted approach
// stops; projected Gauss-Seidel over the rows in a fixed order, warm-started from the last
// substep and swept until it settles (SolverSettings::iterations), then shares that out and
// finds impulses that stop the body's approach and slip where the soil can, and yield where
// it cannot: the soil never pulls and never reverses an approach. The same rule with one
// block is the momentum rule Shore used before (p = -m v_z against S h).
//
// A block whose columns all unload elastically (Material::unload_modulus) is a spring
// instead: its push at the substep's end is preload + stiffness x h x (approach speed at
// the end), solved implicitly and bounded by [0, capacity]; it may push a body it does not
// press, with the elastic energy its columns stored.

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "shore/bullet/config.h"
#include "shore/terrain/contact.h"
#include "shore/terrain/material.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace contact_detail {

using shore::Vec3;

/// The body as the solver sees it: world frame, double precision.
struct SolverBody {
  Vec3 v, w;                      ///< linear and angular velocity
  Vec3 com;                       ///< centre of mass
  double inv_mass = 0.0;          ///< 1 / kg
  double inv_inertia[3][3] = {};  ///< world inverse inertia tensor
  /// An articulated body (a btMultiBody link): an impulse P at the centre with angular
  /// impulse L changes (v, w) by mobility (P, L), its 6 x 6 response through the whole
  /// multibody (coupled_multibody_link.h); inv_mass and inv_inertia are then only a plan.
  bool articulated = false;
  double mobility[6][6] = {};

  [[nodiscard]] Vec3 apply_inv_inertia(Vec3 a) const;
  /// The change of (v, w) an impulse at the centre and an angular impulse make: through the
  /// mobility for an articulated body, through inv_mass and inv_inertia for a free one.
  void respond(Vec3 impulse, Vec3 angular, Vec3& dv, Vec3& dw) const;
  /// 1 / kg: the largest linear mobility (articulated bodies), what "locked" is measured against.
  [[nodiscard]] double mobility_scale() const;
  [[nodiscard]] Vec3 point_velocity(Vec3 p) const { return v + cross(w, p - com); }
  void apply_impulse(Vec3 impulse, Vec3 at);
};

/// One block of contact elements.
struct Block {
  std::uint64_t key = 0;  ///< (block x, block y, kind): fixed solve order, warm start
  Vec3 point, normal;     ///< where and along which direction it pushes
  double capacity = 0.0;  ///< N, the most it pushes (+infinity on bedrock)
  double cohesion = 0.0;  ///< N, sum of c A (1 - exp(-j / K)) over its bottom elements
  double friction = 0.0;  ///< capacity-weighted mean of tan(phi) (1 - exp(-j / K)), each column's c, phi, K
  bool wall = false;
  // Solve state.
  Vec3 t1, t2;                                                      ///< friction directions
  double normal_impulse = 0.0, t1_impulse = 0.0, t2_impulse = 0.0;  ///< N s
  double mass_n = 0.0, mass_t1 = 0.0, mass_t2 = 0.0;                ///< effective masses, kg
  double start_n = 0.0, start_t1 = 0.0, start_t2 = 0.0;             ///< the rows' velocities at the substep's start
  // (Last, so states saved before these fields read as a prefix.)
  /// N/m: the elastic stiffness of its unloading columns along the normal; +infinity: it
  /// holds rigidly up to capacity (some column is being pressed, a wall, bedrock, or the
  /// soil is rigid-plastic).
  double stiffness = std::numeric_limits<double>::infinity();
  double preload = 0.0;  ///< N, the elastic push at the body's pose (finite stiffness)
  /// N/m: how fast capacity grows as the body approaches along the normal (its columns'
  /// Bekker dp/dz; 0 on bedrock and for walls), for follow_body.
  double capacity_rate = 0.0;
  double approach = 0.0;  ///< m the body has approached along the normal since the block was built (follow_body)
  double deepest = 0.0;   ///< m, the most `approach` has been
};

struct SolverSettings {
  int block_columns = 4;  ///< columns per block side
  /// PGS sweeps over the rows (TerrainContactSettings::iterations): at least these; a solve
  /// whose last sweep still moved some row's speed by more than 1 mm/s sweeps on, up to 4
  /// times as many (a body at rest re-solving its kept contact, keep_masses: exactly these).
  int iterations = 6;
  /// The blocks' effective masses are still right (the body has not moved since they were
  /// computed: a body at rest re-solving its kept contact).
  bool keep_masses = false;
};

/// What the solve did.
struct SolveResult {
  Vec3 impulse;             ///< N s, total on the body
  Vec3 normal_impulse;      ///< N s, the part along the blocks' normals
  Vec3 angular_impulse;     ///< N m s about the centre of mass
  double work = 0.0;        ///< J done on the soil (the body's kinetic energy lost to it)
  double shear_work = 0.0;  ///< J of it done by the shear rows
  bool yielded = false;     ///< some block pushed its most and the body still approaches it
  bool stuck = true;        ///< every block holds: no approach, no slip beyond its strength
};

/// Gathers contact elements into blocks, sorted by key. palette: the terrain's materials;
/// material: each element's palette index (its column's), or empty: all palette[0] (a
/// one-material terrain; no look-ups). A block of one material gets exactly the friction
/// of that material alone. shear_displacement and remould_displacement: per envelope
/// column (by the elements' raster_index; empty: none), Janosi-Hanamoto's j and the j the
/// column's strength loss follows (ContactMemory::remould_length).
void gather_blocks(std::span<const terrain::ContactElement> elements, std::span<const terrain::Material> palette,
                   std::span<const std::uint8_t> material, std::span<const double> shear_displacement,
                   std::span<const double> remould_displacement, int block_columns, std::vector<Block>& blocks);

/// The key (Block::key) of the block gather_blocks puts element `e` in.
[[nodiscard]] std::uint64_t block_key(const terrain::ContactElement& e, int block_columns);

/// The share of its capacity block `b` pushed with in its last solve of a substep h long,
/// in [0, 1]; 1 where it has no finite capacity to share (bedrock).
[[nodiscard]] double utilisation(const Block& b, double h);

/// Warm start: the impulses the same blocks ended the last substep with (both sorted by key).
void warm_start(std::span<const Block> previous, std::span<Block> blocks);

/// Keeps blocks built at an earlier pose for the body's pose one substep of motion later:
/// each block's point moves by d = (v + w x r) h with the body's velocities, and its
/// capacity and elastic push follow the approach -d . n to first order: the capacity grows
/// by capacity_rate times the approach beyond the deepest reached since the block was built
/// (plastic soil keeps its strength where the body backs off), the elastic push by stiffness
/// times the approach either way. The point where the soil pushes stays. Returns the
/// largest |d|, m.
double follow_body(std::span<Block> blocks, const SolverBody& body, double h);

/// The largest speed of a block's point with the body's velocities, m/s.
double largest_point_speed(std::span<const Block> blocks, const SolverBody& body);

/// Solves the substep's soil impulses on the body (velocities updated in place). start:
/// the body at the start of the substep, before the engine's forces of this substep (its
/// velocities then and the solved ones bracket the substep's motion, for the work).
SolveResult solve(SolverBody& body, const SolverBody& start, std::span<Block> blocks, double h,
                  const SolverSettings& settings);

}  // namespace contact_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
