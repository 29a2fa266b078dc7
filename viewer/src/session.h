#pragma once
// What shore-viewer shows and does, independent of the window: the open scene, playback
// (play, pause, single step, time scale), the camera, the overlays and colours, driving,
// dropping bodies, statistics, screenshots and saving the soil. The window (window.cpp)
// and the headless run (--headless) both drive one Session.

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "script.h"
#include "shore/render/camera.h"
#include "shore/render/line_batch.h"
#include "shore/render/renderer.h"
#include "shore/scenes/scene.h"

namespace shore::viewer {

/// What is drawn on top of the scene (debug drawing of the couplings).
struct Overlays {
  bool contacts = false;    ///< contact columns
  bool reactions = false;   ///< soil reaction vectors
  bool buoyancy = false;    ///< buoyancy centres and forces
  bool tiles = false;       ///< Bullet tiles' outlines
  bool soil_tiles = false;  ///< soil storage tiles' borders (in the ground shader)
  bool spray = true;        ///< the soils' spray particles in flight (dark crosses)
  bool mesh_edges = false;  ///< the soil and water meshes' triangles (their level of detail)
};

/// Milliseconds of the last substep by part.
struct PartTimes {
  double envelopes = 0, reaction = 0, terrain = 0, push = 0, water_coupling = 0, water = 0, bullet = 0, total = 0;
};

class Session {
 public:
  /// Opens the scene with its defaults (smoke: the scene's smoke settings).
  Session(const std::string& scene, bool smoke);
  ~Session();

  /// Opens a scene afresh; substep (s, > 0) overrides the scene's (0: its default).
  void open(const std::string& scene, double substep = 0.0);
  [[nodiscard]] const std::string& scene_name() const noexcept { return name_; }
  [[nodiscard]] scenes::Scene& scene() { return *scene_; }
  [[nodiscard]] const scenes::SceneContents& contents() const noexcept { return contents_; }
  [[nodiscard]] const scenes::SceneOptions& options() const noexcept { return options_; }

  /// Needs a current GL context: makes the renderer for the open scene.
  void attach_renderer();
  [[nodiscard]] render::Renderer& renderer() { return *renderer_; }
  [[nodiscard]] const render::Renderer& renderer() const { return *renderer_; }

  // ---- a frame ----
  /// Takes the script's actions for this frame, then advances the simulation by one frame
  /// (frame_seconds x time_scale, in whole substeps) unless paused.
  void advance();
  /// Draws the frame (width x height) with the overlays.
  void draw(int width, int height);
  [[nodiscard]] int frame() const noexcept { return frame_; }

  // ---- controls ----
  bool playing = true;
  double time_scale = 1.0;            ///< simulated seconds per frame / frame_seconds
  double frame_seconds = 1.0 / 60.0;  ///< simulated time of one frame at time scale 1
  void single_step();                 ///< one substep now (paused or not)
  render::OrbitCamera camera;
  render::RenderSettings settings;
  Overlays overlays;
  bool follow = true;  ///< the camera follows the scene's focus body
  /// Drive keys held: forward (+1 up, -1 down) and turn (+1 left, -1 right).
  double forward = 0.0, turn = 0.0;
  std::string drop_shape = "sphere";
  double drop_size = 0.15;      ///< m: radius (sphere, cylinder, capsule) or half side (box)
  double drop_density = 800.0;  ///< kg/m^3

  void set_script(std::vector<ScriptAction> script) { script_ = std::move(script); }
  /// Drops a body of drop_shape 1 m above the surface at world (x, y).
  void drop(const std::string& shape, double x, double y);
  /// Drops one where the pointer at pixel (px, py) of a width x height view points; false if it points at nothing.
  bool click(const std::string& shape, double px, double py, int width, int height);
  /// Sets material alpha (and the other fields) of every soil; throws InvalidSetting.
  void set_material(const terrain::Material& material);
  /// The 3-D view as a PNG (without the panels).
  void screenshot(const std::filesystem::path& file) const;
  /// Every soil's state (Terrain::save) as <stem>_<k>.shore; returns the files.
  std::vector<std::filesystem::path> save_soils(const std::filesystem::path& stem) const;

  // ---- statistics ----
  [[nodiscard]] const PartTimes& times() const noexcept { return times_; }
  [[nodiscard]] long active_columns() const;
  [[nodiscard]] long tiles() const;
  [[nodiscard]] std::size_t soil_memory_bytes() const;
  [[nodiscard]] double sim_time() const noexcept { return substeps_ * options_.substep; }
  [[nodiscard]] double last_draw_ms() const noexcept { return draw_ms_; }
  /// Screen position (pixels, y down) of a world point in a width x height view, or (-1, -1) behind the eye.
  [[nodiscard]] Eigen::Vector2d project(const Eigen::Vector3d& p, int width, int height) const;

 private:
  /// The focus body's centre in the ground's coordinates (contents_.focus must be set).
  [[nodiscard]] Eigen::Vector3d focus_point() const;
  void apply(const ScriptAction& a);
  void substep();
  void collect_lines();
  void frame_camera();

  std::string name_;
  bool smoke_ = false;
  scenes::SceneOptions options_;
  std::unique_ptr<scenes::Scene> scene_;
  scenes::SceneContents contents_;
  std::unique_ptr<render::Renderer> renderer_;
  render::LineBatch lines_;
  std::vector<ScriptAction> script_;
  std::size_t next_action_ = 0;
  int frame_ = 0;
  long substeps_ = 0;
  PartTimes times_;
  double draw_ms_ = 0;
  Eigen::Vector3d focus_offset_{0, 0, 0};  // camera target minus the focus body, kept while following
};

}  // namespace shore::viewer
