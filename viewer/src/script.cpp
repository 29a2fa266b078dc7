#include "script.h"

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>

#include "shore/core/error.h"

namespace shore::viewer {
namespace {

/// Words each verb takes.
const std::map<std::string, std::size_t>& arity() {
  static const std::map<std::string, std::size_t> a{{"key", 2},    {"drop", 3},  {"click", 3},
                                                    {"pause", 0},  {"play", 0},  {"step", 0},
                                                    {"ground", 1}, {"water", 1}, {"overlay", 2}};
  return a;
}

}  // namespace

std::vector<ScriptAction> read_script(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw FileError("viewer.script: cannot open " + file.string());
  std::vector<ScriptAction> out;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    text = text.substr(0, text.find('#'));
    std::istringstream words(text);
    ScriptAction a;
    a.line = line;
    if (!(words >> a.frame)) {
      if (text.find_first_not_of(" \t\r") == std::string::npos) continue;
      throw InvalidSetting("viewer.script line " + std::to_string(line), text, "<frame> <verb> [arguments]");
    }
    words >> a.verb;
    for (std::string w; words >> w;) a.args.push_back(w);
    const auto it = arity().find(a.verb);
    if (a.frame < 0 || it == arity().end() || it->second != a.args.size())
      throw InvalidSetting("viewer.script line " + std::to_string(line), text,
                           "frame >= 0 and one of: key K press|release, drop SHAPE X Y, click SHAPE PX PY, pause, "
                           "play, step, ground MODE, water MODE, overlay NAME on|off");
    out.push_back(a);
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const ScriptAction& a, const ScriptAction& b) { return a.frame < b.frame; });
  return out;
}

}  // namespace shore::viewer
