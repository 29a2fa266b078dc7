#pragma once
// Private: spray's part of the saved terrain state (version 4 on; layout at the top of
// terrain_io.cpp): the material's and the terrain's spray settings, and the spray state.

#include "shore/terrain/terrain.h"
#include "spray_state.h"
#include "state_file.h"

namespace shore::terrain {

/// A material's spray settings (part of every saved material).
void write_spray_material(Writer& w, const SprayMaterial& m);
/// The material's spray settings, then the terrain's.
void write_spray_settings(Writer& w, const TerrainSettings& s);
void read_spray_settings(Reader& r, TerrainSettings& s);
void write_spray_state(Writer& w, const SprayState& state);
/// Fails (FileError) on counts that do not fit the file or values that are not finite.
void read_spray_state(Reader& r, SprayState& state);

}  // namespace shore::terrain
