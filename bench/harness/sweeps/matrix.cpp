// matrix: the validation matrix (scenes/validation_matrix.h). Wong's soils crossed with the
// plate, the static and towed rigid wheel, the driven wheel, the box on slopes and the
// sphere drop; every cell against its outside reference and tolerance. One thread per case.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "shore/scenes/validation_matrix.h"
#include "sweep.h"

namespace shore::bench {
namespace {

std::string cell_name(const scenes::MatrixCell& m) {
  return m.soil + ", " + m.family + " " + m.label + ", " + m.quantity;
}

/// v with `decimals` digits after the point, sign shown if `sign`.
std::string fixed(double v, int decimals, bool sign) {
  char buf[48];
  std::snprintf(buf, sizeof buf, sign ? "%+.*f" : "%.*f", decimals, v);
  return buf;
}

void run(const SweepContext& ctx, SweepResult& out) {
  Table& t = out.table("matrix", {"soil", "family", "case", "quantity", "measured", "reference", "error", "error_kind",
                                  "tolerance", "error_over_tolerance", "result", "note", "wall_s"});
  const std::vector<scenes::MatrixSoil> soils = scenes::matrix_soils();
  std::vector<scenes::MatrixCell> cells;
  // The whole matrix takes about a minute on one core, so --quick runs all of it too
  // (matrix_cases(true), one setting per family, is shore_matrix_case --quick's).
  for (const scenes::MatrixCase& c : scenes::matrix_cases(false)) {
    ctx.progress(soils[c.soil].name + ", " + c.family + " " + c.label);
    for (scenes::MatrixCell& m : scenes::run_matrix_case(c)) {
      const std::string result = !m.outside_validity.empty() ? "outside validity: " + m.outside_validity
                                 : m.within()                ? "within"
                                                             : "MISS";
      t.add({m.soil, m.family, m.label, m.quantity, m.measured, m.reference, fixed(m.error, 4, true), m.error_kind,
             m.tolerance, fixed(m.error_over_tolerance(), 2, false), result, m.note, fixed(m.wall_seconds, 2, false)});
      cells.push_back(std::move(m));
    }
  }
  std::size_t within = 0, valid = 0, valid_within = 0;
  const scenes::MatrixCell* worst = nullptr;
  const scenes::MatrixCell* worst_any = nullptr;
  for (const scenes::MatrixCell& m : cells) {
    within += m.within() ? 1 : 0;
    if (!worst_any || m.error_over_tolerance() > worst_any->error_over_tolerance()) worst_any = &m;
    if (!m.outside_validity.empty()) continue;
    ++valid, valid_within += m.within() ? 1 : 0;
    if (!worst || m.error_over_tolerance() > worst->error_over_tolerance()) worst = &m;
  }
  const double n = double(std::max<std::size_t>(cells.size(), 1));
  out.figure("accuracy.matrix_cells", double(cells.size()), "cells (quantities measured against a reference)");
  out.figure("accuracy.matrix_within_tolerance", double(within) / n, "fraction of all cells within tolerance");
  out.figure("accuracy.matrix_valid_cells", double(valid), "cells inside the references' validity");
  out.figure("accuracy.matrix_within_tolerance_valid", double(valid_within) / double(std::max<std::size_t>(valid, 1)),
             "fraction of the cells inside the references' validity within tolerance");
  if (worst)
    out.figure("accuracy.matrix_worst", worst->error_over_tolerance(),
               "x its tolerance, the worst cell inside validity: " + cell_name(*worst) + " (error " +
                   fixed(worst->error, 4, true) + " " + worst->error_kind + ", tolerance " +
                   fixed(worst->tolerance, 2, false) + ")");
  if (worst_any)
    out.figure("accuracy.matrix_worst_any", worst_any->error_over_tolerance(),
               "x its tolerance, the worst cell of all: " + cell_name(*worst_any));
  // The five worst cells inside validity, each as its own figure.
  std::vector<const scenes::MatrixCell*> order;
  for (const scenes::MatrixCell& m : cells)
    if (m.outside_validity.empty()) order.push_back(&m);
  std::sort(order.begin(), order.end(), [](const scenes::MatrixCell* a, const scenes::MatrixCell* b) {
    return a->error_over_tolerance() > b->error_over_tolerance();
  });
  for (std::size_t k = 0; k < std::min<std::size_t>(5, order.size()); ++k)
    out.figure("accuracy.matrix_worst_" + std::to_string(k + 1), order[k]->error_over_tolerance(),
               "x tolerance: " + cell_name(*order[k]) + " (error " + fixed(order[k]->error, 4, true) + " " +
                   order[k]->error_kind + ")");
  // The worst cell of each family, inside validity.
  for (const char* family : {"plate", "wheel static", "wheel towed", "driven wheel", "slope box", "sphere drop"}) {
    const scenes::MatrixCell* w = nullptr;
    std::size_t n_family = 0, n_within = 0;
    for (const scenes::MatrixCell* m : order)
      if (m->family == family) {
        if (!w) w = m;
        ++n_family, n_within += m->within() ? 1 : 0;
      }
    if (!w) continue;
    std::string key = family;
    std::replace(key.begin(), key.end(), ' ', '_');
    out.figure("accuracy.matrix_worst_" + key, w->error_over_tolerance(),
               "x tolerance (" + std::to_string(n_within) + " of " + std::to_string(n_family) +
                   " within): " + cell_name(*w) + " (error " + fixed(w->error, 4, true) + " " + w->error_kind + ")");
  }
  out.target({.key = "accuracy.matrix_worst",
              .what = "validation matrix: the worst cell inside the references' validity, error over tolerance",
              .value = worst ? worst->error_over_tolerance() : 0.0,
              .op = "<=",
              .threshold = 1.0,
              .unit = "x tolerance"});
  out.note(
      "Validation matrix (scenes/src/validation_matrix.cpp): Wong's soils (dry sand = sand preset, LETE sand, sandy "
      "loam 15 % and 22 %, clayey soil 38 % and 55 % = mud preset, heavy clay 25 %, snow = snow preset; the others "
      "are the sand preset with Wong's n, k_c, k_phi, c, phi, K) crossed with: a square plate 0.2 and 0.4 m wide at "
      "two pressures, weight eased in over 3 s so it arrives at rest (Bekker, tolerance 3 %); a rigid wheel D 0.5 and "
      "0.8 m, b 0.3 m at two "
      "loads, pressed statically (both halves, 10 %) and towed 2 m at 1 m/s (rolling sinkage 10 %, compaction "
      "resistance 15 %); a driven wheel D 0.6 m, b 0.15 m at slips 0.1, 0.2, 0.3, 0.5 (Wong-Reece: drawbar pull "
      "0.08 W, torque 15 %, sinkage 20 %); a flat box (0.3 m square, 0.06 m tall) released on slopes phi - 7, phi + 7 "
      "and phi + 12 deg "
      "pressing the soil 5 mm (Wong's sliding block on the soil's Janosi-Hanamoto curve, Coulomb's at K 0, less "
      "Bekker's compaction resistance of its sinkage: whole slide 2 d / T^2 over 1.5 s and the second half's fit, "
      "each the mean over 4 starts spread over a column cell, 10 %, of g sin theta where it should hold); a 10 kg "
      "sphere D 0.2 m dropped 1 m (deepest "
      "point against the energy balance on Bekker's pressure with the soil's shear on the sphere's surface, 10 %). "
      "Loads per soil keep Bekker's sinkage at a few cm. 1 cm cells, "
      "1/240 s, one thread per case; --quick runs the whole matrix too (about a minute). Cells outside a "
      "reference's own assumptions are marked (docs/terrain.md, 'Validation matrix') and not counted in "
      "matrix_worst.");
}

const SweepRegistrar kRegistered{Sweep{
    .name = "matrix",
    .description = "validation matrix: Wong's soils x plate, rigid wheel, driven wheel, slope box, sphere drop",
    .run = run,
}};

}  // namespace
}  // namespace shore::bench
