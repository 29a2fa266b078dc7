#pragma once
// Private: spray's part of the saved terrain state (version 4 on; layout at the top of
// terrain_io.cpp): the material's and the terrain's spray settings, and the spray state
// (with each particle's and clinging piece's palette index, version 7 on).

#include "shore/terrain/terrain.h"
#include "spray_state.h"
#include "state_file.h"

namespace shore::terrain {

/// A material's spray settings (part of every saved material).
void write_spray_material(Writer& w, const SprayMaterial& m);
/// The material's spray settings, then the terrain's.
void write_spray_settings(Writer& w, const TerrainSettings& s);
void read_spray_settings(Reader& r, TerrainSettings& s);
/// `materials`: each particle and clinging piece carries its palette index (u8, after its
/// other fields: terrain state version 7 on, soil delta version 4 on); without it every one
/// must be entry 0's (a terrain with one material writes the bytes it wrote before maps).
void write_spray_state(Writer& w, const SprayState& state, bool materials = false);
/// Fails (FileError) on counts that do not fit the file or values that are not finite.
/// `materials`: the indices are there to read (else all are 0); check_spray_materials checks
/// them against the palette once it is known.
void read_spray_state(Reader& r, SprayState& state, bool materials = false);
/// Fails (FileError) naming the particle or piece whose palette index is beyond a palette
/// of `palette_size` entries.
void check_spray_materials(const Reader& r, const SprayState& state, std::size_t palette_size);

}  // namespace shore::terrain
