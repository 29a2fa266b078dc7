// The scenes, one file each in scenes/ (adding one: see scene.h).
#include <algorithm>

#include "shore/scenes/scene.h"

namespace shore::scenes {

SceneType beach_scene();
SceneType footprints_scene();
SceneType impact_scene();
SceneType impact_y_up_scene();
SceneType pond_scene();
SceneType rally_scene();
SceneType rover_scene();
SceneType rigid_drop_scene();
SceneType tracks_scene();
SceneType vehicle_scene();
SceneType walker_scene();

const std::vector<SceneType>& scenes() {
  static const std::vector<SceneType> list = [] {
    std::vector<SceneType> all = {beach_scene(),  footprints_scene(), impact_scene(), impact_y_up_scene(),
                                  pond_scene(),   rally_scene(),      rover_scene(),  rigid_drop_scene(),
                                  tracks_scene(), vehicle_scene(),    walker_scene()};
    std::sort(all.begin(), all.end(), [](const SceneType& a, const SceneType& b) { return a.name < b.name; });
    return all;
  }();
  return list;
}

std::vector<std::string> scene_names() {
  std::vector<std::string> names;
  for (const SceneType& s : scenes()) names.push_back(s.name);
  return names;
}

const SceneType* find_scene(std::string_view name) {
  for (const SceneType& s : scenes())
    if (s.name == name) return &s;
  return nullptr;
}

}  // namespace shore::scenes
