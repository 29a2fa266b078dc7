#pragma once
// Runs a scene: the loop over its substeps, their timing, the filmstrip, the state hash,
// the common metrics and metrics.json. shore-demo, the scene tests and shore-bench all
// run scenes through here.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "shore/scenes/progress.h"
#include "shore/scenes/scene.h"

namespace shore::scenes {

class Recorder;

/// Command-line overrides; unset fields take the scene's defaults.
struct Overrides {
  std::filesystem::path out_root = "out";
  int threads = 0;       ///< 0: the machine's hardware threads
  double seconds = 0;    ///< 0: scene default (or its smoke_seconds with smoke)
  double substep = 0;    ///< 0: scene default
  std::string material;  ///< empty: scene default
  double cell = 0;       ///< 0: scene default
  bool smoke = false;
  bool write_files = true;
};

/// The scene's defaults with the overrides applied; out_dir = out_root / scene.name.
SceneOptions resolve(const SceneType& scene, const Overrides& overrides);

/// The smoke run on one thread without files: what the pinned hashes, the checkpoint and
/// recording tests run.
SceneOptions pinning_options(const SceneType& scene);

/// What a run produced: the common metrics (common_metric_help) plus the scene's own, the
/// files written (metrics.json last) and the state hash of the end of the run.
struct SceneResult {
  nlohmann::json metrics = nlohmann::json::object();
  std::vector<std::filesystem::path> files;
  std::uint64_t state_hash = 0;
};

/// Runs a scene: validates options, creates out_dir, creates
/// the scene and steps it options.substeps() times (timing the steps alone), takes the
/// filmstrip, hashes the final state, fills the metrics, and with write_files draws the
/// scene and writes out_dir/metrics.json. Scene errors propagate. The pictures (the
/// filmstrip too) are the painter's (shore-demo's: the OpenGL renderer); without one none
/// are written and metrics["pictures_skipped"] lists them.
/// With a recorder (recording.h), the run is recorded to its file and
/// metrics["recording_bytes"] holds its size.
SceneResult run_scene(const SceneType& scene, const SceneOptions& options, ProgressMode progress,
                      Painter* painter = nullptr, Recorder* recorder = nullptr);

/// Names of the common metrics, in report order, with their meaning.
const std::vector<MetricHelp>& common_metric_help();

/// "float" or "double": the btScalar precision this build uses (hashes differ by it).
std::string precision_name();

/// Adds an outside-reference check to metrics["checks"]; the scene tests assert
/// |value - reference| <= tolerance for each. source names where the reference comes from.
void add_check(nlohmann::json& metrics, const std::string& name, double value, double reference, double tolerance,
               const std::string& source);

}  // namespace shore::scenes
