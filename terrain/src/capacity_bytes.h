#pragma once
// Private: memory accounting. Every owner of scratch or storage reports the bytes its own
// containers hold, so a new array is counted where it is declared.

#include <cstddef>

namespace shore::terrain {

/// Bytes reserved by the given containers (capacity, not size: what stays allocated).
template <class... Containers>
[[nodiscard]] std::size_t capacity_bytes(const Containers&... c) {
  return (std::size_t{0} + ... + (c.capacity() * sizeof(typename Containers::value_type)));
}

}  // namespace shore::terrain
