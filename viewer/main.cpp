// shore-viewer: Shore's samples application. Opens any scene of scenes/, plays it, lets you
// drive, drop bodies and tweak the soil, with live statistics and debug overlays
// (docs/VIEWER.md). --headless renders the same frames without a display (EGL on Mesa).
// GCC 12 reports a false "potential null pointer dereference" inside CLI11's string
// splitting once inlined here (as in shore-bench); the warning is off for this file only.
#pragma GCC diagnostic ignored "-Wnull-dereference"
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include "src/run.h"

int main(int argc, char** argv) {
  shore::viewer::RunOptions o;
  CLI::App app{"shore-viewer: watch and play with Shore's scenes (docs/VIEWER.md)"};
  app.add_option("--scene", o.scene, "scene to open")->capture_default_str();
  app.add_option("--frames", o.frames, "exit after this many frames (0: when the window closes)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--script", o.script, "scripted input, one action per line (docs/VIEWER.md)")
      ->check(CLI::ExistingFile);
  app.add_option("--screenshot", o.screenshot, "write the last frame's 3-D view (no panels) as PNG");
  app.add_option("--window-shot", o.window_shot, "write the last frame's whole window, panels included, as PNG");
  app.add_option("--report", o.report, "write frame times, bytes uploaded and body pixels as JSON");
  app.add_option("--width", o.width, "pixels")->check(CLI::Range(16, 8192))->capture_default_str();
  app.add_option("--height", o.height, "pixels")->check(CLI::Range(16, 8192))->capture_default_str();
  app.add_option("--samples", o.samples, "MSAA samples (1: none)")->check(CLI::Range(1, 16))->capture_default_str();
  app.add_flag("--smoke", o.smoke, "the scene's smoke settings (small grids, as the tests use)");
  app.add_flag("--headless", o.headless, "no window: EGL on Mesa (no display or GPU needed)");
  app.add_flag("!--no-shadows", o.shadows, "no shadow map");
  CLI11_PARSE(app, argc, argv);
  try {
    return o.headless ? shore::viewer::run_headless(o) : shore::viewer::run_window(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "shore-viewer: %s\n", e.what());
    return 1;
  }
}
