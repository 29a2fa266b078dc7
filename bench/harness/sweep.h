#pragma once
// shore-bench sweeps: speed against error, one file per module in bench/harness/sweeps/.
//
// Adding a sweep = adding one file bench/harness/sweeps/<module>.cpp, listed in
// bench/harness/CMakeLists.txt. In it:
//
//   #include "sweep.h"
//   namespace shore::bench {
//   namespace {
//   void run(const SweepContext& ctx, SweepResult& out) {
//     Table& t = out.table("water_modes", {"method", "cells", "ms_per_substep", "error_rel"});
//     for (int n : ctx.quick ? std::vector{64, 128} : std::vector{64, 128, 256, 512}) {
//       ctx.progress("grid " + std::to_string(n));
//       const Measurement m = measure([&] { ... one substep ... });   // median of repeats
//       t.add({"fast", n, m.median_s * 1e3, error});
//     }
//     out.figure("water.fast_vs_reference_256", ratio, "x");          // nested JSON key + unit
//     out.plot({.name = "water_time_vs_error", .title = "...", .table = "water_modes",
//               .x = "error_rel", .y = "ms_per_substep", .series = "method"});
//   }
//   const SweepRegistrar kRegistered{{.name = "water", .description = "...", .run = run}};
//   }  // namespace
//   }  // namespace shore::bench
//
// Conventions: column names and figure keys carry their unit (ms_per_substep, error_m,
// triad_gbps_1t) or the figure gets an adjacent "<key>_unit"; "error" means the distance to
// an outside reference (Bekker's closed forms, Archimedes, exact volumes, the continuum:
// the reference cases of scenes/ name theirs), never to the code itself; compare methods
// side by side in one run (the machine is shared and noisy); keep --quick runs short (the
// whole quick suite must stay under 5 minutes on 2 cores). The scenes of scenes/ can be run
// from a sweep with shore::scenes::run_scene (write_files = false).

#include <functional>
#include <string>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

namespace shore::bench {

/// A table cell: a number or a label.
using Cell = std::variant<double, std::string>;

/// Rows of one CSV file (<out>/<name>.csv).
struct Table {
  std::string name;
  std::vector<std::string> columns;  ///< with units in the names: "ms_per_substep", "error_m"
  std::vector<std::vector<Cell>> rows;
  /// Appends a row; throws std::invalid_argument if its size differs from the columns'.
  void add(std::vector<Cell> row);
  /// Index of a column, or throws std::invalid_argument.
  [[nodiscard]] std::size_t column(const std::string& name) const;
};

/// A performance target: value op threshold, printed PASS or SHORT (never hidden).
struct Target {
  std::string key;     ///< the figure it checks ("plugin.wheel_ms_per_substep")
  std::string what;    ///< one line: "one towed wheel, 1 cm sand, 1/240 s"
  double value = 0.0;  ///< measured (NaN: not measured, counts as SHORT)
  std::string op;      ///< "<", "<=", ">" or ">="
  double threshold = 0.0;
  std::string unit;
  [[nodiscard]] bool pass() const;
};

/// One PNG plot (<out>/<name>.png): y against x, one curve per distinct value of series.
struct PlotSpec {
  std::string name;  ///< file stem, [a-z0-9_]+
  std::string title;
  std::string table;    ///< a table of the same sweep
  std::string x;        ///< column for the x axis
  std::string y;        ///< column for the y axis
  std::string series;   ///< column whose values name the curves (empty: one curve)
  std::string x_label;  ///< empty: the column name
  std::string y_label;  ///< empty: the column name
  bool log_x = true;
  bool log_y = true;
};

/// What a sweep produces.
class SweepResult {
 public:
  /// A new table (CSV) with these columns.
  Table& table(const std::string& name, std::vector<std::string> columns);
  /// A headline figure under a dotted key ("terrain.wheel_ms_per_substep" becomes
  /// {"terrain": {"wheel_ms_per_substep": v, "wheel_ms_per_substep_unit": unit}}).
  void figure(const std::string& key, double value, const std::string& unit);
  void plot(PlotSpec spec);
  /// A sentence for docs/BENCHMARKS.md (what was measured, conditions).
  void note(std::string text);
  /// A target the report states as PASS or SHORT; throws std::invalid_argument on a bad op.
  void target(Target t);

  [[nodiscard]] const std::vector<Table>& tables() const noexcept { return tables_; }
  [[nodiscard]] const std::vector<PlotSpec>& plots() const noexcept { return plots_; }
  [[nodiscard]] const nlohmann::json& figures() const noexcept { return figures_; }
  [[nodiscard]] const std::vector<std::pair<std::string, std::string>>& figure_list() const noexcept {
    return figure_list_;
  }
  [[nodiscard]] const std::vector<std::string>& notes() const noexcept { return notes_; }
  [[nodiscard]] const std::vector<Target>& targets() const noexcept { return targets_; }

 private:
  std::vector<Table> tables_;
  std::vector<PlotSpec> plots_;
  nlohmann::json figures_ = nlohmann::json::object();
  std::vector<std::pair<std::string, std::string>> figure_list_;  // key, unit (in order)
  std::vector<std::string> notes_;
  std::vector<Target> targets_;
};

struct SweepContext {
  bool quick = false;   ///< short run (all sweeps together well under 5 minutes on 2 cores)
  int max_threads = 1;  ///< hardware threads of the machine
  std::function<void(const std::string&)> progress_fn;
  /// Prints a progress line for the current sweep.
  void progress(const std::string& what) const {
    if (progress_fn) progress_fn(what);
  }
};

struct Sweep {
  std::string name;         ///< [a-z0-9_]+, used by --only and as the figures' first key
  std::string description;  ///< one line for --help and BENCHMARKS.md
  std::function<void(const SweepContext&, SweepResult&)> run;
};

/// Every registered sweep, sorted by name.
const std::vector<Sweep>& sweeps();

/// Registers a sweep at static-initialisation time; throws std::logic_error on duplicates.
struct SweepRegistrar {
  explicit SweepRegistrar(Sweep sweep);
};

}  // namespace shore::bench
