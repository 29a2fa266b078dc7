#pragma once
// Progress of a long run on stderr. Nothing is printed for runs shorter than about a
// second; after that a redrawn bar when stderr is a terminal (or when forced), plain
// periodic lines otherwise (logs, CI).

#include <chrono>
#include <string>

namespace shore::scenes {

enum class ProgressMode {
  automatic,  ///< bar on a terminal, lines otherwise
  bar,        ///< always the redrawn bar
  lines,      ///< always plain periodic lines
  quiet,      ///< nothing
};

/// Parses "auto", "bar", "lines", "quiet"; throws shore::InvalidSetting otherwise.
ProgressMode parse_progress_mode(const std::string& text);

class Progress {
 public:
  explicit Progress(std::string label, ProgressMode mode = ProgressMode::automatic);
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  ~Progress();

  /// fraction of the work done, in [0, 1]; cheap enough to call every substep.
  void update(double fraction);
  /// Ends the bar's line (if one was drawn). Called by the destructor too.
  void finish();

 private:
  using Clock = std::chrono::steady_clock;
  void draw_bar(double fraction, double elapsed);
  void print_line(double fraction, double elapsed);

  std::string label_;
  ProgressMode mode_;
  Clock::time_point start_;
  Clock::time_point last_print_;
  double last_fraction_ = 0.0;
  bool drawn_ = false;
  bool finished_ = false;
};

}  // namespace shore::scenes
