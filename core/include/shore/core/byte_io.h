#pragma once
// Little binary writers and readers for Shore's saved states (checkpoints, deltas):
// trivially copyable values in the machine's byte order, appended to or read from a byte
// buffer; a read past the end throws shore::FileError naming the source and what was read.

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "shore/core/error.h"

namespace shore {

class ByteWriter {
 public:
  template <class T>
  requires std::is_trivially_copyable_v<T>
  void put(const T& v) {
    const auto* p = reinterpret_cast<const unsigned char*>(&v);
    bytes.insert(bytes.end(), p, p + sizeof(T));
  }
  /// A u64 count, then the values.
  template <class T>
  requires std::is_trivially_copyable_v<T>
  void put_array(const std::vector<T>& v) {
    put(static_cast<std::uint64_t>(v.size()));
    const auto* p = reinterpret_cast<const unsigned char*>(v.data());
    bytes.insert(bytes.end(), p, p + v.size() * sizeof(T));
  }
  std::vector<unsigned char> bytes;
};

class ByteReader {
 public:
  /// source: what the bytes are ("checkpoint save.ckp, section WATER") for messages.
  ByteReader(std::span<const unsigned char> bytes, std::string source) : bytes_(bytes), source_(std::move(source)) {}
  template <class T>
  requires std::is_trivially_copyable_v<T> T get(const char* what) {
    need(sizeof(T), what);
    T v;
    std::memcpy(&v, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  /// Reads put_array's form into v; its count must equal `expected`.
  template <class T>
  requires std::is_trivially_copyable_v<T>
  void get_array(std::vector<T>& v, std::size_t expected, const char* what) {
    const auto count = get<std::uint64_t>(what);
    if (count != expected)
      fail(std::string(what) + " holds " + std::to_string(count) + " values, expected " + std::to_string(expected));
    need(count * sizeof(T), what);
    v.resize(count);
    if (count == 0) return;  // an empty vector's data() may be null, which memcpy must not see
    std::memcpy(v.data(), bytes_.data() + pos_, count * sizeof(T));
    pos_ += count * sizeof(T);
  }
  /// Steps over size bytes.
  void skip(std::size_t size, const char* what) {
    need(size, what);
    pos_ += size;
  }
  [[nodiscard]] std::size_t remaining() const { return bytes_.size() - pos_; }
  [[noreturn]] void fail(const std::string& problem) const { throw FileError(source_ + ": " + problem); }

 private:
  void need(std::size_t size, const char* what) const {
    if (size > bytes_.size() - pos_) fail(std::string("truncated (ends inside ") + what + ")");
  }
  std::span<const unsigned char> bytes_;
  std::size_t pos_ = 0;
  std::string source_;
};

}  // namespace shore
