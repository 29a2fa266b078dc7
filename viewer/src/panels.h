#pragma once
// The Dear ImGui panels of shore-viewer: scene and playback, camera, colours and overlays
// with the colour bar, live statistics, interaction (drop, material, screenshot, save).

#include <string>

#include "session.h"

namespace shore::viewer {

class Panels {
 public:
  /// Draws the panels for this frame (between ImGui::NewFrame and ImGui::Render).
  void draw(Session& session, int width, int height);

 private:
  void scene_panel(Session& s);
  void view_panel(Session& s);
  void stats_panel(Session& s);
  void tools_panel(Session& s);
  std::string message_;
  int material_ = 0;
  int substep_ = 0;  // index into the substep choices (0: the scene's default)
  float alpha_ = -1.0f;
  int shots_ = 0;
};

}  // namespace shore::viewer
