#pragma once
// Private: the random numbers of spray, from a counter-based generator. Each number is a
// hash of what it is for: (seed, step, body, piece of surface, candidate, draw), so no
// generator state is carried, and results depend neither on the thread count nor on the
// order bodies are given in. The mixing function is SplitMix64's finaliser (Steele, Lea &
// Flood 2014), a bijection of 64-bit words whose outputs pass BigCrush.

#include <array>
#include <cstddef>
#include <cstdint>

namespace shore::terrain {

[[nodiscard]] constexpr std::uint64_t mix64(std::uint64_t z) noexcept {
  z += 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

/// mix64(k) for the first kMixedCounters counters k = candidate * 16 + draw: a piece's
/// candidates number from 0, so most draws find their counter's mix here (the same word).
inline constexpr std::size_t kMixedCounters = 1024;
inline constexpr std::array<std::uint64_t, kMixedCounters> kMixedCounter = [] {
  std::array<std::uint64_t, kMixedCounters> t{};
  for (std::size_t k = 0; k < kMixedCounters; ++k) t[k] = mix64(k);
  return t;
}();

/// The random numbers of one (seed, step, body, piece) tuple; uniform(candidate, draw) is
/// the draw-th number of the candidate-th particle.
class CounterRandom {
 public:
  /// Key 0, for a member (`Candidate::random`) that `Cling::emit` assigns a keyed
  /// generator before any number is drawn.
  CounterRandom() noexcept = default;
  CounterRandom(std::uint64_t seed, std::uint64_t step, std::uint64_t body, std::uint64_t piece) noexcept
      : key_(mix64(body_key(seed, step, body) ^ piece)) {}
  /// The part of the key (seed, step, body) fix, to be mixed with each piece's.
  [[nodiscard]] static constexpr std::uint64_t body_key(std::uint64_t seed, std::uint64_t step,
                                                        std::uint64_t body) noexcept {
    return mix64(mix64(mix64(seed) ^ step) ^ body);
  }
  /// The numbers of (seed, step, body, piece) from body_key(seed, step, body): the same as
  /// the four-part constructor's.
  [[nodiscard]] static CounterRandom of_piece(std::uint64_t body_key, std::uint64_t piece) noexcept {
    return CounterRandom(mix64(body_key ^ piece));
  }
  /// In [0, 1), 53 random bits.
  [[nodiscard]] double uniform(std::uint64_t candidate, std::uint64_t draw) const noexcept {
    return static_cast<double>(bits(candidate, draw) >> 11) * 0x1.0p-53;
  }
  /// In [-1, 1): 2 uniform - 1, with 2 (b 2^-53) as b 2^-52 (both exact: b < 2^53).
  [[nodiscard]] double symmetric(std::uint64_t candidate, std::uint64_t draw) const noexcept {
    return static_cast<double>(bits(candidate, draw) >> 11) * 0x1.0p-52 - 1.0;
  }

 private:
  explicit CounterRandom(std::uint64_t key) noexcept : key_(key) {}
  /// The 64 random bits of (candidate, draw).
  [[nodiscard]] std::uint64_t bits(std::uint64_t candidate, std::uint64_t draw) const noexcept {
    const std::uint64_t counter = candidate * 16u + draw;
    return mix64(key_ ^ (counter < kMixedCounters ? kMixedCounter[counter] : mix64(counter)));
  }
  std::uint64_t key_ = 0;
};

}  // namespace shore::terrain
