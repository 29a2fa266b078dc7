// Saving when the disk fails: a full disk, a folder that refuses the write, a size limit,
// the process killed mid-write. Each time the old file stays byte for byte what it was and
// loads, and the error names the file and the system's cause. Files of another format
// version, byte order or precision are refused with a message saying so.
//
// How each fault is made without mounting anything (the tests run as root in CI):
// - full disk: the temporary file save() writes (<file>.tmp) is made a symbolic link to
//   /dev/full, whose writes fail with ENOSPC, as a full disk's do;
// - read-only folder: a folder without write permission. Root ignores permissions, so as
//   root the save runs in a child process that has given up root (setuid to nobody); a
//   folder path whose parent is a file is refused for every user alike;
// - size limit: a child process with RLIMIT_FSIZE below the file's size (EFBIG);
// - killed mid-write: <file>.tmp is made a FIFO, so the saving child blocks inside its
//   write once the pipe is full; the parent reads part of the file and kills it (SIGKILL).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "shore/core/error.h"
#include "shore/core/hash.h"
#include "shore/terrain/terrain.h"
#include "terrain_fixtures.h"

using namespace shore::terrain;
using namespace shore::terrain::testing;
namespace fs = std::filesystem;

namespace {

std::vector<unsigned char> read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// A folder of its own for each test, removed at the end.
class DiskFaults : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("shore_disk_faults_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(dir_, ec))
      if (e.is_directory(ec)) fs::permissions(e.path(), fs::perms::owner_all, fs::perm_options::add, ec);
    fs::remove_all(dir_, ec);
  }
  fs::path dir_;
};

/// A terrain with a history: a sphere pressed `steps` times at (x, 0).
Terrain pressed(double x, int steps, int tile_columns = 16) {
  TerrainSettings s;
  s.tile_columns = tile_columns;
  s.threads = 1;
  Terrain t(s);
  for (int k = 1; k <= steps; ++k) {
    const shore::EnvelopeRaster env = sphere_envelope(t, x, 0.0, 0.1 - 0.003 * k, 0.1);
    const Imprint im{&env};
    t.step({&im, 1});
  }
  return t;
}

/// The file is what `old` saved, and loads to its state.
void expect_old_file_intact(const fs::path& file, const std::vector<unsigned char>& old_bytes, std::uint64_t old_hash) {
  EXPECT_EQ(read_bytes(file), old_bytes) << file << " changed";
  EXPECT_EQ(Terrain::load(file).state_hash(), old_hash);
}

std::string save_error(const Terrain& t, const fs::path& file) {
  try {
    t.save(file);
  } catch (const shore::FileError& e) {
    return e.what();
  }
  return "(no exception)";
}

/// Runs fn in a child process and returns what it wrote to the pipe (its error message).
std::string in_child(const std::function<std::string()>& fn) {
  std::array<int, 2> pipe_fds{};
  if (::pipe(pipe_fds.data()) != 0) return "(pipe failed)";
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(pipe_fds[0]);
    const std::string message = fn();
    const ssize_t wrote = ::write(pipe_fds[1], message.data(), message.size());
    ::_exit(wrote == static_cast<ssize_t>(message.size()) ? 0 : 1);
  }
  ::close(pipe_fds[1]);
  std::string out;
  char buf[4096];
  for (ssize_t n; (n = ::read(pipe_fds[0], buf, sizeof buf)) > 0;) out.append(buf, static_cast<std::size_t>(n));
  ::close(pipe_fds[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "child status " << status;
  return out;
}

}  // namespace

TEST_F(DiskFaults, FullDiskKeepsTheOldFileAndSaysSo) {
  const fs::path file = dir_ / "soil.state";
  const Terrain old_soil = pressed(0.0, 3), new_soil = pressed(0.2, 5);
  old_soil.save(file);
  const std::vector<unsigned char> old_bytes = read_bytes(file);
  fs::create_symlink("/dev/full", dir_ / "soil.state.tmp");
  const std::string error = save_error(new_soil, file);
  EXPECT_TRUE(mentions(error, file.string())) << error;
  EXPECT_TRUE(mentions(error, "No space left on device")) << error;
  EXPECT_TRUE(mentions(error, "previous file")) << error;
  expect_old_file_intact(file, old_bytes, old_soil.state_hash());
  EXPECT_FALSE(fs::exists(fs::symlink_status(dir_ / "soil.state.tmp"))) << "the temporary is removed";
  // The disk has room again: the save goes through.
  new_soil.save(file);
  EXPECT_EQ(Terrain::load(file).state_hash(), new_soil.state_hash());
}

