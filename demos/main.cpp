// shore-demo: headless Shore scenes. One subcommand per registered scene, "all" for every
// scene, "pin" to check or update the pinned state hashes of the regression test,
// "replay" to re-render a run recorded with --record (shore/scenes/recording.h).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gl_pictures.h"
#include "shore/core/hash.h"
#include "shore/scenes/recording.h"
#include "shore/scenes/report.h"
#include "shore/scenes/runner.h"

namespace fs = std::filesystem;
using namespace shore::scenes;

namespace {

struct Cli {
  Overrides overrides;
  std::string progress = "auto";
  bool pictures = true;  ///< the pictures, from the OpenGL renderer (when built)
  std::string record;    ///< --record: the file the one scene run is recorded to
};

void add_common_options(CLI::App& app, Cli& cli) {
  Overrides& o = cli.overrides;
  app.add_option("--out", o.out_root, "output root; each scene writes to <out>/<scene>/")->capture_default_str();
  app.add_option("--threads", o.threads, "threads of the soil and the water (default: the machine's hardware threads)")
      ->check(CLI::Range(1, 1024));
  app.add_option("--seconds", o.seconds, "simulated seconds (default: the scene's)")->check(CLI::PositiveNumber);
  app.add_option("--substep", o.substep, "fixed substep, s (default: the scene's)")->check(CLI::Range(1e-6, 0.1));
  app.add_option("--material", o.material, "soil material (default: the scene's)")
      ->check(CLI::IsMember({"sand", "mud", "snow"}));
  app.add_option("--cell", o.cell, "grid spacing, m (default: the scene's)")->check(CLI::Range(1e-4, 1.0));
  app.add_flag("--smoke", o.smoke, "short run (the scene's smoke_seconds), as the tests do");
  app.add_flag("!--no-pictures", cli.pictures, "no pictures (they need the OpenGL renderer, headless through EGL)");
  app.add_option("--record", cli.record,
                 "record the run (one scene) to this file: its initial state, then per frame the soil deltas, "
                 "water, body and multibody states; shore-demo replay <file> re-renders it");
  app.add_option("--progress", cli.progress, "progress on stderr: auto (bar on a terminal), bar, lines, quiet")
      ->check(CLI::IsMember({"auto", "bar", "lines", "quiet"}))
      ->capture_default_str();
}

std::string scene_help(const SceneType& s) {
  char buf[200];
  std::snprintf(buf, sizeof buf, "\n\ndefaults: --seconds %g --substep %g --material %s --cell %g (smoke: %g s)",
                s.defaults.seconds, s.defaults.substep, s.defaults.material.c_str(), s.defaults.cell,
                s.defaults.smoke_seconds);
  return s.description + buf;
}

/// Runs the scenes; returns the number that failed.
int run_scenes(const std::vector<const SceneType*>& list, const Cli& cli) {
  int failed = 0;
  const ProgressMode mode = parse_progress_mode(cli.progress);
  if (!cli.record.empty() && list.size() != 1) {
    std::fprintf(stderr, "shore-demo: --record records one scene, not %zu\n", list.size());
    return 1;
  }
  const std::unique_ptr<shore::scenes::Painter> painter = shore::demo::make_painter(cli.pictures);
  std::unique_ptr<Recorder> recorder = cli.record.empty() ? nullptr : std::make_unique<Recorder>(cli.record);
  for (const SceneType* s : list) {
    std::fprintf(stderr, "shore-demo: %s ...\n", s->name.c_str());
    try {
      const SceneResult r = run_scene(*s, resolve(*s, cli.overrides), mode, painter.get(), recorder.get());
      const auto& m = r.metrics;
      if (recorder) {
        const Recorder::Sizes& z = recorder->sizes();
        std::printf(
            "recorded to %s: %zu bytes (%.0f per simulated second; uncompressed: initial state %zu, soil deltas "
            "%zu, bodies %zu, multibodies %zu, water states %zu; the water frames add %zu bytes to the file)\n",
            cli.record.c_str(), z.file, static_cast<double>(z.file) / m["sim_seconds"].get<double>(), z.initial,
            z.terrain_deltas, z.bodies, z.multibodies, z.water_states, z.water_compressed);
      }
      std::printf("%-16s %6.2f s simulated in %6.3f s (x%.1f real time), hash %s, %zu files in %s\n", s->name.c_str(),
                  m["sim_seconds"].get<double>(), m["wall_seconds"].get<double>(), m["realtime_factor"].get<double>(),
                  m["state_hash"].get<std::string>().c_str(), r.files.size(),
                  (cli.overrides.out_root / s->name).c_str());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "shore-demo: scene %s failed: %s\n", s->name.c_str(), e.what());
      ++failed;
    }
  }
  const fs::path report = write_report(cli.overrides.out_root);
  std::printf("output: %s/  (report: %s)\n", fs::absolute(cli.overrides.out_root).lexically_normal().c_str(),
              fs::absolute(report).lexically_normal().c_str());
  return failed;
}

