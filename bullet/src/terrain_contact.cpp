#include "terrain_contact.h"

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

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
  // Each element's shear law is its column's material (the one it shows: a layered
  // column's lower material once broken through); a one-material terrain looks nothing up.
  const std::span<const terrain::Material> palette = terrain.palette();
  thread_local std::vector<std::uint8_t> material;  // kept per thread: no allocation per build
  material.clear();
  if (palette.size() > 1)
    for (const terrain::ContactElement& e : patch.elements)
      material.push_back(static_cast<std::uint8_t>(terrain.exposed_index(e.i, e.j)));
  gather_blocks(patch.elements, palette, material, memory.shear_length(), memory.remould_length(), block_columns,
                blocks);
  warm_start(previous, blocks);
}

void TerrainContact::follow(const SolverBody& start, double h) { drift += follow_body(blocks, start, h); }

}  // namespace contact_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