TEST_F(DiskFaults, FileSizeLimitKeepsTheOldFile) {
  const fs::path file = dir_ / "soil.state";
  const Terrain old_soil = pressed(0.0, 3), new_soil = pressed(0.2, 5);
  old_soil.save(file);
  const std::vector<unsigned char> old_bytes = read_bytes(file);
  ASSERT_GT(new_soil.save_bytes().size(), 8192u);
  const std::string error = in_child([&] {
    ::signal(SIGXFSZ, SIG_IGN);  // a write past the limit fails with EFBIG instead of killing
    const rlimit limit{8192, 8192};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    return save_error(new_soil, file);
  });
  EXPECT_TRUE(mentions(error, file.string())) << error;
  EXPECT_TRUE(mentions(error, "File too large")) << error;
  expect_old_file_intact(file, old_bytes, old_soil.state_hash());
  EXPECT_FALSE(fs::exists(dir_ / "soil.state.tmp"));
}

TEST_F(DiskFaults, ReadOnlyFolderKeepsTheOldFile) {
  const fs::path folder = dir_ / "read_only";
  fs::create_directories(folder);
  const fs::path file = folder / "soil.state";
  const Terrain old_soil = pressed(0.0, 3), new_soil = pressed(0.2, 5);
  old_soil.save(file);
  const std::vector<unsigned char> old_bytes = read_bytes(file);
  fs::permissions(folder, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read |
                              fs::perms::group_exec | fs::perms::others_read | fs::perms::others_exec);
  const std::string error = in_child([&] {
    if (::geteuid() == 0) {  // root writes anywhere: save as nobody, as an ordinary user would
      if (::setgid(65534) != 0 || ::setuid(65534) != 0) return std::string("(cannot drop root)");
    }
    return save_error(new_soil, file);
  });
  EXPECT_TRUE(mentions(error, file.string())) << error;
  EXPECT_TRUE(mentions(error, "Permission denied")) << error;
  expect_old_file_intact(file, old_bytes, old_soil.state_hash());
  EXPECT_FALSE(fs::exists(folder / "soil.state.tmp"));
}

TEST_F(DiskFaults, FolderThatIsAFileIsRefusedByName) {
  // Refused for root too: the path's parent is a regular file.
  const fs::path not_a_folder = dir_ / "plain_file";
  std::ofstream(not_a_folder) << "not a folder";
  const fs::path file = not_a_folder / "soil.state";
  const std::string error = save_error(pressed(0.0, 2), file);
  EXPECT_TRUE(mentions(error, file.string())) << error;
  EXPECT_TRUE(mentions(error, "Not a directory")) << error;
  EXPECT_EQ(read_bytes(not_a_folder).size(), 12u);
}

