#pragma once
// Whole files in and out, with errors that name the path and the system's cause. The
// terrain state, the heightmaps and checkpoints read through here; the terrain state and
// checkpoints are written through here, atomically: a reader never sees half a file.

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <system_error>
#include <vector>

#include "shore/core/error.h"

namespace shore {

namespace file_detail {

inline std::string cause(int err) { return std::generic_category().message(err); }

/// Closes a descriptor once, on every path out.
class Descriptor {
 public:
  explicit Descriptor(int fd) : fd_(fd) {}
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  [[nodiscard]] int get() const noexcept { return fd_; }
  /// Closes now and returns 0 or the errno of close (a deferred write error shows here).
  int close() {
    const int fd = fd_;
    fd_ = -1;
    return ::close(fd) == 0 ? 0 : errno;
  }

 private:
  int fd_;
};

/// Writes all of bytes; returns 0 or the errno of the write that failed.
inline int write_all(int fd, std::span<const unsigned char> bytes) {
  constexpr std::size_t kChunk = std::size_t{1} << 20;  // bounded writes: a signal interrupts one chunk at most
  std::size_t done = 0;
  while (done < bytes.size()) {
    const std::size_t n = std::min(kChunk, bytes.size() - done);
    const ssize_t wrote = ::write(fd, bytes.data() + done, n);
    if (wrote < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    if (wrote == 0) return ENOSPC;  // no progress and no error: the device took nothing
    done += static_cast<std::size_t>(wrote);
  }
  return 0;
}

/// Makes the rename itself durable; a folder that cannot be synced (some file systems)
/// loses nothing that the rename did not already make visible.
inline void sync_folder(const std::filesystem::path& file) {
  std::filesystem::path folder = file.parent_path();
  if (folder.empty()) folder = ".";
  const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

}  // namespace file_detail

/// The whole file. Throws shore::FileError "<what> <path>: cannot open for reading (<cause>)"
/// or "... read failed (<cause>)".
[[nodiscard]] inline std::vector<unsigned char> read_file_bytes(const std::filesystem::path& file,
                                                                const std::string& what) {
  using namespace file_detail;
  const std::string where = what + " " + file.string() + ": ";
  Descriptor fd(::open(file.c_str(), O_RDONLY | O_CLOEXEC));
  if (fd.get() < 0) throw FileError(where + "cannot open for reading (" + cause(errno) + ")");
  std::vector<unsigned char> bytes;
  unsigned char buffer[1 << 16];
  for (;;) {
    const ssize_t got = ::read(fd.get(), buffer, sizeof buffer);
    if (got < 0) {
      if (errno == EINTR) continue;
      throw FileError(where + "read failed (" + cause(errno) + ")");
    }
    if (got == 0) break;
    bytes.insert(bytes.end(), buffer, buffer + got);
  }
  return bytes;
}

/// Writes bytes to `<file>.tmp`, flushes them to the disk (fsync), then renames the
/// temporary over `file`: the old file stays whole until the new one is complete, whatever
/// happens during the write (a full disk, a refused folder, the process killed). On error
/// the temporary is removed and shore::FileError names the file, the step that failed and
/// the system's cause ("No space left on device", "Permission denied", ...), and says that
/// the previous file is untouched. POSIX only (open, write, fsync, rename).
inline void write_file_atomically(const std::filesystem::path& file, std::span<const unsigned char> bytes,
                                  const std::string& what) {
  using namespace file_detail;
  std::filesystem::path temp = file;
  temp += ".tmp";
  const std::string where = what + " " + file.string() + ": ";
  const std::string untouched = "; the previous file, if any, is untouched";
  auto fail = [&](const std::string& step, int err) {
    ::unlink(temp.c_str());
    throw FileError(where + step + " (" + cause(err) + ")" + untouched);
  };
  Descriptor fd(::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644));
  if (fd.get() < 0) throw FileError(where + "cannot create " + temp.string() + " (" + cause(errno) + ")" + untouched);
  if (const int err = write_all(fd.get(), bytes)) fail("cannot write " + temp.string(), err);
  if (::fsync(fd.get()) != 0) fail("cannot flush " + temp.string() + " to the disk", errno);
  if (const int err = fd.close()) fail("cannot close " + temp.string(), err);
  if (::rename(temp.c_str(), file.c_str()) != 0) fail("cannot rename " + temp.string() + " over the file", errno);
  sync_folder(file);
}

}  // namespace shore
