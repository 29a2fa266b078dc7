// Physics regression: each scene's state hash after its smoke run (a fixed number of
// substeps, one thread) must equal the value pinned in tests/scenes/pinned_hashes.json for
// this build's btScalar precision. A change of physics changes the hash: re-pin on purpose
// with the command printed on failure (see tests/scenes/README.md). The pins hold for every
// build of the cross-platform deterministic configuration (the default): any x86-64 CPU,
// either water kernel, sanitizers or not.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "shore/core/hash.h"
#include "shore/scenes/runner.h"
#include "shore/water/surface.h"

using namespace shore::scenes;

namespace {

#ifndef SHORE_DEMO_EXE
#define SHORE_DEMO_EXE "shore-demo"
#endif

std::string pin_command(const std::string& scene) {
  return std::string(SHORE_DEMO_EXE) + " pin --update " + SHORE_PINNED_HASHES_FILE + " --scene " + scene;
}

class PinnedHash : public testing::TestWithParam<std::string> {};

TEST_P(PinnedHash, SmokeRunStateHashMatchesThePinnedValue) {
  const std::string name = GetParam();
  nlohmann::json pinned;
  std::ifstream in(SHORE_PINNED_HASHES_FILE);
  ASSERT_TRUE(in) << "cannot read " << SHORE_PINNED_HASHES_FILE;
  in >> pinned;
  const std::string precision = precision_name();
  ASSERT_TRUE(pinned.contains(name) && pinned[name].contains(precision))
      << "scene '" << name << "' has no pinned state hash for the " << precision
      << " build. Run it, look at its pictures, then pin it on purpose with:\n  " << pin_command(name);

  const SceneType& scene = *find_scene(name);
  const SceneOptions opt = pinning_options(scene);
  const SceneResult r = run_scene(scene, opt, ProgressMode::quiet);
  const nlohmann::json& want = pinned[name][precision];
  EXPECT_EQ(want["substeps"].get<int>(), opt.substeps())
      << "the scene's smoke settings changed; re-pin with:\n  " << pin_command(name);
#ifndef SHORE_CROSS_PLATFORM_DETERMINISTIC
  if (want["state_hash"].get<std::string>() != shore::to_hex(r.state_hash) &&
      std::string(shore::water::Surface::fast_kernel_isa()) != "generic")
    GTEST_SKIP()
        << "built without SHORE_CROSS_PLATFORM_DETERMINISTIC: the vectorised water kernels may fuse multiply-adds, "
           "so water scenes differ from the pinned (generic-kernel) bits";
#endif
  EXPECT_EQ(want["state_hash"].get<std::string>(), shore::to_hex(r.state_hash))
      << "the physics of '" << name << "' changed (" << precision
      << " build). If intended, check its pictures and re-pin with:\n  " << pin_command(name);
}

INSTANTIATE_TEST_SUITE_P(AllScenes, PinnedHash, testing::ValuesIn(scene_names()),
                         [](const testing::TestParamInfo<std::string>& p) { return p.param; });

}  // namespace
