#pragma once
// Private: whole files in and out, with errors that name the path and the system's cause.
// The terrain state and the heightmaps read through here; the terrain state is written
// through here (atomically: a reader never sees half a file). A future checkpoint or delta
// format (issue 20) should write through write_file_atomically too.

#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace shore::terrain {

/// The whole file. Throws shore::FileError "<what> <path>: cannot open for reading (<cause>)"
/// or "... read failed (<cause>)".
[[nodiscard]] std::vector<unsigned char> read_file_bytes(const std::filesystem::path& file, const std::string& what);

/// Writes bytes to `<file>.tmp`, flushes them to the disk (fsync), then renames the
/// temporary over `file`: the old file stays whole until the new one is complete, whatever
/// happens during the write (a full disk, a refused folder, the process killed). On error
/// the temporary is removed and shore::FileError names the file, the step that failed and
/// the system's cause ("No space left on device", "Permission denied", ...), and says that
/// the previous file is untouched. POSIX only (open, write, fsync, rename).
void write_file_atomically(const std::filesystem::path& file, std::span<const unsigned char> bytes,
                           const std::string& what);

}  // namespace shore::terrain
