#pragma once
// Internal: one body's contact with the terrain, kept from substep to substep: the soil's
// contact elements under the body (terrain::Terrain::contact), their blocks and the
// impulses they pushed with (the next solve's warm start), the per-column memory
// (contact_memory.h), and where the body is in its path through the substeps (ContactState).

#include <cstdint>
#include <optional>
#include <vector>

#include <LinearMath/btVector3.h>

#include "contact_memory.h"
#include "contact_solver.h"
#include "shore/bullet/config.h"
#include "shore/bullet/terrain_coupling.h"
#include "shore/core/byte_io.h"
#include "shore/core/envelope.h"
#include "shore/terrain/contact.h"
#include "shore/terrain/terrain.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace contact_detail {

/// Where a body's contact stands between two substeps, which decides what the next
/// substep's solve does (terrain_coupling.cpp, solve_contact).
enum class ContactState : std::uint8_t {
  none,       ///< no envelope over the terrain: nothing to solve
  to_build,   ///< the envelope is newer than the contact: the next solve builds it afresh
  following,  ///< built or followed last substep, no envelope since: the contact follows the body
  resting,    ///< at rest: last substep's impulse holds it, else its kept contact is solved again
};

/// The body's velocities at the end of a substep (the start of the next).
struct EndMotion {
  btVector3 linear{0, 0, 0}, angular{0, 0, 0};
};

class TerrainContact {
 public:
  ContactState state = ContactState::none;
  terrain::ContactPatch patch;
  std::vector<Block> blocks;    ///< this substep's, sorted by key
  std::vector<Block> previous;  ///< the last built contact's (warm start)
  ContactMemory memory;
  TerrainForce last;  ///< the terrain's push in the last substep
  /// m: how far the blocks' points have moved with the body since they were built (a bound:
  /// the sum of each substep's largest move), for TerrainContactSettings::follow_drift.
  double drift = 0.0;
  std::optional<EndMotion> end;  ///< unknown before the body's first substep

  /// Builds the patch and blocks from the terrain under the envelope, warm-started from
  /// the blocks before; the contact then follows the body.
  void build(const terrain::Terrain& terrain, const EnvelopeRaster& envelope, const terrain::SurfaceProbe* probe,
             int block_columns);
  /// Moves the blocks with the body over one substep from `start` (follow_body).
  void follow(const SolverBody& start, double h);

  /// Field by field (terrain_contact_state.cpp).
  void save(ByteWriter& w) const;
  /// Reads save's form for an envelope of `columns` columns; FileError (the contact
  /// unchanged where it throws before the end) for corrupt or non-finite values or indices
  /// beyond the envelope. with_remould: the state holds the memory's remould displacements
  /// (ContactMemory::restore).
  void restore(ByteReader& r, std::size_t columns, bool with_remould);
  /// Multiplies the blocks' friction by tan_phi: blocks saved when the friction held the
  /// mobilisation alone (one material's tan(phi) applied at the solve).
  void scale_friction(double tan_phi);
};

}  // namespace contact_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
