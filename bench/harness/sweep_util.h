#pragma once
// Small helpers shared by the sweeps: labels, relative errors and the "cross" of settings
// (a cell-size series at the standard substep and a substep series at the standard cell).

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace shore::bench {

/// "1/240 s" for a substep of 1/240 s.
inline std::string substep_label(double h) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "1/%.0f s", 1.0 / h);
  return buf;
}

/// "1 cm", "0.5 cm".
inline std::string cell_label(double cell) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g cm", cell * 100.0);
  return buf;
}

/// Signed relative error in percent: 100 (value - reference) / reference.
inline double error_pct(double value, double reference) { return 100.0 * (value - reference) / reference; }

/// True when two substeps (or cells) are the same setting.
inline bool same(double a, double b) { return std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b)); }

/// One run of a cross sweep: which parameter this row varies, and the setting.
struct CrossPoint {
  double cell = 0.01;            ///< m
  double substep = 1.0 / 240;    ///< s
  bool on_cell_axis = false;     ///< part of the cell-size series (substep = standard)
  bool on_substep_axis = false;  ///< part of the substep series (cell = standard)
};

/// Cell sizes at the standard substep, then substeps at the standard cell; the standard
/// point (on both axes) is listed once.
inline std::vector<CrossPoint> cross(const std::vector<double>& cells, const std::vector<double>& substeps,
                                     double standard_cell, double standard_substep) {
  std::vector<CrossPoint> points;
  for (double c : cells) points.push_back({c, standard_substep, true, same(c, standard_cell)});
  for (double h : substeps) {
    bool listed = false;
    for (CrossPoint& p : points)
      if (same(p.cell, standard_cell) && same(p.substep, h)) {
        p.on_substep_axis = true;
        listed = true;
      }
    if (!listed) points.push_back({standard_cell, h, false, true});
  }
  return points;
}

}  // namespace shore::bench
