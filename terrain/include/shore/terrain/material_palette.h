#pragma once
// A material palette as a text file, for a material map (Terrain::set_palette; an index
// image paints it, shore/terrain/material_image.h). One material per line:
//
//   # index  preset  [field=value ...]      ('#' starts a comment; blank lines are skipped)
//   0 sand
//   1 mud bekker_kphi=1.5e6 alpha=0.3
//   2 sand name=gravel bekker_kphi=6e6 theta_out=0.6
//
// Indices run from 0 without gaps, in order, at most 256 of them. The preset is one of
// Material::preset's names ("sand", "mud", "snow", "rigid"); the fields, in the units of
// shore/terrain/material.h (angles in radians), override it: name (text), rigid (0 or 1),
// and every number of Material and its spray (spray.adhesion, spray.drag, ...).

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "shore/terrain/material.h"

namespace shore::terrain {

/// Reads a palette file. Throws shore::FileError naming the file, the line and the problem
/// (an unknown preset or field, a value that is not a number, a missing or repeated index, a
/// material that fails Material::validate, which names the field and its range).
std::vector<Material> read_palette(const std::filesystem::path& file);
/// read_palette() of text already in memory; `name` stands for the file in messages.
std::vector<Material> parse_palette(std::string_view text, const std::string& name);

}  // namespace shore::terrain
