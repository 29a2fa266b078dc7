#include "terrain_contact.h"

#include <utility>

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace contact_detail {

void TerrainContact::build(const terrain::Terrain& terrain, const EnvelopeRaster& envelope,
                           const terrain::SurfaceProbe* probe, int block_columns) {
  terrain.contact(envelope, memory.shear_length(), probe, patch);
  state = ContactState::following;
  drift = 0.0;
  memory.limit_unloading(patch.elements, envelope);
  std::swap(previous, blocks);
  gather_blocks(patch.elements, terrain.settings().material, memory.shear_length(), block_columns, blocks);
  warm_start(previous, blocks);
}

void TerrainContact::follow(const SolverBody& start, double h) { drift += follow_body(blocks, start, h); }

}  // namespace contact_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
