// The fuzzers' inputs as ordinary tests: every seed of fuzz/corpus/<target>/ and every
// input a fuzzer crashed on, kept in fuzz/regressions/<target>/ once fixed, goes through
// its target's entry point (fuzz/entries.h): refused with a FileError or loaded into a
// finite state that steps and round-trips, never a crash or a broken invariant.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "entries.h"

namespace fs = std::filesystem;

namespace {

struct Input {
  std::string target;
  fs::path file;
};

/// Every input file under root/<target>/.
std::vector<Input> inputs_under(const fs::path& root) {
  std::vector<Input> out;
  for (const shore::fuzz::Target& t : shore::fuzz::targets()) {
    const fs::path dir = root / t.name;
    if (!fs::is_directory(dir)) continue;
    for (const fs::directory_entry& e : fs::directory_iterator(dir))
      if (e.is_regular_file() && e.path().filename() != "README.md") out.push_back({t.name, e.path()});
  }
  std::sort(out.begin(), out.end(), [](const Input& a, const Input& b) { return a.file < b.file; });
  return out;
}
std::vector<Input> inputs(const char* kind) { return inputs_under(fs::path(SHORE_FUZZ_DIR) / kind); }

std::vector<std::uint8_t> read(const fs::path& file) {
  std::ifstream f(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

/// Whether a valid seed of this target can load in this build.
bool fits_build(const Input& in) {
  for (const shore::fuzz::Target& t : shore::fuzz::targets())
    if (in.target == t.name && t.seed_fits_build) return t.seed_fits_build(read(in.file));
  return true;
}

/// Runs the input through its target; returns whether the loader accepted it.
bool run(const Input& in) {
  const std::vector<std::uint8_t> bytes = read(in.file);
  for (const shore::fuzz::Target& t : shore::fuzz::targets())
    if (in.target == t.name) {
      try {
        return t.run(bytes);
      } catch (const shore::fuzz::InvariantBroken& e) {
        ADD_FAILURE() << in.file << ": " << e.what();
        return false;
      }
    }
  ADD_FAILURE() << "no fuzz target " << in.target;
  return false;
}

}  // namespace

TEST(FuzzInputs, EveryTargetHasSeeds) {
  for (const shore::fuzz::Target& t : shore::fuzz::targets()) {
    const fs::path dir = fs::path(SHORE_FUZZ_DIR) / "corpus" / t.name;
    ASSERT_TRUE(fs::is_directory(dir)) << dir;
    EXPECT_FALSE(fs::is_empty(dir)) << dir;
  }
}

void expect_seeds_load(const std::vector<Input>& seeds) {
  EXPECT_GE(seeds.size(), 3u);
  for (const Input& in : seeds) {
    if (fits_build(in))
      EXPECT_TRUE(run(in)) << in.file << " was refused";
    else
      EXPECT_FALSE(run(in)) << in.file << " was written with the other precision, yet accepted";
  }
}

// The seeds are valid files (shore-fuzz-corpus writes them): each loads.
TEST(FuzzInputs, SeedsLoad) { expect_seeds_load(inputs("corpus")); }

// What shore-fuzz-corpus writes today loads too: its hand-made old-version files and the
// entries' raw modes follow the formats as they change (both fell behind once, unseen,
// while the committed seeds, older, still loaded).
TEST(FuzzInputs, SeedsWrittenByThisBuildLoad) {
  const fs::path dir = fs::temp_directory_path() / ("shore_fresh_seeds_" + std::to_string(::getpid()));
  const std::string command = std::string(SHORE_FUZZ_CORPUS_EXE) + " " + dir.string() + " > /dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  expect_seeds_load(inputs_under(dir));
  fs::remove_all(dir);
}

TEST(FuzzInputs, EveryCrashFoundStaysFixed) {
  for (const Input& in : inputs("regressions")) (void)run(in);
}
