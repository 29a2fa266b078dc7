#pragma once
// A demo scene: written once, run by shore-demo, the demos test suite and shore-bench.
//
// Adding a scene = adding one file demos/scenes/<name>.cpp (globbed) that builds a Scene
// and registers it at static-initialisation time:
//
//   namespace {
//   shore::demo::SceneResult run(const shore::demo::SceneOptions& o, shore::demo::Progress& p) {
//     ... simulate o.substeps() substeps of o.substep seconds, call p.update(k / n) ...
//     shore::demo::SceneResult r;
//     r.state_hash = hash.value();
//     r.metrics = shore::demo::common_metrics("my_scene", o, substeps, wall, r.state_hash, nan_count);
//     r.metrics["my_metric_m"] = ...;                      // plus a line in metric_help
//     r.files.push_back(shore::demo::write_png(o.file("top.png"), image));
//     return r;
//   }
//   const shore::demo::SceneRegistrar kRegistered{{.name = "my_scene", .description = "...",
//                                                  .defaults = {...}, .metric_help = {...}, .run = run}};
//   }  // namespace
//
// then pin its state hash on purpose (see tests/demos/README.md).

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "shore/demo/progress.h"

namespace shore::demo {

/// What a scene runs with unless the command line says otherwise.
struct SceneDefaults {
  double seconds = 2.0;           ///< s, simulated time of a normal run, > 0
  double substep = 1.0 / 240.0;   ///< s, fixed substep, > 0
  std::string material = "sand";  ///< sand | mud | snow
  double cell = 0.01;             ///< m, grid spacing, > 0
  double smoke_seconds = 0.25;    ///< s, simulated time of a smoke run (tests, hash pinning), > 0
};

/// Fully resolved settings of one run.
struct SceneOptions {
  std::filesystem::path out_dir = "out";  ///< this scene's own output directory (<out>/<scene>)
  int threads = 1;                        ///< OpenMP threads, >= 1
  double seconds = 2.0;                   ///< s, simulated time, > 0
  double substep = 1.0 / 240.0;           ///< s, fixed substep, in (0, 0.1]
  std::string material = "sand";          ///< sand | mud | snow
  double cell = 0.01;                     ///< m, grid spacing, in (0, 1]
  bool smoke = false;                     ///< short run: scenes may also shrink grids and frames
  bool write_files = true;                ///< false: metrics only (benchmarks, hash pinning)

  /// Throws shore::InvalidSetting naming the field, the value and the allowed range.
  void validate() const;
  /// Number of fixed substeps: seconds / substep rounded, at least 1.
  [[nodiscard]] int substeps() const;
  /// out_dir / name.
  [[nodiscard]] std::filesystem::path file(const std::string& name) const { return out_dir / name; }
};

/// What a run produced. metrics holds the common fields (see common_metrics) plus the
/// scene's own; files are the paths written (metrics.json is added by run_scene).
struct SceneResult {
  nlohmann::json metrics = nlohmann::json::object();
  std::vector<std::filesystem::path> files;
  std::uint64_t state_hash = 0;
};

/// One line of the report: what a metric means.
struct MetricHelp {
  std::string name;
  std::string meaning;
};

struct Scene {
  std::string name;         ///< identifier: [a-z0-9_]+, the subcommand and the output folder
  std::string description;  ///< one paragraph: what it shows and what to look at
  SceneDefaults defaults;
  std::vector<MetricHelp> metric_help;  ///< the scene's own metrics (common ones are known)
  std::function<SceneResult(const SceneOptions&, Progress&)> run;
};

/// Every registered scene, sorted by name.
const std::vector<Scene>& scenes();
/// Their names, in the same order.
std::vector<std::string> scene_names();
/// The scene called name, or nullptr.
const Scene* find_scene(std::string_view name);

/// Registers a scene at static-initialisation time (one per scene file). Throws
/// std::logic_error on a duplicate or malformed name.
struct SceneRegistrar {
  explicit SceneRegistrar(Scene scene);
};

/// Command-line overrides; unset fields take the scene's defaults.
struct Overrides {
  std::filesystem::path out_root = "out";
  int threads = 0;       ///< 0: OpenMP's default
  double seconds = 0;    ///< 0: scene default (or its smoke_seconds with smoke)
  double substep = 0;    ///< 0: scene default
  std::string material;  ///< empty: scene default
  double cell = 0;       ///< 0: scene default
  bool smoke = false;
  bool write_files = true;
};

/// The scene's defaults with the overrides applied; out_dir = out_root / scene.name.
SceneOptions resolve(const Scene& scene, const Overrides& overrides);

/// Runs a scene: validates options, creates out_dir, sets the OpenMP thread count,
/// checks the common metrics are present, adds "files" and "precision", writes
/// out_dir/metrics.json (when write_files). Scene errors propagate.
SceneResult run_scene(const Scene& scene, const SceneOptions& options, ProgressMode progress);

/// The common metrics every scene reports: scene, material, threads, substeps,
/// sim_seconds, wall_seconds, realtime_factor, state_hash (16 hex digits), nan_count.
nlohmann::json common_metrics(const std::string& scene, const SceneOptions& options, int substeps, double wall_seconds,
                              std::uint64_t state_hash, long nan_count);

/// Names of the common metrics, in report order, with their meaning.
const std::vector<MetricHelp>& common_metric_help();

/// "float" or "double": the btScalar precision this build uses (hashes differ by it).
std::string precision_name();

/// Adds an outside-reference check to metrics["checks"]; the demos smoke test asserts
/// |value - reference| <= tolerance for each. source names where the reference comes from.
void add_check(nlohmann::json& metrics, const std::string& name, double value, double reference, double tolerance,
               const std::string& source);

}  // namespace shore::demo
