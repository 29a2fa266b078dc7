// reliability: the long soak and the extremes of the settings ranges.
// - Soak: 50 bodies of every shape type, 40 on sand and 10 in a walled pool beside it,
//   100,000 substeps at 1/240 s (--soak-substeps to change; --quick: 5,000): NaN count,
//   one body thrown up every second (SoakCase::kick_every); fall-throughs, rescues after settling, soil volume drift
//   over the moved volume, water volume drift against what the bodies displaced, resident memory growth over the last
//   90 % and time per substep of the last 10,000 substeps over the first 10,000 after the
//   warm-up (a tenth of the run): the stepping thread's median CPU time per 100-substep
//   block (soak_slowdown; wall time on a shared machine is noisy) and the wall time
//   (soak_slowdown_wall).
// - Extremes: each case of shore/scenes/extreme_cases.h, its sinkage against its reference.
// - Fuzzing: executions per target of the last `./shore fuzz` run in this checkout
//   (build/fuzz/fuzz_stats.json), stated as a CI or a local run; absent if it was never run.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "shore/scenes/extreme_cases.h"
#include "shore/scenes/soak.h"
#include "sweep.h"

namespace shore::bench {
namespace {

void soak(const SweepContext& ctx, SweepResult& out) {
  scenes::SoakCase c;
  c.floating_bodies = 10;
  c.substeps = ctx.soak_substeps > 0 ? ctx.soak_substeps : (ctx.quick ? 5000 : 100000);
  c.check_every = 100;
  const std::int64_t report_every = std::max<std::int64_t>(c.check_every, c.substeps / 20 / 100 * 100);
  c.progress = [&](std::int64_t s) {
    if (s % report_every == 0) ctx.progress("soak substep " + std::to_string(s) + " / " + std::to_string(c.substeps));
  };
  const scenes::SoakResult r = scenes::run_soak(c);
  const double volume_drift = r.soil_moved_volume > 0 ? r.soil_volume_drift / r.soil_moved_volume : 0.0;
  const double rss_growth = scenes::SoakResult::growth(r.rss_warm, r.rss_max);
  Table& t = out.table("reliability_soak", {"quantity", "value", "unit"});
  t.add({"substeps", double(r.substeps), "substeps of 1/240 s"});
  t.add({"nan", double(r.nan_count), "non-finite values seen"});
  t.add({"fall_throughs", double(r.fall_throughs), "bodies"});
  t.add({"rescues", double(r.rescues), "lifts above bedrock"});
  t.add({"rescues_after_settling", double(r.rescues_after_settling), "lifts after 2 s"});
  t.add({"lost_bodies", double(r.lost_bodies), "bodies"});
  t.add({"soil_moved_volume", r.soil_moved_volume, "m^3"});
  t.add({"soil_volume_drift", r.soil_volume_drift, "m^3"});
  t.add({"water_displaced_volume", r.water_displaced_volume, "m^3"});
  t.add({"water_volume_drift", r.water_volume_drift, "m^3"});
  t.add({"soil_memory_warm", double(r.soil_memory_warm), "bytes"});
  t.add({"soil_memory_max", double(r.soil_memory_max), "bytes"});
  t.add({"soil_tiles_warm", double(r.soil_tiles_warm), "tiles"});
  t.add({"soil_tiles_max", double(r.soil_tiles_max), "tiles"});
  t.add({"water_memory_warm", double(r.water_memory_warm), "bytes"});
  t.add({"water_memory_max", double(r.water_memory_max), "bytes"});
  t.add({"rss_warm", double(r.rss_warm), "bytes"});
  t.add({"rss_max", double(r.rss_max), "bytes"});
  t.add({"first_window_ms_per_substep", 1e3 * r.first_window_seconds / double(r.window_substeps), "ms"});
  t.add({"last_window_ms_per_substep", 1e3 * r.last_window_seconds / double(r.window_substeps), "ms"});
  t.add({"first_window_cpu_ms_per_substep", 1e3 * r.first_window_cpu, "ms (median of 100-substep blocks)"});
  t.add({"last_window_cpu_ms_per_substep", 1e3 * r.last_window_cpu, "ms (median of 100-substep blocks)"});
  t.add({"wall_seconds", r.wall_seconds, "s"});
  out.figure("reliability.soak_substeps", double(r.substeps), "substeps");
  out.figure("reliability.soak_nan", double(r.nan_count), "count");
  out.figure("reliability.soak_fall_throughs", double(r.fall_throughs), "bodies");
  out.figure("reliability.soak_rescues_after_settling", double(r.rescues_after_settling), "count");
  out.figure("reliability.soak_volume_drift", volume_drift, "of the moved volume");
  out.figure("reliability.soak_water_volume_drift", r.water_volume_drift, "m^3");
  out.figure("reliability.soak_rss_growth", rss_growth, "ratio - 1");
  out.figure("reliability.soak_soil_memory_growth", scenes::SoakResult::growth(r.soil_memory_warm, r.soil_memory_max),
             "ratio - 1");
  out.figure("reliability.soak_soil_tiles_growth", scenes::SoakResult::growth(r.soil_tiles_warm, r.soil_tiles_max),
             "ratio - 1");
  out.figure("reliability.soak_slowdown", r.slowdown(), "last/first (median CPU time per substep)");
  out.figure("reliability.soak_slowdown_wall", r.slowdown_wall(), "last/first (wall time)");
  const std::string what = std::to_string(r.substeps) + " substeps, 50 bodies";
  out.target({"reliability.soak_nan", what, double(r.nan_count), "<=", 0.0, "count"});
  out.target({"reliability.soak_fall_throughs", what, double(r.fall_throughs), "<=", 0.0, "bodies"});
  out.target({"reliability.soak_rescues_after_settling", what, double(r.rescues_after_settling), "<=", 0.0, "count"});
  out.target({"reliability.soak_volume_drift", what, volume_drift, "<=", 1e-9, "of the moved volume"});
  out.target({"reliability.soak_water_volume_drift", what + " (walled pool: exact)", r.water_volume_drift, "<=", 1e-12,
              "m^3"});
  out.target({"reliability.soak_rss_growth", what + ", last 90 %", rss_growth, "<=", 0.05, "ratio - 1"});
  out.target({"reliability.soak_slowdown",
              what + ", last/first " + std::to_string(r.window_substeps) + " substeps (median CPU time per substep)",
              r.slowdown(), "<=", 1.10, "last/first"});
  out.note("Soak: " + std::to_string(r.substeps) + " substeps of 1/240 s, 40 bodies on 4 cm sand and 10 in a walled " +
           "0.3 m pool beside it, one thread; warm-up " + std::to_string(r.warm_up_substeps) +
           " substeps, windows of " + std::to_string(r.window_substeps) +
           "; resident memory from /proc/self/statm (the whole process). Wall time on a shared machine is " +
           "noisy: soak_slowdown compares the stepping thread's median CPU time per substep (blocks of 100 " +
           "substeps) in the two windows, soak_slowdown_wall their wall times.");
}

void extremes(const SweepContext& ctx, SweepResult& out) {
  Table& t = out.table("reliability_extremes", {"case", "sinkage_m", "reference_m", "error_m", "error_pct", "finite",
                                                "above_bedrock", "wall_s"});
  int bad = 0;
  for (const scenes::ExtremeCase& c : scenes::extreme_cases(ctx.quick)) {
    ctx.progress("extreme " + c.name + ": " + c.what);
    const scenes::ExtremeResult r = scenes::run_extreme(c);
    const double pct = r.reference > 0 ? 100.0 * r.error() / r.reference : std::numeric_limits<double>::quiet_NaN();
    t.add({c.name, r.sinkage, r.reference, r.error(), pct, r.finite ? 1.0 : 0.0, r.above_bedrock() ? 1.0 : 0.0,
           r.wall_seconds});
    out.figure("reliability.extreme." + c.name + "_sinkage_m", r.sinkage, "m");
    out.figure("reliability.extreme." + c.name + "_error_pct", pct, "%");
    if (!r.finite || !r.above_bedrock()) ++bad;
  }
  out.figure("reliability.extreme_failures", bad, "cases not finite or below bedrock");
  out.target(
      {"reliability.extreme_failures", "every extreme finite and above bedrock", double(bad), "<=", 0.0, "cases"});
}

/// What build/fuzz/fuzz_stats.json says, or why it cannot be used (a run of scripts/fuzz.sh
/// from before it wrote "run", or a file cut short).
struct FuzzStats {
  nlohmann::json targets;
  std::string run, source, problem;
};

FuzzStats read_fuzz_stats(const std::filesystem::path& file) {
  FuzzStats s;
  std::ifstream in(file);
  if (!in) {
    s.problem = "no " + file.string() + " (run ./shore fuzz 60 first)";
    return s;
  }
  try {
    const nlohmann::json stats = nlohmann::json::parse(in);
    s.targets = stats.at("targets");
    s.run = stats.value("run", std::string("local"));
    s.source = stats.at("source").get<std::string>();
  } catch (const nlohmann::json::exception& e) {
    s.problem = file.string() + " is not what ./shore fuzz writes (" + e.what() + ")";
  }
  return s;
}

void fuzz_stats(SweepResult& out) {
  const FuzzStats stats = read_fuzz_stats(std::filesystem::path(SHORE_SOURCE_DIR) / "build/fuzz/fuzz_stats.json");
  if (!stats.problem.empty()) {
    out.note("Fuzzing: " + stats.problem + ": reliability.fuzz_execs_per_target not reported.");
    return;
  }
  Table& t = out.table("reliability_fuzz", {"target", "executions", "executions_per_second", "crashed"});
  double fewest = std::numeric_limits<double>::infinity();
  std::string crashed;
  for (const auto& [name, target] : stats.targets.items()) {
    const double runs = target.at("executions").get<double>();
    const bool crash = target.value("crashed", false);
    t.add({name, runs, target.value("executions_per_second", 0.0), crash ? 1.0 : 0.0});
    out.figure("reliability.fuzz_execs." + name, runs, "executions");
    fewest = std::min(fewest, runs);
    if (crash) crashed += (crashed.empty() ? "" : ", ") + name;
  }
  out.figure("reliability.fuzz_execs_per_target", fewest, "executions (fewest of the targets)");
  out.figure("reliability.fuzz_from_ci", stats.run == "ci" ? 1.0 : 0.0, "1: the CI run, 0: a local run");
  out.note("Fuzzing: executions per target from " + std::string(stats.run == "ci" ? "the CI run" : "a local run") +
           ", " + stats.source + " (read from build/fuzz/fuzz_stats.json)" +
           (crashed.empty() ? ", no crash." : "; crashed: " + crashed + "."));
}

void run(const SweepContext& ctx, SweepResult& out) {
  soak(ctx, out);
  extremes(ctx, out);
  fuzz_stats(out);
}

const SweepRegistrar kRegistered{
    {.name = "reliability",
     .description = "soak of 50 bodies on sand beside water (100,000 substeps), extremes of the settings, fuzz runs",
     .run = run}};

}  // namespace
}  // namespace shore::bench
