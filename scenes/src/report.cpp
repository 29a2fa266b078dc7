#include "shore/scenes/report.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "shore/core/error.h"
#include "shore/scenes/runner.h"

namespace shore::scenes {
namespace {

std::string explain(const SceneType* scene, const std::string& key) {
  if (scene)
    for (const MetricHelp& h : scene->metric_help)
      if (h.name == key) return h.meaning;
  for (const MetricHelp& h : common_metric_help())
    if (h.name == key) return h.meaning;
  return "";
}

std::string show(const nlohmann::json& v) {
  if (v.is_number_float()) {
    std::ostringstream s;
    s.precision(6);
    s << v.get<double>();
    return s.str();
  }
  if (v.is_string()) return v.get<std::string>();
  return v.dump();
}

bool is_picture(const std::string& name) { return name.size() > 4 && name.substr(name.size() - 4) == ".png"; }

void write_scene(std::ostream& md, const std::filesystem::path& dir, const nlohmann::json& m) {
  const std::string name = m.value("scene", dir.filename().string());
  const SceneType* scene = find_scene(name);
  md << "## " << name << "\n\n";
  if (scene) md << scene->description << "\n\n";
  const nlohmann::json files = m.value("files", nlohmann::json::array());
  for (const auto& f : files)
    if (is_picture(f.get<std::string>()))
      md << "![" << name << " " << f.get<std::string>() << "](" << name << "/" << f.get<std::string>() << ")\n\n";
  const nlohmann::json skipped = m.value("pictures_skipped", nlohmann::json::array());
  if (!skipped.empty()) {
    md << "**Pictures not drawn** (no OpenGL renderer: built without it or run with `--no-pictures`):";
    for (const auto& f : skipped) md << " " << f.get<std::string>();
    md << "\n\n";
  }
  md << "Files:";
  for (const auto& f : files) md << " [" << f.get<std::string>() << "](" << name << "/" << f.get<std::string>() << ")";
  md << "\n\n| metric | value | meaning |\n|---|---|---|\n";
  // Common metrics first, in their usual order, then the scene's own.
  auto row = [&](const std::string& key) {
    md << "| " << key << " | " << show(m[key]) << " | " << explain(scene, key) << " |\n";
  };
  for (const MetricHelp& h : common_metric_help())
    if (m.contains(h.name) && h.name != "files" && h.name != "checks" && h.name != "pictures_skipped") row(h.name);
  for (const auto& item : m.items()) {
    const std::string& key = item.key();
    const auto& common = common_metric_help();
    const bool is_common =
        std::any_of(common.begin(), common.end(), [&](const MetricHelp& h) { return h.name == key; });
    if (!is_common) row(key);
  }
  if (m.contains("checks") && !m["checks"].empty()) {
    md << "\n| check | value | reference | tolerance | pass | reference from |\n|---|---|---|---|---|---|\n";
    for (const auto& c : m["checks"]) {
      const double v = c.value("value", NAN), r = c.value("reference", NAN), t = c.value("tolerance", NAN);
      const bool pass = std::abs(v - r) <= t;
      md << "| " << c.value("name", "") << " | " << show(c["value"]) << " | " << show(c["reference"]) << " | "
         << show(c["tolerance"]) << " | " << (pass ? "yes" : "**NO**") << " | " << c.value("source", "") << " |\n";
    }
  }
  md << "\n";
}

}  // namespace

std::filesystem::path write_report(const std::filesystem::path& out_root) {
  std::vector<std::filesystem::path> dirs;
  if (std::filesystem::is_directory(out_root))
    for (const auto& entry : std::filesystem::directory_iterator(out_root))
      if (entry.is_directory() && std::filesystem::exists(entry.path() / "metrics.json")) dirs.push_back(entry.path());
  std::sort(dirs.begin(), dirs.end());

  const std::filesystem::path path = out_root / "report.md";
  std::ofstream md(path, std::ios::trunc);
  if (!md) throw FileError("cannot write " + path.string());
  md << "# Shore demo report\n\n"
     << "Every scene found under this folder, with its pictures and metrics. Regenerate with "
        "`./shore demo` (all scenes) or `build/release/demos/shore-demo <scene>`.\n\n";
  for (const auto& dir : dirs) {
    std::ifstream in(dir / "metrics.json");
    nlohmann::json m;
    try {
      in >> m;
    } catch (const nlohmann::json::exception& e) {
      md << "## " << dir.filename().string() << "\n\nmetrics.json unreadable: " << e.what() << "\n\n";
      continue;
    }
    write_scene(md, dir, m);
  }
  if (!md) throw FileError("error while writing " + path.string());
  return path;
}

}  // namespace shore::scenes
