#include "shore/core/pacer.h"

#include <algorithm>

namespace shore {

bool Pacer::choose_parallel() {
  if (parallel < 0.0) return true;
  if (serial < 0.0) return false;
  const bool better = parallel <= serial;
  if (--countdown <= 0) {
    countdown = interval;
    return !better;
  }
  return better;
}

void Pacer::record(bool parallel_run, double seconds_per_unit) {
  double& mine = parallel_run ? parallel : serial;
  const double other = parallel_run ? serial : parallel;
  const bool was_worse = mine >= 0.0 && other >= 0.0 && (parallel_run ? parallel > serial : serial > parallel);
  mine = mine < 0.0 ? seconds_per_unit : 0.75 * mine + 0.25 * seconds_per_unit;
  if (was_worse) {  // a try of the slower mode: back off if it lost again
    interval = seconds_per_unit > other ? std::min(2 * interval, 4096) : 16;
    countdown = interval;
  }
}

}  // namespace shore
