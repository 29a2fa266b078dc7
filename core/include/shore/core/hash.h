#pragma once
// FNV-1a, 64 bit, over raw bytes: the state hash that tests and demos use to check that
// runs are bit-identical (whatever the thread count).

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <type_traits>

namespace shore {

class StateHash {
 public:
  static constexpr std::uint64_t kOffset = 14695981039346656037ull;
  static constexpr std::uint64_t kPrime = 1099511628211ull;

  void add_bytes(const void* data, std::size_t size) noexcept {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) {
      h_ ^= p[i];
      h_ *= kPrime;
    }
  }
  template <class T>
    requires std::is_trivially_copyable_v<T>
  void add(const T& value) noexcept {
    add_bytes(&value, sizeof(T));
  }
  template <class T>
    requires std::is_trivially_copyable_v<T>
  void add(std::span<const T> values) noexcept {
    add_bytes(values.data(), values.size_bytes());
  }
  [[nodiscard]] std::uint64_t value() const noexcept { return h_; }

 private:
  std::uint64_t h_ = kOffset;
};

/// "0123456789abcdef": a hash as 16 lowercase hex digits.
inline std::string to_hex(std::uint64_t h) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

}  // namespace shore
