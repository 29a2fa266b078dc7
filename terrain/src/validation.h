#pragma once
// Private: the checks of what a caller passes in. Each throws shore::InvalidSetting naming
// the field, the value and the allowed range, before any state changes.

#include <span>
#include <string>

#include "shore/core/envelope.h"
#include "shore/terrain/terrain.h"

namespace shore::terrain {

/// Not null, nx * ny values, none NaN or -inf.
void check_envelope(const EnvelopeRaster* env, const std::string& name);
/// Every imprint of a step: its envelope, offset, motion and pose; the step's dt (>= 0,
/// finite); with dt > 0, no two spraying imprints with the same body key.
void check_imprints(std::span<const Imprint> imprints, double dt);
/// A rectangle for Terrain::relax: not negative, not larger than one region may be.
void check_relax_region(const GridRect& region);

}  // namespace shore::terrain
