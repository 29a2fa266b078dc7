#pragma once
// One versioned binary container for everything Shore saves: named sections (the terrain's
// own state bytes, the water surface's, the couplings', the application's bodies), a
// precision mark and a checksum over the whole, written atomically (a temporary file
// beside the target, then a rename: a reader never sees half a checkpoint).
//
//   "SHORECKP", u32 version, u32 byte-order mark 0x01020304, u32 scalar bytes (the writer's
//   btScalar size: 4 or 8; 0 if the file holds no Bullet state), u32 section count;
//   per section: 8-byte tag (zero padded), u64 size, the bytes; u64 FNV-1a of all before.
// docs/checkpoints.md lists the sections Shore writes.

#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "shore/core/byte_io.h"
#include "shore/core/error.h"
#include "shore/core/file_bytes.h"
#include "shore/core/hash.h"

namespace shore {

namespace checkpoint_format {
inline constexpr char kMagic[8] = {'S', 'H', 'O', 'R', 'E', 'C', 'K', 'P'};
inline constexpr std::uint32_t kVersion = 1;
inline constexpr std::uint32_t kByteOrderMark = 0x01020304u;
using Tag = std::array<char, 8>;
/// A tag of 1 to 8 printable characters, zero padded; InvalidSetting otherwise.
inline Tag make_tag(std::string_view name) {
  if (name.empty() || name.size() > 8)
    throw InvalidSetting("checkpoint.section", std::string(name), "must be 1 to 8 characters");
  Tag t{};
  std::memcpy(t.data(), name.data(), name.size());
  return t;
}
inline std::string tag_name(const Tag& t) { return std::string(t.data(), strnlen(t.data(), t.size())); }
}  // namespace checkpoint_format

class CheckpointWriter {
 public:
  /// scalar_bytes: sizeof(btScalar) of the writer when it saves Bullet state, else 0.
  explicit CheckpointWriter(std::uint32_t scalar_bytes = 0) : scalar_bytes_(scalar_bytes) {}
  /// Adds a section; InvalidSetting if the tag is malformed or already used.
  void add(std::string_view tag, std::vector<unsigned char> bytes) {
    const auto t = checkpoint_format::make_tag(tag);
    for (const auto& s : sections_)
      if (s.first == t) throw InvalidSetting("checkpoint.section", std::string(tag), "is already in the checkpoint");
    sections_.emplace_back(t, std::move(bytes));
  }
  [[nodiscard]] std::vector<unsigned char> bytes() const {
    using namespace checkpoint_format;
    ByteWriter w;
    for (char c : kMagic) w.put(c);
    w.put(kVersion), w.put(kByteOrderMark), w.put(scalar_bytes_), w.put(static_cast<std::uint32_t>(sections_.size()));
    for (const auto& [tag, data] : sections_) {
      w.put(tag), w.put(static_cast<std::uint64_t>(data.size()));
      w.bytes.insert(w.bytes.end(), data.begin(), data.end());
    }
    StateHash h;
    h.add_bytes(w.bytes.data(), w.bytes.size());
    w.put(h.value());
    return std::move(w.bytes);
  }
  /// Atomic: the file is either the old one or the whole new one.
  void save(const std::filesystem::path& file) const { write_file_atomically(file, bytes(), "checkpoint"); }

