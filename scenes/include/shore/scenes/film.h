#pragma once
// When a scene's filmstrip frames are taken and how they are labelled.

#include <span>
#include <string>
#include <vector>

namespace shore::scenes {

/// "t = 1.25 s".
std::string time_label(double seconds);

/// `frames` substeps spread evenly over a run of `substeps`: round(substeps q / (frames - 1))
/// for q = 0 .. frames - 1, the first at 0 (before the first substep), the last at the end.
std::vector<int> evenly_spread(int substeps, int frames);

/// The usual filmstrip of a run of `substeps`: 3 frames spread evenly in smoke runs, 6 otherwise.
std::vector<int> evenly_spread_film(int substeps, bool smoke);

/// The substep nearest each fraction of a run of `substeps`, clamped to [first, substeps].
std::vector<int> at_fractions(int substeps, std::span<const double> fractions, int first);

}  // namespace shore::scenes
