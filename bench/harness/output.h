#pragma once
// shore-bench output: CSV per table, gnuplot PNGs, the results JSON and docs/BENCHMARKS.md.

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sweep.h"

namespace shore::bench {

struct SweepRun {
  const Sweep* sweep = nullptr;
  SweepResult result;
  double wall_seconds = 0.0;
  std::string error;  ///< empty if it ran
};

/// Writes <dir>/<table>.csv for every table; returns the paths.
std::vector<std::filesystem::path> write_csv(const std::filesystem::path& dir, const SweepResult& r);

/// True if a gnuplot executable is on PATH.
bool have_gnuplot();

/// Writes <dir>/<plot>.gp and renders <dir>/<plot>.png with gnuplot; returns the PNGs made.
/// Without gnuplot, writes the scripts only and warns once on stderr.
std::vector<std::filesystem::path> render_plots(const std::filesystem::path& dir, const SweepResult& r);

/// The results document: meta (date, host, cpu, threads, precision, quick), figures merged
/// across sweeps, tables, and per-sweep wall time and errors.
/// hardware_threads: the machine's (std::thread::hardware_concurrency);
/// load_at_start: load_average() before the first sweep.
nlohmann::json results_json(const std::vector<SweepRun>& runs, bool quick, const std::string& command,
                            int hardware_threads, double load_at_start, double total_seconds);

/// 1-minute load average (-1 if unknown): above the core count, timings are inflated.
double load_average();

/// "PASS" or "SHORT" and the target as text, e.g. "0.31 ms < 0.5 ms".
std::string target_text(const Target& t);

/// Writes docs/BENCHMARKS.md: the figures table, per-sweep notes and plots (copied from
/// plot_dir to docs/bench/), and the command that reproduces them.
std::filesystem::path write_benchmarks_md(const std::filesystem::path& source_dir, const nlohmann::json& results,
                                          const std::vector<SweepRun>& runs, const std::filesystem::path& plot_dir,
                                          const std::string& results_file);

/// "YYYY-MM-DD" (local date) and the host name.
std::string today();
std::string host_name();

/// Writes text to path through a temporary file renamed into place.
void write_text(const std::filesystem::path& path, const std::string& text);

}  // namespace shore::bench
