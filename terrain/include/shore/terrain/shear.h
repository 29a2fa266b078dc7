#pragma once
// Janosi and Hanamoto's shear law and the loss of bearing in sheared soil (Wong, Theory
// of Ground Vehicles, ch. 2). Stresses in Pa, shear displacements in m.

#include "shore/terrain/material.h"

namespace shore::terrain::shear {

/// Shear strength under normal stress sigma: c + sigma tan(phi).
double strength(const Material& m, double sigma);

/// Share of the strength mobilised at shear displacement j: 1 - exp(-|j| / K).
double mobilisation(const Material& m, double j);

/// Shear stress (Janosi-Hanamoto): (c + sigma tan phi)(1 - exp(-|j| / K)).
double stress(const Material& m, double sigma, double j);

/// How much shallower soil sheared by j bears as: s = 1 - remould_ratio (1 - exp(-|j| /
/// remould_length)). Shear loosens soil; pressed to sinkage z it bears Bekker's pressure of
/// intact soil pressed to s z, so the sinkage shear adds is a multiple 1 / s of the
/// sinkage, the same for every exponent n (docs/terrain.md, "Validation matrix").
double loosening(const Material& m, double j);

/// Share of Bekker's yield pressure left in soil sheared by j: loosening(m, j)^n.
double remoulding(const Material& m, double j);

/// Share of the shear strength left in soil sheared by j:
/// 1 - remould_shear_ratio (1 - exp(-|j| / remould_length)).
double strength_remoulding(const Material& m, double j);

}  // namespace shore::terrain::shear
