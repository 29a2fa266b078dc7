#pragma once
// A scene: a Bullet world with soil and/or water, set up to show or to measure one thing.
// Each is written once and run by shore-demo, the scene tests and shore-bench through
// run_scene (runner.h), which owns the loop, its timing, the state hash, the common
// metrics and the filmstrip. A scene is created, stepped, measured and drawn:
//
//   const SceneType& type = *find_scene("pond");
//   std::unique_ptr<Scene> scene = type.create(options);  // the world, set up
//   scene->step();                                        // one substep (a viewer: one per frame)
//   scene->observe();                                     // what it measures over time
//   SceneState state = scene->state();                    // bodies, soils, water: hashed
//
// Adding a scene: one file scenes/<name>.cpp with a class derived from Scene and a
// function returning its SceneType (scenes/rigid_drop.cpp is the smallest), listed in
// scenes/src/catalog.cpp and scenes/CMakeLists.txt. Then pin its state hash on purpose
// (tests/scenes/README.md).

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "shore/scenes/contents.h"
#include "shore/scenes/image.h"
#include "shore/scenes/picture.h"
#include "shore/scenes/state.h"

namespace shore::scenes {

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
  int threads = 1;                        ///< threads of the soil and the water, >= 1
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

/// Where a scene's draw() writes its pictures and meshes: options.file(name), each file
/// listed in the order written. Pictures are drawn by the painter (picture.h); without one
/// they are not written but listed in skipped().
class Drawing {
 public:
  /// painter: null for no pictures; contents: what it draws (the scene's, at the end of the run).
  Drawing(const SceneOptions& options, Image filmstrip, Painter* painter = nullptr, SceneContents contents = {});
  /// The picture the view asks for, painted now, as `name`.
  void view(const std::string& name, const View& view);
  /// A picture painted earlier (an empty one, from a run without a painter, is skipped).
  void png(const std::string& name, const Image& image);
  void obj(const std::string& name, const HeightGrid& grid);
  /// The filmstrip the runner took (film_substeps), as filmstrip.png.
  void filmstrip();
  [[nodiscard]] const std::vector<std::filesystem::path>& files() const noexcept { return files_; }
  /// The pictures not written for want of a painter.
  [[nodiscard]] const std::vector<std::string>& skipped() const noexcept { return skipped_; }

 private:
  const SceneOptions& options_;
  Image filmstrip_;
  Painter* painter_;
  SceneContents contents_;
  std::vector<std::filesystem::path> files_;
  std::vector<std::string> skipped_;
};

class Scene {
 public:
  virtual ~Scene() = default;
  /// One substep of options.substep: the scene's scripted input, then the world's step.
  /// The runner times this call alone.
  virtual void step() = 0;
  /// After each substep (untimed): what the scene measures over time.
  virtual void observe() {}
  /// What the state hash covers and what is scanned for non-finite values.
  [[nodiscard]] virtual SceneState state() const = 0;
  /// The scene's own metrics and outside-reference checks (add_check, runner.h) after the
  /// run; `metrics` already holds the common ones.
  virtual void measure(nlohmann::json& metrics) const = 0;
  /// Substeps after which the runner takes a filmstrip frame (0: before the first), in order.
  [[nodiscard]] virtual std::vector<int> film_substeps() const = 0;
  /// A filmstrip frame of the world as it is now, drawn by the painter.
  virtual Image film_frame(Painter& painter) = 0;
  /// The pictures and meshes of the end of the run.
  virtual void draw(Drawing& out) const = 0;
  /// What a viewer draws and drives live (contents.h); empty by default.
  virtual SceneContents contents() { return {}; }
};

/// One line of the report: what a metric means.
struct MetricHelp {
  std::string name;
  std::string meaning;
};

struct SceneType {
  std::string name;         ///< identifier: [a-z0-9_]+, the subcommand and the output folder
  std::string description;  ///< one paragraph: what it shows and what to look at
  SceneDefaults defaults;
  std::vector<MetricHelp> metric_help;  ///< the scene's own metrics (common ones are known)
  std::function<std::unique_ptr<Scene>(const SceneOptions&)> create;
};

/// SceneType::create of a scene class built from its options.
template <class S>
std::unique_ptr<Scene> make_scene(const SceneOptions& options) {
  return std::make_unique<S>(options);
}

/// Every scene, sorted by name.
const std::vector<SceneType>& scenes();
/// Their names, in the same order.
std::vector<std::string> scene_names();
/// The scene called name, or nullptr.
const SceneType* find_scene(std::string_view name);

}  // namespace shore::scenes
