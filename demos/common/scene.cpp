#include "shore/demo/scene.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include "shore/bullet/config.h"
#include "shore/core/error.h"
#include "shore/core/hash.h"

namespace shore::demo {
namespace {

std::vector<Scene>& registry() {
  static std::vector<Scene> list;  // function-local: safe whatever the static-init order
  return list;
}

bool valid_name(const std::string& name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
  });
}

const char* const kRequired[] = {"scene",        "material",        "threads",    "substeps", "sim_seconds",
                                 "wall_seconds", "realtime_factor", "state_hash", "nan_count"};

}  // namespace

void SceneOptions::validate() const {
  const Check c{"demo.SceneOptions"};
  c.at_least("threads", threads, 1);
  c.in_left_open("seconds", seconds, 0.0, 3600.0);
  c.in_left_open("substep", substep, 0.0, 0.1);
  c.in_left_open("cell", cell, 0.0, 1.0);
  if (material != "sand" && material != "mud" && material != "snow")
    throw InvalidSetting(c.name("material"), material, "must be one of sand, mud, snow");
  if (seconds / substep > 1e8)
    throw InvalidSetting(c.name("seconds"), detail::to_text(seconds), "more than 1e8 substeps");
}

int SceneOptions::substeps() const { return std::max(1, static_cast<int>(std::lround(seconds / substep))); }

const std::vector<Scene>& scenes() { return registry(); }

std::vector<std::string> scene_names() {
  std::vector<std::string> names;
  for (const Scene& s : registry()) names.push_back(s.name);
  return names;
}

const Scene* find_scene(std::string_view name) {
  for (const Scene& s : registry())
    if (s.name == name) return &s;
  return nullptr;
}

SceneRegistrar::SceneRegistrar(Scene scene) {
  if (!valid_name(scene.name)) throw std::logic_error("demo scene name '" + scene.name + "' is not [a-z0-9_]+");
  if (scene.name == "all" || scene.name == "pin" || scene.name == "list")
    throw std::logic_error("demo scene name '" + scene.name + "' is reserved");
  if (find_scene(scene.name)) throw std::logic_error("demo scene '" + scene.name + "' registered twice");
  if (!scene.run) throw std::logic_error("demo scene '" + scene.name + "' has no run function");
  auto& list = registry();
  list.push_back(std::move(scene));
  std::sort(list.begin(), list.end(), [](const Scene& a, const Scene& b) { return a.name < b.name; });
}

SceneOptions resolve(const Scene& scene, const Overrides& o) {
  SceneOptions s;
  s.out_dir = o.out_root / scene.name;
  s.threads = o.threads > 0 ? o.threads : std::max(1, omp_get_max_threads());
  s.smoke = o.smoke;
  s.seconds = o.seconds > 0 ? o.seconds : (o.smoke ? scene.defaults.smoke_seconds : scene.defaults.seconds);
  s.substep = o.substep > 0 ? o.substep : scene.defaults.substep;
  s.material = o.material.empty() ? scene.defaults.material : o.material;
  s.cell = o.cell > 0 ? o.cell : scene.defaults.cell;
  s.write_files = o.write_files;
  return s;
}

nlohmann::json common_metrics(const std::string& scene, const SceneOptions& options, int substeps, double wall_seconds,
                              std::uint64_t state_hash, long nan_count) {
  const double sim = substeps * options.substep;
  return {{"scene", scene},
          {"material", options.material},
          {"threads", options.threads},
          {"substeps", substeps},
          {"substep_s", options.substep},
          {"cell_m", options.cell},
          {"smoke", options.smoke},
          {"sim_seconds", sim},
          {"wall_seconds", wall_seconds},
          {"realtime_factor", wall_seconds > 0.0 ? sim / wall_seconds : 0.0},
          {"state_hash", to_hex(state_hash)},
          {"nan_count", nan_count}};
}

const std::vector<MetricHelp>& common_metric_help() {
  static const std::vector<MetricHelp> help{
      {"scene", "scene name"},
      {"material", "soil material preset (sand, mud, snow)"},
      {"threads", "OpenMP threads used"},
      {"substeps", "fixed substeps simulated"},
      {"substep_s", "substep length, s"},
      {"cell_m", "grid spacing, m"},
      {"smoke", "true for a shortened test run"},
      {"sim_seconds", "simulated time, s"},
      {"wall_seconds", "wall-clock time of the simulation loop (pictures excluded), s"},
      {"realtime_factor", "simulated seconds per wall second (> 1: faster than real time)"},
      {"state_hash", "FNV-1a hash of the final state (bodies and grids); equal across thread counts"},
      {"nan_count", "non-finite values found in the final state (must be 0)"},
      {"precision", "btScalar precision of this build (float or double)"},
      {"checks", "comparisons with outside references: value, reference, tolerance, source"},
      {"files", "files written by the scene"},
  };
  return help;
}

std::string precision_name() { return bullet::built_with_double_precision() ? "double" : "float"; }

void add_check(nlohmann::json& metrics, const std::string& name, double value, double reference, double tolerance,
               const std::string& source) {
  metrics["checks"].push_back(
      {{"name", name}, {"value", value}, {"reference", reference}, {"tolerance", tolerance}, {"source", source}});
}

SceneResult run_scene(const Scene& scene, const SceneOptions& options, ProgressMode progress_mode) {
  options.validate();
  if (options.write_files) std::filesystem::create_directories(options.out_dir);
  omp_set_num_threads(options.threads);
  SceneResult result;
  {
    Progress progress(scene.name, progress_mode);
    result = scene.run(options, progress);
  }
  for (const char* key : kRequired)
    if (!result.metrics.contains(key))
      throw std::logic_error("demo scene '" + scene.name + "' did not report the common metric '" + key + "'");
  result.metrics["precision"] = precision_name();
  nlohmann::json files = nlohmann::json::array();
  for (const auto& f : result.files) files.push_back(f.filename().string());
  if (options.write_files) {
    files.push_back("metrics.json");
    result.metrics["files"] = files;
    const std::filesystem::path path = options.file("metrics.json");
    std::filesystem::path tmp = path;
    tmp += ".tmp";
    {
      std::ofstream out(tmp, std::ios::trunc);
      out << result.metrics.dump(2) << '\n';
      if (!out) throw FileError("cannot write " + tmp.string());
    }
    std::filesystem::rename(tmp, path);
    result.files.push_back(path);
  } else {
    result.metrics["files"] = files;
  }
  return result;
}

}  // namespace shore::demo
