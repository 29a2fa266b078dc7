#pragma once
// Internal: when the terrain deforms (TerrainCouplingSettings::step_interval): once per
// round(interval / substep) substeps, at least one. Substeps are counted, not timed, so no
// rounding of summed substeps can skip or add a terrain step.

#include <cmath>
#include <cstdint>
#include <string>

#include "shore/bullet/config.h"
#include "shore/core/byte_io.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

class StepClock {
 public:
  /// Counts one substep of `substep` seconds; true when the terrain steps in it.
  bool advance(double substep, double interval) {
    const double per_step = std::floor(interval / substep + 0.5);
    ++substeps_;
    seconds_ += substep;
    return static_cast<double>(substeps_) >= per_step;
  }
  /// s since the terrain last stepped: the time its next step covers.
  [[nodiscard]] double seconds() const noexcept { return seconds_; }
  /// The terrain has stepped.
  void restart() noexcept { substeps_ = 0, seconds_ = 0.0; }

  void save(ByteWriter& w) const { w.put(static_cast<std::int32_t>(substeps_)), w.put(seconds_); }
  /// FileError for a count below zero or a time that is negative or not finite.
  void restore(ByteReader& r) {
    const auto substeps = r.get<std::int32_t>("substeps since the terrain's step");
    const auto seconds = r.get<double>("time since the terrain's step");
    if (substeps < 0 || !(seconds >= 0.0) || !std::isfinite(seconds))
      r.fail("the terrain's clock (" + std::to_string(substeps) + " substeps, " + std::to_string(seconds) +
             " s since its step) is not a clock");
    substeps_ = substeps, seconds_ = seconds;
  }

 private:
  int substeps_ = 0;
  double seconds_ = 0.0;
};

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
