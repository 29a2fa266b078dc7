#pragma once
// Private: one material as the saved terrain state writes it (layout at the top of
// terrain_io.cpp), shared by the state file's header and palette and the soil deltas'
// palette (soil_delta.cpp).

#include "shore/terrain/material.h"
#include "state_file.h"

namespace shore::terrain {

/// A material's name, soil, bearing and shear fields, in the file's order (its spray and
/// unload_modulus follow, with the terrain's spray settings between them in the header).
void write_material_fields(Writer& w, const Material& m);
/// A whole material: its fields, its spray settings and unload_modulus (a palette entry).
void write_material(Writer& w, const Material& m);
/// What write_material wrote. Fails (FileError) if the bytes end early or the name is
/// longer than 4096 bytes; the values are not validated (Material::validate does).
Material read_material(Reader& r);

}  // namespace shore::terrain
