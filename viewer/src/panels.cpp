#include "panels.h"

#include <cstdio>
#include <exception>
#include <vector>

#include <imgui.h>

#include "shore/scenes/image.h"
#include "shore/scenes/picture.h"

namespace shore::viewer {
namespace {

/// The colour bar of the current ground or water colouring, with its range.
void colour_bar(const Session& s) {
  const render::FrameStats& st = s.renderer().stats();
  const bool ground = s.settings.ground != render::GroundColour::natural && !s.contents().soils.empty();
  const bool water = s.settings.water != render::WaterColour::natural && !s.contents().waters.empty();
  if (!ground && !water) return;
  const bool height_map = ground && s.settings.ground == render::GroundColour::height;
  const bool water_map = !ground && s.settings.water == render::WaterColour::height;
  ImDrawList* d = ImGui::GetWindowDrawList();
  const ImVec2 p = ImGui::GetCursorScreenPos();
  const float w = ImGui::GetContentRegionAvail().x, h = 12.0f;
  for (int k = 0; k < 64; ++k) {
    const double t = k / 63.0;
    const scenes::Rgb c = height_map  ? scenes::height_colour(t)
                          : water_map ? scenes::water_colour(2 * t - 1)
                                      : scenes::diverging_colour(2 * t - 1);
    d->AddRectFilled({p.x + w * k / 64, p.y}, {p.x + w * (k + 1) / 64 + 1, p.y + h}, IM_COL32(c.r, c.g, c.b, 255));
  }
  ImGui::Dummy({w, h});
  const double scale = ground ? st.ground_scale : st.water_scale;
  if (ground && s.settings.ground == render::GroundColour::deformation) {
    const scenes::Legend l = scenes::deformation_legend(scale);
    ImGui::Text("%s  |  %s", l.low.c_str(), l.high.c_str());
  } else if (ground && s.settings.ground == render::GroundColour::sinkage) {
    ImGui::Text("pressed %s  |  loose", scenes::format_length(scale, false).c_str());
  } else if (water && s.settings.water == render::WaterColour::velocity) {
    ImGui::Text("down %.3g m/s  |  up %.3g m/s", scale, scale);
  } else if (!height_map) {
    ImGui::Text("trough %s  |  crest %s", scenes::format_length(-scale, true).c_str(),
                scenes::format_length(scale, true).c_str());
  } else {
    ImGui::Text("low  |  high");
  }
}

}  // namespace

void Panels::draw(Session& s, int, int) {
  ImGui::SetNextWindowPos({8, 8}, ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize({330, 0}, ImGuiCond_FirstUseEver);
  ImGui::Begin("Shore");
  if (ImGui::CollapsingHeader("Scene", ImGuiTreeNodeFlags_DefaultOpen)) scene_panel(s);
  if (ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) view_panel(s);
  if (ImGui::CollapsingHeader("Statistics", ImGuiTreeNodeFlags_DefaultOpen)) stats_panel(s);
  if (ImGui::CollapsingHeader("Tools", ImGuiTreeNodeFlags_DefaultOpen)) tools_panel(s);
  if (!message_.empty()) ImGui::TextWrapped("%s", message_.c_str());
  ImGui::End();
}

void Panels::scene_panel(Session& s) {
  const std::vector<std::string> names = scenes::scene_names();
  if (ImGui::BeginCombo("scene", s.scene_name().c_str())) {
    for (const std::string& n : names)
      if (ImGui::Selectable(n.c_str(), n == s.scene_name())) {
        s.open(n);
        alpha_ = -1.0f;
        substep_ = 0;
      }
    ImGui::EndCombo();
  }
  if (ImGui::Button(s.playing ? "pause" : "play")) s.playing = !s.playing;
  ImGui::SameLine();
  if (ImGui::Button("step")) s.single_step();
  ImGui::SameLine();
  if (ImGui::Button("restart")) s.open(s.scene_name(), s.options().substep);
  float scale = float(s.time_scale);
  if (ImGui::SliderFloat("time scale", &scale, 0.05f, 4.0f, "%.2f", ImGuiSliderFlags_Logarithmic)) s.time_scale = scale;
  // The substep: the scene restarts with it (the physics of a run depends on it).
  const double substeps[] = {0.0, 1.0 / 120, 1.0 / 240, 1.0 / 480, 1.0 / 960};
  const char* substep_names[] = {"scene default", "1/120 s", "1/240 s", "1/480 s", "1/960 s"};
  if (ImGui::Combo("substep", &substep_, substep_names, 5)) s.open(s.scene_name(), substeps[substep_]);
  ImGui::Text("substep %.3g ms (%d per frame), t = %.2f s", 1e3 * s.options().substep,
              std::max(1, int(s.frame_seconds * s.time_scale / s.options().substep + 0.5)), s.sim_time());
  if (s.contents().drive) ImGui::TextUnformatted("arrow keys drive the vehicle");
}

void Panels::view_panel(Session& s) {
  const char* grounds[] = {"natural", "deformation", "sinkage", "height"};
  int g = static_cast<int>(s.settings.ground);
  if (ImGui::Combo("ground", &g, grounds, 4)) s.settings.ground = static_cast<render::GroundColour>(g);
  const char* waters[] = {"natural", "height", "velocity"};
  int w = static_cast<int>(s.settings.water);
  if (ImGui::Combo("water", &w, waters, 3)) s.settings.water = static_cast<render::WaterColour>(w);
  colour_bar(s);
  ImGui::Checkbox("contact columns", &s.overlays.contacts);
  ImGui::Checkbox("soil reaction", &s.overlays.reactions);
  ImGui::Checkbox("buoyancy", &s.overlays.buoyancy);
  ImGui::Checkbox("Bullet tiles", &s.overlays.tiles);
  ImGui::SameLine();
  ImGui::Checkbox("soil tiles", &s.overlays.soil_tiles);
  ImGui::Checkbox("shadows", &s.settings.shadows);
  ImGui::SameLine();
  ImGui::Checkbox("follow", &s.follow);
  ImGui::Checkbox("spray", &s.overlays.spray);
  ImGui::SameLine();
  ImGui::Checkbox("mesh edges", &s.overlays.mesh_edges);
}

void Panels::stats_panel(Session& s) {
  const PartTimes& t = s.times();
  ImGui::Text("substep %.3f ms", t.total);
  ImGui::Text("  envelopes %.3f  soil reaction %.3f", t.envelopes, t.reaction);
  ImGui::Text("  terrain step %.3f  push-back %.3f", t.terrain, t.push);
  ImGui::Text("  water coupling %.3f  water %.3f", t.water_coupling, t.water);
  ImGui::Text("  Bullet and scene %.3f", t.bullet);
  const render::FrameStats& r = s.renderer().stats();
  ImGui::Text("active columns %ld, tiles %ld, soil memory %.1f MB", s.active_columns(), s.tiles(),
              double(s.soil_memory_bytes()) / 1e6);
  ImGui::Text("draw %.1f ms, %lld triangles, %lld lines", s.last_draw_ms(), static_cast<long long>(r.triangles),
              static_cast<long long>(r.lines));
  ImGui::Text("surfaces %lld of %lld triangles (full), chunks %d drawn, %d culled",
              static_cast<long long>(r.surface_triangles), static_cast<long long>(r.full_triangles), r.chunks_drawn,
              r.chunks_culled);
  ImGui::Text("uploaded soil %lld B of %lld B (whole), water %lld B of %lld B", static_cast<long long>(r.soil_bytes),
              static_cast<long long>(r.whole_soil_bytes), static_cast<long long>(r.water_bytes),
              static_cast<long long>(r.whole_water_bytes));
  ImGui::Text("%.0f fps", ImGui::GetIO().Framerate);
}

void Panels::tools_panel(Session& s) {
  const char* shapes[] = {"sphere", "box", "cylinder", "capsule"};
  int k = 0;
  for (int i = 0; i < 4; ++i)
    if (s.drop_shape == shapes[i]) k = i;
  if (ImGui::Combo("drop shape", &k, shapes, 4)) s.drop_shape = shapes[k];
  float size = float(s.drop_size), density = float(s.drop_density);
  if (ImGui::SliderFloat("size, m", &size, 0.03f, 0.5f)) s.drop_size = size;
  if (ImGui::SliderFloat("density", &density, 100.0f, 8000.0f, "%.0f kg/m3")) s.drop_density = density;
  ImGui::TextUnformatted("ctrl + click drops it where the pointer is");
  if (!s.contents().soils.empty()) {
    const terrain::Material& now = s.contents().soils.front().soil->settings().material;
    if (alpha_ < 0.0f) alpha_ = float(now.alpha);
    const char* materials[] = {"sand", "mud", "snow"};
    bool changed = ImGui::Combo("material", &material_, materials, 3);
    changed |= ImGui::SliderFloat("alpha (to the rim)", &alpha_, 0.0f, 1.0f);
    if (changed) {
      try {
        terrain::Material m = terrain::Material::preset(materials[material_]);
        m.alpha = alpha_;
        s.set_material(m);
        message_ = "material " + m.name + ", alpha " + std::to_string(m.alpha);
      } catch (const std::exception& e) {
        message_ = e.what();
      }
    }
  }
  if (ImGui::Button("screenshot")) {
    const std::string f = "shore-viewer-" + std::to_string(++shots_) + ".png";
    s.screenshot(f);
    message_ = "wrote " + f;
  }
  ImGui::SameLine();
  if (ImGui::Button("save terrain")) {
    try {
      const auto files = s.save_soils("shore-viewer-soil");
      message_ = files.empty() ? "no soil in this scene"
                               : "wrote " + files.front().string() + (files.size() > 1 ? " ..." : "");
    } catch (const std::exception& e) {
      message_ = e.what();
    }
  }
}

}  // namespace shore::viewer