/// Replays a recording; 0 if its final state hash equals the recorded run's.
int replay_file(const std::string& file, const Cli& cli) {
  const std::unique_ptr<shore::scenes::Painter> painter = shore::demo::make_painter(cli.pictures);
  const ReplayResult r =
      replay(file, cli.overrides.out_root, cli.overrides.write_files, painter.get(), parse_progress_mode(cli.progress));
  const bool same = r.state_hash == r.recorded_state_hash;
  std::printf(
      "replay %-9s %d frames, %6.2f s simulated, replayed in %6.3f s, hash %s %s the run's %s, %zu files in %s\n",
      r.scene.c_str(), r.frames, r.sim_seconds, r.wall_seconds, shore::to_hex(r.state_hash).c_str(),
      same ? "equals" : "DIFFERS from", shore::to_hex(r.recorded_state_hash).c_str(), r.files.size(),
      (cli.overrides.out_root / r.scene).c_str());
  return same ? 0 : 1;
}

/// Smoke-run state hashes of the chosen scenes (one thread, no files), keyed by name.
nlohmann::json current_hashes(const std::vector<const SceneType*>& list) {
  nlohmann::json out = nlohmann::json::object();
  for (const SceneType* s : list) {
    const SceneOptions opt = pinning_options(*s);
    const SceneResult r = run_scene(*s, opt, ProgressMode::quiet);
    out[s->name] = {{"state_hash", shore::to_hex(r.state_hash)},
                    {"substeps", opt.substeps()},
                    {"substep_s", opt.substep},
                    {"seconds", opt.seconds}};
  }
  return out;
}

int pin(const std::string& file, bool update, const std::vector<std::string>& names) {
  std::vector<const SceneType*> list;
  if (names.empty())
    for (const SceneType& s : scenes()) list.push_back(&s);
  for (const auto& n : names) {
    const SceneType* s = find_scene(n);
    if (!s) {
      std::fprintf(stderr, "shore-demo pin: no scene called %s\n", n.c_str());
      return 2;
    }
    list.push_back(s);
  }
  nlohmann::json pinned = nlohmann::json::object();
  if (fs::exists(file)) std::ifstream(file) >> pinned;
  const std::string precision = precision_name();
  const nlohmann::json now = current_hashes(list);
  int differ = 0;
  for (const auto& [name, entry] : now.items()) {
    const nlohmann::json* old =
        pinned.contains(name) && pinned[name].contains(precision) ? &pinned[name][precision] : nullptr;
    const bool same = old && (*old)["state_hash"] == entry["state_hash"] && (*old)["substeps"] == entry["substeps"];
    std::printf("%-16s %s %s  %s\n", name.c_str(), precision.c_str(), entry["state_hash"].get<std::string>().c_str(),
                same ? "pinned" : (old ? "DIFFERS from pinned" : "not pinned"));
    if (!same) ++differ;
    if (update) pinned[name][precision] = entry;
  }
  if (update) {
    pinned["_about"] =
        "State hash of each demo scene after its smoke run (fixed substeps, one thread), per btScalar precision. "
        "Checked by tests/scenes (ctest -L scenes). Update on purpose with: "
        "build/release/demos/shore-demo pin --update tests/scenes/pinned_hashes.json "
        "(and build/double/demos/shore-demo pin --update ... for double).";
    const std::string tmp = file + ".tmp";
    std::ofstream(tmp) << pinned.dump(2) << '\n';
    fs::rename(tmp, file);
    std::printf("updated %s (%s)\n", file.c_str(), precision.c_str());
    return 0;
  }
  return differ == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "shore-demo: headless Shore scenes. Each writes pictures, a mesh and metrics.json to <out>/<scene>/, "
      "then <out>/report.md shows them all."};
  app.require_subcommand(1, 1);
  Cli cli;
  add_common_options(app, cli);
  std::vector<std::pair<const SceneType*, CLI::App*>> subs;
  for (const SceneType& s : scenes()) subs.emplace_back(&s, app.add_subcommand(s.name, scene_help(s)));
  CLI::App* all = app.add_subcommand("all", "run every scene in turn");
  CLI::App* list = app.add_subcommand("list", "list the scenes and their defaults");

  CLI::App* pin_cmd = app.add_subcommand(
      "pin", "print each scene's smoke-run state hash and compare it with a pinned-hash file; --update writes it");
  std::string pin_file = "tests/scenes/pinned_hashes.json";
  bool pin_update = false;
  std::vector<std::string> pin_scenes;
  pin_cmd->add_option("file", pin_file, "pinned-hash file")->capture_default_str();
  pin_cmd->add_flag("--update", pin_update, "write the current hashes for this build's precision");
  pin_cmd->add_option("--scene", pin_scenes, "only these scenes");
  CLI::App* replay_cmd = app.add_subcommand(
      "replay", "re-render a recording (--record) into <out>/<scene>/ and check its final state hash");
  std::string replay_file_name;
  replay_cmd->add_option("file", replay_file_name, "the recording")->required();
  for (auto& [scene, sub] : subs) {
    (void)scene;
    sub->fallthrough();
  }
  all->fallthrough();
  replay_cmd->fallthrough();
  CLI11_PARSE(app, argc, argv);

  try {
    if (list->parsed()) {
      for (const SceneType& s : scenes()) std::printf("%s\n  %s\n\n", s.name.c_str(), scene_help(s).c_str());
      return 0;
    }
    if (pin_cmd->parsed()) return pin(pin_file, pin_update, pin_scenes);
    if (replay_cmd->parsed()) return replay_file(replay_file_name, cli);
    std::vector<const SceneType*> chosen;
    if (all->parsed())
      for (const SceneType& s : scenes()) chosen.push_back(&s);
    for (auto& [scene, sub] : subs)
      if (sub->parsed()) chosen.push_back(scene);
    return run_scenes(chosen, cli) == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "shore-demo: %s\n", e.what());
    return 1;
  }
}
