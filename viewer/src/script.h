#pragma once
// Scripted input for shore-viewer (--script FILE): one action per line, taken at the start
// of the given frame (frames count from 0); '#' starts a comment.
//
//   <frame> key <up|down|left|right> <press|release>   drive keys (the vehicle)
//   <frame> drop <sphere|box|cylinder|capsule> <x> <y>  drop a body 1 m above the surface at world (x, y)
//   <frame> click <sphere|box|cylinder|capsule> <px> <py>  drop one where the pointer at pixel (px, py) points
//   <frame> pause | play | step                          playback
//   <frame> ground <natural|deformation|sinkage|height>  ground colour
//   <frame> water <natural|height|velocity>              water colour
//   <frame> overlay <contacts|reactions|buoyancy|tiles|soil_tiles> <on|off>

#include <filesystem>
#include <string>
#include <vector>

namespace shore::viewer {

struct ScriptAction {
  int frame = 0;
  std::string verb;               ///< key, drop, click, pause, play, step, ground, water, overlay
  std::vector<std::string> args;  ///< the words after the verb
  int line = 0;                   ///< in the file, for messages
};

/// Reads and checks a script; throws shore::FileError if it cannot be read and
/// shore::InvalidSetting naming the line for a malformed one. Sorted by frame (stable).
std::vector<ScriptAction> read_script(const std::filesystem::path& file);

}  // namespace shore::viewer
