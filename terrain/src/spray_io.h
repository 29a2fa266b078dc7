#pragma once
// Private: spray's part of the saved terrain state (version 4 on; layout at the top of
// terrain_io.cpp): the material's and the terrain's spray settings, and the spray state
// (with each particle's and clinging piece's palette index, version 8 on; with each body's
// last clinging step, version 9 on).

#include "shore/terrain/terrain.h"
#include "spray_state.h"
#include "state_file.h"

namespace shore::terrain {

/// A material's spray settings (part of every saved material).
void write_spray_material(Writer& w, const SprayMaterial& m);
/// The material's spray settings, then the terrain's.
void write_spray_settings(Writer& w, const TerrainSettings& s);
void read_spray_settings(Reader& r, TerrainSettings& s);
/// What a saved spray state carries beyond the first layout (version 4 of the terrain state).
struct SprayLayout {
  /// Each particle and clinging piece carries its palette index (u8, after its other
  /// fields: terrain state version 8 on, soil delta version 5 on); without it every one must
  /// be entry 0's (a terrain with one material writes the bytes it wrote before maps).
  bool materials = false;
  /// Each body carries the spray step its soil was last stepped on (i64 `stepped`, after its
  /// orientation: terrain state version 9 on, soil delta version 6 on); without it every body
  /// must have been stepped on the step just done (SprayState::has_bodies_between_steps
  /// false), and loads so.
  bool steps = false;
};

void write_spray_state(Writer& w, const SprayState& state, SprayLayout layout = {});
/// Fails (FileError) on counts that do not fit the file, values that are not finite, or a
/// body's `stepped` not before the state's step. `layout.materials`: the indices are there
/// to read (else all are 0); check_spray_materials checks them against the palette once it
/// is known. Without `layout.steps`, each body takes step - 1.
void read_spray_state(Reader& r, SprayState& state, SprayLayout layout = {});
/// Fails (FileError) naming the particle or piece whose palette index is beyond a palette
/// of `palette_size` entries.
void check_spray_materials(const Reader& r, const SprayState& state, std::size_t palette_size);

}  // namespace shore::terrain