 private:
  std::uint32_t scalar_bytes_;
  std::vector<std::pair<checkpoint_format::Tag, std::vector<unsigned char>>> sections_;
};

class CheckpointReader {
 public:
  /// Checks magic, version, byte order, checksum and precision (scalar_bytes: this build's
  /// sizeof(btScalar) if it will read Bullet state, else 0: any); FileError naming the
  /// source and the problem.
  CheckpointReader(std::vector<unsigned char> bytes, std::string source, std::uint32_t scalar_bytes = 0)
      : bytes_(std::move(bytes)), source_(std::move(source)) {
    using namespace checkpoint_format;
    ByteReader r(bytes_, "checkpoint " + source_);
    if (bytes_.size() < sizeof kMagic || std::memcmp(bytes_.data(), kMagic, sizeof kMagic) != 0)
      r.fail("not a Shore checkpoint (magic \"SHORECKP\" missing)");
    if (bytes_.size() < sizeof kMagic + 16 + 8) r.fail("truncated (ends inside the header)");
    for (std::size_t k = 0; k < sizeof kMagic; ++k) (void)r.get<char>("magic");
    const auto version = r.get<std::uint32_t>("version");
    if (version != kVersion)
      r.fail("unsupported checkpoint version " + std::to_string(version) + " (this build reads " +
             std::to_string(kVersion) + ")");
    if (r.get<std::uint32_t>("byte-order mark") != kByteOrderMark) r.fail("written with the other byte order");
    StateHash h;
    h.add_bytes(bytes_.data(), bytes_.size() - 8);
    std::uint64_t stored = 0;
    std::memcpy(&stored, bytes_.data() + bytes_.size() - 8, sizeof stored);
    if (stored != h.value()) r.fail("checksum mismatch (file truncated or corrupt)");
    scalar_bytes_ = r.get<std::uint32_t>("precision");
    if (scalar_bytes != 0 && scalar_bytes_ != 0 && scalar_bytes_ != scalar_bytes)
      r.fail("written by a build with " + std::to_string(8 * scalar_bytes_) + "-bit Bullet scalars, this one uses " +
             std::to_string(8 * scalar_bytes) + "-bit (SHORE_DOUBLE_PRECISION differs)");
    read_sections(r);
  }
  static CheckpointReader open(const std::filesystem::path& file, std::uint32_t scalar_bytes = 0) {
    return {read_file_bytes(file, "checkpoint"), file.string(), scalar_bytes};
  }
  [[nodiscard]] bool has(std::string_view tag) const { return find(checkpoint_format::make_tag(tag)) != nullptr; }
  /// A section's bytes; FileError naming the missing section.
  [[nodiscard]] std::span<const unsigned char> section(std::string_view tag) const {
    const auto* s = find(checkpoint_format::make_tag(tag));
    if (s == nullptr) throw FileError("checkpoint " + source_ + ": no section " + std::string(tag));
    return {bytes_.data() + s->offset, s->size};
  }
  /// "checkpoint <source>, section <tag>": for the sections' own error messages.
  [[nodiscard]] std::string describe(std::string_view tag) const {
    return "checkpoint " + source_ + ", section " + std::string(tag);
  }
  [[nodiscard]] std::uint32_t scalar_bytes() const { return scalar_bytes_; }

 private:
  struct Section {
    checkpoint_format::Tag tag;
    std::size_t offset = 0, size = 0;
  };
  void read_sections(ByteReader& r) {
    const auto count = r.get<std::uint32_t>("section count");
    std::size_t offset = sizeof checkpoint_format::kMagic + 16;  // after the header
    for (std::uint32_t k = 0; k < count; ++k) {
      Section s;
      s.tag = r.get<checkpoint_format::Tag>("section header");
      const auto size = r.get<std::uint64_t>("section header");
      offset += 16;
      if (size > r.remaining() - 8)
        r.fail("section " + checkpoint_format::tag_name(s.tag) + " of " + std::to_string(size) +
               " bytes overruns the file");
      s.offset = offset, s.size = static_cast<std::size_t>(size);
      r.skip(s.size, "section");
      offset += s.size;
      sections_.push_back(s);
    }
    if (r.remaining() != 8) r.fail("bytes after the last section (corrupt)");
  }
  [[nodiscard]] const Section* find(const checkpoint_format::Tag& t) const {
    for (const Section& s : sections_)
      if (s.tag == t) return &s;
    return nullptr;
  }
  std::vector<unsigned char> bytes_;
  std::string source_;
  std::uint32_t scalar_bytes_ = 0;
  std::vector<Section> sections_;
};

}  // namespace shore
