#pragma once
// The two ways shore-viewer runs: in a GLFW window with the Dear ImGui panels, or headless
// (EGL, no display) for scripted frames and benchmarks.

#include <filesystem>
#include <memory>
#include <string>

namespace shore::viewer {

struct RunOptions {
  std::string scene = "vehicle";
  int frames = 0;                     ///< 0: until the window closes (headless: 1)
  std::filesystem::path script;       ///< scripted input (empty: none)
  std::filesystem::path screenshot;   ///< the last frame's 3-D view as PNG (empty: none)
  std::filesystem::path window_shot;  ///< the last frame's whole window, panels included (window only)
  std::filesystem::path report;       ///< JSON: frame times, bytes uploaded, where the bodies are on screen
  int width = 1280, height = 720;     ///< pixels of the 3-D view
  bool smoke = false;                 ///< the scene's smoke settings (small grids)
  bool headless = false;              ///< EGL instead of a window
  bool shadows = true;
  int samples = 4;
};

class Session;
class RunReport;

/// The session both runs start: the scene, the renderer (a GL context must be current),
/// shadows, samples and the script.
std::unique_ptr<Session> start_session(const RunOptions& options);
/// What both runs write at the end: the screenshot and the report (a width x height view).
void finish_run(const Session& session, const RunReport& report, const RunOptions& options, int width, int height);

/// Each returns the process exit code.
int run_window(const RunOptions& options);
int run_headless(const RunOptions& options);

}  // namespace shore::viewer
