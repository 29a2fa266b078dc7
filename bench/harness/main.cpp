// shore-bench: Shore's speed-against-error report. Runs the registered sweeps
// (bench/harness/sweeps/*.cpp), writes one CSV per table and gnuplot PNGs to --out, the
// results JSON to --json, and with --save a dated reference run under bench/results/ plus
// docs/BENCHMARKS.md.
// GCC 12 reports a false "potential null pointer dereference" inside CLI11's string
// splitting once inlined here; the warning is off for this file only.
#pragma GCC diagnostic ignored "-Wnull-dereference"
#include <CLI/CLI.hpp>

#include <charconv>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "output.h"
#include "shore/scenes/static_shares.h"
#include "sweep.h"

namespace fs = std::filesystem;
using namespace shore::bench;

namespace {

std::string command_line(int argc, char** argv) {
  std::string s = "shore-bench";
  for (int k = 1; k < argc; ++k) s += std::string(" ") + argv[k];
  return s;
}

std::vector<const Sweep*> select(const std::vector<std::string>& only) {
  std::vector<const Sweep*> chosen;
  std::set<std::string> wanted;
  for (const std::string& item : only) {
    std::stringstream parts(item);
    for (std::string name; std::getline(parts, name, ',');)
      if (!name.empty()) wanted.insert(name);
  }
  std::set<std::string> unknown = wanted;  // names no sweep answers to
  for (const Sweep& s : sweeps())
    if (wanted.empty() || wanted.count(s.name)) {
      chosen.push_back(&s);
      unknown.erase(s.name);
    }
  for (const auto& w : unknown) throw CLI::ValidationError("--only", "no sweep called " + w);
  return chosen;
}

void print_figures(const SweepResult& r) {
  for (const auto& [key, unit] : r.figure_list()) {
    std::string path = "/" + key;
    for (char& c : path)
      if (c == '.') c = '/';
    std::printf("    %-52s %12.4g %s\n", key.c_str(), r.figures()[nlohmann::json::json_pointer(path)].get<double>(),
                unit.c_str());
  }
}

/// An option's check whose message gives the value and what is allowed (CLI11 puts the
/// option's name first; its own PositiveNumber says only "Number less or equal to 0").
CLI::Validator whole_number_at_least_one(const std::string& allowed) {
  return CLI::Validator(
      [allowed](const std::string& text) -> std::string {
        std::int64_t v = 0;
        const char* end = text.data() + text.size();
        const auto [at, error] = std::from_chars(text.data(), end, v);
        if (error == std::errc() && at == end && v >= 1) return {};
        return "'" + text + "' is not allowed: " + allowed;
      },
      "INT >= 1");
}

}  // namespace

int main(int argc, char** argv) {
  std::string list_text;
  for (const Sweep& s : sweeps()) list_text += "\n  " + s.name + ": " + s.description;
  CLI::App app{"shore-bench: speed against error for Shore's modules.\nSweeps:" + list_text};
  bool quick = false, save = false, list = false;
  std::string json_file;
  fs::path out = "out/bench";
  std::vector<std::string> only;
  app.add_flag("--quick", quick, "short run (all sweeps under 5 minutes on 2 cores)");
  app.add_option("--json", json_file, "also write the results JSON to this file");
  app.add_option("--out", out, "folder for CSV files, plot scripts and PNGs")->capture_default_str();
  app.add_option("--only", only, "run only these sweeps (repeat or comma-separate)");
  app.add_flag("--save", save,
               "write bench/results/<YYYY-MM-DD>-<hostname>.json and docs/BENCHMARKS.md (committed reference runs)");
  app.add_flag("--list", list, "list the sweeps and exit");
  std::int64_t soak_substeps = 0;
  app.add_option("--soak-substeps", soak_substeps,
                 "substeps of the reliability sweep's soak (default 100,000; 5,000 with --quick)")
      ->check(whole_number_at_least_one(
          "must be a whole number of substeps (of 1/240 s) >= 1; leave the option out for the default "
          "(100,000; 5,000 with --quick)"));
  CLI11_PARSE(app, argc, argv);

  try {
    if (list) {
      for (const Sweep& s : sweeps()) std::printf("%-12s %s\n", s.name.c_str(), s.description.c_str());
      return 0;
    }
    const std::vector<const Sweep*> chosen = select(only);
    const int hardware_threads = shore::scenes::hardware_threads();
    fs::create_directories(out);
    std::vector<SweepRun> runs;
    int failed = 0;
    const auto start = std::chrono::steady_clock::now();
    const double load_at_start = load_average();
    std::printf("load average (1 min) at start: %.2f on %d hardware threads\n", load_at_start, hardware_threads);
    for (std::size_t k = 0; k < chosen.size(); ++k) {
      const Sweep& s = *chosen[k];
      std::printf("[%zu/%zu] %s: %s\n", k + 1, chosen.size(), s.name.c_str(), s.description.c_str());
      std::fflush(stdout);
      SweepRun run;
      run.sweep = &s;
      SweepContext ctx;
      ctx.quick = quick;
      ctx.max_threads = hardware_threads;
      ctx.soak_substeps = soak_substeps;
      const auto t0 = std::chrono::steady_clock::now();
      ctx.progress_fn = [&](const std::string& what) {
        const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::printf("    %6.1f s  %s\n", t, what.c_str());
        std::fflush(stdout);
      };
      try {
        s.run(ctx, run.result);
      } catch (const std::exception& e) {
        run.error = e.what();
        ++failed;
        std::fprintf(stderr, "shore-bench: sweep %s failed: %s\n", s.name.c_str(), e.what());
      }
      run.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      write_csv(out, run.result);
      render_plots(out, run.result);
      print_figures(run.result);
      for (const Target& tg : run.result.targets())
        std::printf("    target %-45s %s  %s\n", tg.key.c_str(), target_text(tg).c_str(), tg.pass() ? "PASS" : "SHORT");
      std::printf("    done in %.1f s\n", run.wall_seconds);
      runs.push_back(std::move(run));
    }
    const double total_so_far = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const nlohmann::json results =
        results_json(runs, quick, command_line(argc, argv), hardware_threads, load_at_start, total_so_far);
    write_text(out / "results.json", results.dump(2) + "\n");
    if (!json_file.empty()) write_text(json_file, results.dump(2) + "\n");
    if (save) {
      const fs::path source = SHORE_SOURCE_DIR;
      const std::string name = "bench/results/" + today() + "-" + host_name() + ".json";
      fs::create_directories(source / "bench/results");
      write_text(source / name, results.dump(2) + "\n");
      const fs::path md = write_benchmarks_md(source, results, runs, out, name);
      std::printf("saved %s and %s\n", (source / name).c_str(), md.c_str());
    }
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("output: %s/ (CSV, plots, results.json); total %.1f s\n", fs::absolute(out).lexically_normal().c_str(),
                total);
    return failed == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "shore-bench: %s\n", e.what());
    return 1;
  }
}
