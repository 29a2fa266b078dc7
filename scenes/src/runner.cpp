#include "shore/scenes/runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include "shore/bullet/config.h"
#include "shore/core/error.h"
#include "shore/core/hash.h"
#include "shore/scenes/film.h"
#include "shore/scenes/mesh.h"
#include "shore/scenes/picture.h"
#include "shore/scenes/recording.h"
#include "shore/scenes/static_shares.h"

namespace shore::scenes {
namespace {

/// The common metrics every scene reports (common_metric_help lists their meaning).
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

void write_metrics(const std::filesystem::path& path, const nlohmann::json& metrics) {
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    out << metrics.dump(2) << '\n';
    if (!out) throw FileError("cannot write " + tmp.string());
  }
  std::filesystem::rename(tmp, path);
}

}  // namespace

void SceneOptions::validate() const {
  const Check c{"scenes.SceneOptions"};
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

Drawing::Drawing(const SceneOptions& options, Image filmstrip, Painter* painter, SceneContents contents)
    : options_(options), filmstrip_(std::move(filmstrip)), painter_(painter), contents_(std::move(contents)) {}

void Drawing::view(const std::string& name, const View& view) {
  if (painter_ == nullptr) {
    skipped_.push_back(name);
    return;
  }
  files_.push_back(write_png(options_.file(name), painter_->paint(contents_, view)));
}

void Drawing::png(const std::string& name, const Image& image) {
  if (image.width() == 0 || image.height() == 0) {
    skipped_.push_back(name);
    return;
  }
  files_.push_back(write_png(options_.file(name), image));
}

void Drawing::obj(const std::string& name, const HeightGrid& grid) {
  files_.push_back(write_obj(options_.file(name), grid));
}

void Drawing::filmstrip() { png("filmstrip.png", filmstrip_); }

SceneOptions resolve(const SceneType& scene, const Overrides& o) {
  SceneOptions s;
  s.out_dir = o.out_root / scene.name;
  s.threads = o.threads > 0 ? o.threads : hardware_threads();
  s.smoke = o.smoke;
  s.seconds = o.seconds > 0 ? o.seconds : (o.smoke ? scene.defaults.smoke_seconds : scene.defaults.seconds);
  s.substep = o.substep > 0 ? o.substep : scene.defaults.substep;
  s.material = o.material.empty() ? scene.defaults.material : o.material;
  s.cell = o.cell > 0 ? o.cell : scene.defaults.cell;
  s.write_files = o.write_files;
  return s;
}

SceneOptions pinning_options(const SceneType& scene) {
  Overrides o;
  o.smoke = true;
  o.threads = 1;
  o.write_files = false;
  return resolve(scene, o);
}

SceneResult run_scene(const SceneType& type, const SceneOptions& options, ProgressMode progress_mode, Painter* painter,
                      Recorder* recorder) {
  options.validate();
  if (options.write_files) std::filesystem::create_directories(options.out_dir);
  Progress progress(type.name, progress_mode);
  const std::unique_ptr<Scene> scene = type.create(options);
  if (recorder != nullptr) recorder->begin(type, options, *scene);

  // The loop: only the steps are timed; frames are taken between them.
  const int n = options.substeps();
  const std::vector<int> film_at =
      options.write_files && painter != nullptr ? scene->film_substeps() : std::vector<int>{};
  std::vector<Image> frames;
  std::vector<std::string> labels;
  auto film = [&](int k) {
    if (std::find(film_at.begin(), film_at.end(), k) == film_at.end()) return;
    frames.push_back(scene->film_frame(*painter));
    labels.push_back(time_label(k * options.substep));
  };
  film(0);
  double wall = 0.0;
  for (int k = 1; k <= n; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    scene->step();
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    scene->observe();
    if (recorder != nullptr) recorder->after_substep(*scene, k);
    film(k);
    progress.update(static_cast<double>(k) / n);
  }

  SceneResult result;
  const SceneState state = scene->state();
  result.state_hash = state_hash(state);
  result.metrics = common_metrics(type.name, options, n, wall, result.state_hash, non_finite_count(state));
  scene->measure(result.metrics);
  result.metrics["precision"] = precision_name();
  if (recorder != nullptr) {
    recorder->finish(result.state_hash);
    const Recorder::Sizes& z = recorder->sizes();
    result.metrics["recording_bytes"] = {{"file", z.file},
                                         {"initial", z.initial},
                                         {"terrain_deltas", z.terrain_deltas},
                                         {"bodies", z.bodies},
                                         {"multibodies", z.multibodies},
                                         {"water_states", z.water_states},
                                         {"water_compressed", z.water_compressed}};
  }
  nlohmann::json files = nlohmann::json::array();
  if (options.write_files) {
    Drawing drawing(options, frames.empty() ? Image() : scenes::filmstrip(frames, labels, 3), painter,
                    scene->contents());
    scene->draw(drawing);
    result.files = drawing.files();
    for (const auto& f : result.files) files.push_back(f.filename().string());
    files.push_back("metrics.json");
    result.metrics["files"] = files;
    result.metrics["pictures_skipped"] = drawing.skipped();
    write_metrics(options.file("metrics.json"), result.metrics);
    result.files.push_back(options.file("metrics.json"));
  } else {
    result.metrics["files"] = files;
  }
  return result;
}

const std::vector<MetricHelp>& common_metric_help() {
  static const std::vector<MetricHelp> help{
      {"scene", "scene name"},
      {"material", "soil material preset (sand, mud, snow)"},
      {"threads", "threads of the soil and the water"},
      {"substeps", "fixed substeps simulated"},
      {"substep_s", "substep length, s"},
      {"cell_m", "grid spacing, m"},
      {"smoke", "true for a shortened test run"},
      {"sim_seconds", "simulated time, s"},
      {"wall_seconds", "wall-clock time of the substeps (pictures and measurements excluded), s"},
      {"realtime_factor", "simulated seconds per wall second (> 1: faster than real time)"},
      {"state_hash", "FNV-1a hash of the final state (bodies and grids); equal across thread counts"},
      {"nan_count", "non-finite values found in the final state (must be 0)"},
      {"precision", "btScalar precision of this build (float or double)"},
      {"checks", "comparisons with outside references: value, reference, tolerance, source"},
      {"files", "files written by the scene"},
      {"pictures_skipped", "pictures not drawn for want of the OpenGL renderer (empty: all drawn)"},
      {"recording_bytes",
       "the recording written with --record (recording.h), bytes: the file; before its "
       "compression, the initial checkpoint, the soil deltas, the body states"},
  };
  return help;
}

std::string precision_name() { return bullet::built_with_double_precision() ? "double" : "float"; }

void add_check(nlohmann::json& metrics, const std::string& name, double value, double reference, double tolerance,
               const std::string& source) {
  metrics["checks"].push_back(
      {{"name", name}, {"value", value}, {"reference", reference}, {"tolerance", tolerance}, {"source", source}});
}

}  // namespace shore::scenes
