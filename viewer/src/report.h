#pragma once
// The JSON report of a shore-viewer run (--report): frame and render times, bytes
// uploaded per frame against a whole-field upload, and where the bodies are on screen
// (for pixel checks of the screenshot).

#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "session.h"

namespace shore::viewer {

class RunReport {
 public:
  /// Records one frame: its wall time (ms), draw time and what the renderer uploaded.
  void frame(const Session& s, double frame_ms);
  /// Writes the report with the final state of the session (body pixels in a width x height view).
  void write(const std::filesystem::path& file, const Session& s, int width, int height) const;

 private:
  std::vector<double> frame_ms_, draw_ms_;
  std::vector<double> soil_bytes_;
  double whole_soil_bytes_ = 0;
  std::vector<double> surface_triangles_;
  double full_triangles_ = 0;
};

}  // namespace shore::viewer