TEST_F(DiskFaults, KilledMidWriteKeepsTheOldFile) {
  const fs::path file = dir_ / "soil.state";
  const Terrain old_soil = pressed(0.0, 3);
  Terrain new_soil = pressed(0.2, 5, 64);
  for (int k = 1; k <= 20; ++k)
    new_soil.set_height(64 * k, 0, 0.01);  // 20 more tiles: 2 MB, far more than a pipe holds
  old_soil.save(file);
  const std::vector<unsigned char> old_bytes = read_bytes(file);
  const std::size_t new_size = new_soil.save_bytes().size();
  ASSERT_GT(new_size, std::size_t{1} << 20);
  const fs::path temp = dir_ / "soil.state.tmp";
  ASSERT_EQ(::mkfifo(temp.c_str(), 0600), 0) << std::strerror(errno);
  const pid_t pid = ::fork();
  if (pid == 0) {
    try {
      new_soil.save(file);
    } catch (...) {
    }
    ::_exit(0);
  }
  // Read a part of what the child writes: it is then blocked inside its write.
  std::ifstream pipe(temp, std::ios::binary);
  std::vector<char> part(256 * 1024);
  pipe.read(part.data(), static_cast<std::streamsize>(part.size()));
  ASSERT_EQ(pipe.gcount(), static_cast<std::streamsize>(part.size()));
  ASSERT_EQ(::kill(pid, SIGKILL), 0);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << "the child finished before the kill";
  EXPECT_EQ(std::memcmp(part.data(), "SHORETRN", 8), 0) << "it was writing the new state";
  expect_old_file_intact(file, old_bytes, old_soil.state_hash());
  // What a killed save leaves behind (a partial temporary) does not stop the next save.
  fs::remove(temp);
  std::ofstream(temp, std::ios::binary).write(part.data(), 1000);
  new_soil.save(file);
  EXPECT_FALSE(fs::exists(temp));
  EXPECT_EQ(Terrain::load(file).state_hash(), new_soil.state_hash());
}

namespace {

/// The file's header fields as another writer would have put them, checksum recomputed.
std::vector<unsigned char> with_header(std::vector<unsigned char> bytes, std::size_t at, std::uint32_t value) {
  std::memcpy(bytes.data() + at, &value, sizeof value);
  bytes.resize(bytes.size() - 8);
  shore::StateHash sum;
  sum.add_bytes(bytes.data(), bytes.size());
  const std::uint64_t checksum = sum.value();
  const auto* p = reinterpret_cast<const unsigned char*>(&checksum);
  bytes.insert(bytes.end(), p, p + sizeof checksum);
  return bytes;
}

std::string load_error(const std::vector<unsigned char>& bytes) {
  try {
    (void)Terrain::load_bytes(bytes, "other.state");
  } catch (const shore::FileError& e) {
    return e.what();
  }
  return "(no exception)";
}

}  // namespace

TEST(Files, OtherVersionByteOrderAndPrecisionAreRefusedSayingSo) {
  const std::vector<unsigned char> good = pressed(0.0, 3).save_bytes();
  ASSERT_EQ(load_error(good), "(no exception)");
  // Header: magic (8), u32 version at 8, u32 byte-order mark at 12, u32 bytes per real at 16.
  const std::string newer = load_error(with_header(good, 8, 99));
  EXPECT_TRUE(mentions(newer, "other.state")) << newer;
  EXPECT_TRUE(mentions(newer, "unsupported format version 99 (this build reads versions 1 to 9)")) << newer;
  EXPECT_TRUE(mentions(load_error(with_header(good, 8, 0)), "unsupported format version 0")) << newer;
  // A big-endian writer: every header number swapped, the mark first of all.
  std::vector<unsigned char> swapped = with_header(good, 8, __builtin_bswap32(4u));
  swapped = with_header(swapped, 12, __builtin_bswap32(0x01020304u));
  swapped = with_header(swapped, 16, __builtin_bswap32(8u));
  const std::string order = load_error(swapped);
  EXPECT_TRUE(mentions(order, "other byte order")) << order;
  const std::string junk_mark = load_error(with_header(good, 12, 0x11223344u));
  EXPECT_TRUE(mentions(junk_mark, "neither byte order")) << junk_mark;
  // A writer storing float32 reals (a float-precision checkpoint, say).
  const std::string single = load_error(with_header(good, 16, 4));
  EXPECT_TRUE(mentions(single, "stores 4-byte real numbers; this build reads 8-byte (float64) ones only")) << single;
}

TEST(Files, BytesInMemoryRoundTripAsTheFileDoes) {
  const Terrain a = pressed(0.0, 4);
  const std::vector<unsigned char> bytes = a.save_bytes();
  const fs::path file = fs::temp_directory_path() / ("shore_bytes_" + std::to_string(::getpid()) + ".state");
  a.save(file);
  EXPECT_EQ(read_bytes(file), bytes);
  EXPECT_EQ(Terrain::load_bytes(bytes, "memory").state_hash(), a.state_hash());
  fs::remove(file);
}
