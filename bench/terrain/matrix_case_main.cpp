// shore_matrix_case: runs the validation matrix's cases whose soil and family contain the
// given words (case-sensitive; empty: all) and prints every cell, for iterating on a family
// of misses without the whole sweep.
//   shore_matrix_case [soil-part] [family-part] [--quick] [--box-starts N] [--box-shift M]
// --box-starts: the slope box's starts per cell (default 4; 0: one on the column lattice's
// tie, as before); --box-shift: every start moved across the slope by M metres (to see how
// a cell spreads with sub-micron changes).
#include <cstdio>
#include <cstdlib>
#include <string>

#include "shore/scenes/validation_matrix.h"

namespace sc = shore::scenes;

int main(int argc, char** argv) {
  std::string soil, family;
  bool quick = false;
  int positional = 0, box_starts = sc::MatrixCase{}.box_starts;
  double box_shift = 0.0;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--quick")
      quick = true;
    else if (a == "--box-starts" && k + 1 < argc)
      box_starts = std::atoi(argv[++k]);
    else if (a == "--box-shift" && k + 1 < argc)
      box_shift = std::atof(argv[++k]);
    else
      (positional++ == 0 ? soil : family) = a;
  }
  const auto soils = sc::matrix_soils();
  int cells = 0, within = 0;
  for (sc::MatrixCase c : sc::matrix_cases(quick)) {
    if (soils[c.soil].name.find(soil) == std::string::npos || c.family.find(family) == std::string::npos) continue;
    c.box_starts = box_starts, c.box_shift = box_shift;
    for (const sc::MatrixCell& m : sc::run_matrix_case(c)) {
      std::printf("%-24s %-13s %-28s %-26s measured %11.5g reference %11.5g error %+8.4f (%s) tol %.2f %s %s  %.1f s\n",
                  m.soil.c_str(), m.family.c_str(), m.label.c_str(), m.quantity.c_str(), m.measured, m.reference,
                  m.error, m.error_kind.c_str(), m.tolerance, m.within() ? "ok   " : "MISS ",
                  (m.outside_validity.empty() ? m.note : "[outside: " + m.outside_validity + "] " + m.note).c_str(),
                  m.wall_seconds);
      std::fflush(stdout);
      ++cells, within += m.within() ? 1 : 0;
    }
  }
  std::printf("%d cells, %d within tolerance\n", cells, within);
  return 0;
}
