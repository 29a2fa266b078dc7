#include "shore/scenes/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "shore/core/error.h"

namespace shore::scenes {
namespace {
constexpr double kQuietSeconds = 1.0;  // runs shorter than this print nothing
constexpr double kBarInterval = 0.1;   // s between bar redraws
constexpr double kLineInterval = 5.0;  // s between plain lines
constexpr int kBarWidth = 30;
}  // namespace

ProgressMode parse_progress_mode(const std::string& text) {
  if (text == "auto") return ProgressMode::automatic;
  if (text == "bar") return ProgressMode::bar;
  if (text == "lines") return ProgressMode::lines;
  if (text == "quiet") return ProgressMode::quiet;
  throw InvalidSetting("progress", text, "must be one of auto, bar, lines, quiet");
}

Progress::Progress(std::string label, ProgressMode mode)
    : label_(std::move(label)), mode_(mode), start_(Clock::now()), last_print_(start_) {
  if (mode_ == ProgressMode::automatic) mode_ = isatty(STDERR_FILENO) ? ProgressMode::bar : ProgressMode::lines;
}

Progress::~Progress() { finish(); }

void Progress::update(double fraction) {
  if (mode_ == ProgressMode::quiet || finished_) return;
  fraction = std::clamp(std::isfinite(fraction) ? fraction : 0.0, 0.0, 1.0);
  last_fraction_ = fraction;
  const auto now = Clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (elapsed < kQuietSeconds) return;
  const double since = std::chrono::duration<double>(now - last_print_).count();
  if (mode_ == ProgressMode::bar && (since >= kBarInterval || !drawn_)) {
    draw_bar(fraction, elapsed);
    last_print_ = now;
  } else if (mode_ == ProgressMode::lines && (since >= kLineInterval || !drawn_)) {
    print_line(fraction, elapsed);
    last_print_ = now;
  }
}

void Progress::finish() {
  if (finished_) return;
  finished_ = true;
  if (!drawn_) return;
  const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
  if (mode_ == ProgressMode::bar) {
    draw_bar(1.0, elapsed);
    std::fputc('\n', stderr);
  } else {
    std::fprintf(stderr, "  %s: done in %.1f s\n", label_.c_str(), elapsed);
  }
  std::fflush(stderr);
}

void Progress::draw_bar(double fraction, double elapsed) {
  const int filled = static_cast<int>(std::lround(fraction * kBarWidth));
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.append(static_cast<std::size_t>(kBarWidth - filled), '-');
  const double eta = fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
  std::fprintf(stderr, "\r  %-16s [%s] %3.0f%%  %5.1f s  eta %5.1f s ", label_.c_str(), bar.c_str(), 100.0 * fraction,
               elapsed, eta);
  std::fflush(stderr);
  drawn_ = true;
}

void Progress::print_line(double fraction, double elapsed) {
  std::fprintf(stderr, "  %s: %3.0f%% after %.1f s\n", label_.c_str(), 100.0 * fraction, elapsed);
  std::fflush(stderr);
  drawn_ = true;
}

}  // namespace shore::scenes
