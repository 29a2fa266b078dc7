#pragma once
// Integer division rounded toward -infinity, for mapping column indices (any sign) to the
// tiles and blocks that hold them.

#include <bit>
#include <cstdint>

namespace shore {

/// a / b rounded toward -infinity (b != 0).
[[nodiscard]] inline std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && ((a < 0) != (b < 0))) ? q - 1 : q;
}

/// floor_div by one fixed divisor > 0: an arithmetic shift when it is a power of two (the
/// usual tile and block sizes), which spares a 64-bit division (tens of cycles) per call.
class FloorDivider {
 public:
  explicit FloorDivider(std::int64_t divisor) : divisor_(divisor) {
    if (divisor > 0 && (divisor & (divisor - 1)) == 0) shift_ = std::countr_zero(static_cast<std::uint64_t>(divisor));
  }
  [[nodiscard]] std::int64_t operator()(std::int64_t a) const {
    return shift_ >= 0 ? a >> shift_ : floor_div(a, divisor_);
  }

 private:
  std::int64_t divisor_;
  int shift_ = -1;  ///< log2 of the divisor; -1: not a power of two
};

}  // namespace shore
