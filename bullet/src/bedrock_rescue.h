#pragma once
// Internal: nothing falls through the terrain. A body driven below bedrock within one
// substep (a very fast impact) is lifted back out; a body that fell through anyway is put
// back on the surface.

#include <vector>

#include "coupled_body.h"
#include "shore/bullet/config.h"
#include "shore/bullet/terrain_tiles.h"
#include "shore/core/envelope.h"
#include "shore/terrain/terrain.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

/// Lifts the body (and its envelope, just made at its pose) by how far the envelope's
/// lowest point lies below bedrock, and stops its fall. `scratch` holds base heights.
/// True if it was lifted.
bool keep_above_bedrock(CoupledBody& body, EnvelopeRaster& envelope, const terrain::Terrain& terrain,
                        std::vector<double>& scratch);

/// A body whose lowest point lies below bedrock under its centre of mass (inside `region`)
/// is put back with its lowest point on the surface, its fall stopped, and woken. True if
/// it was moved.
bool rescue_fallen(CoupledBody& body, const terrain::Terrain& terrain, const Region& region);

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
