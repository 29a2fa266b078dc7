#pragma once
// The soak: many bodies of every shape type on sand beside a pool of water, run
// for a long time (one body thrown up every second, so the soil keeps working), with what
// must not happen counted and what must stay flat measured.
// Written once; the 2,000-substep version is a test (tests/bullet/test_soil_robustness.cpp),
// the long one a benchmark (shore-bench --only reliability).

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <random>
#include <vector>

class btCollisionShape;

namespace shore::scenes {

/// A seeded shape of one of seven types (sphere, box, capsule, cylinder, cone, convex hull,
/// compound), sides 5-25 cm. A compound's children go to `children`, which must outlive
/// the shape.
std::unique_ptr<btCollisionShape> random_body_shape(std::mt19937& rng,
                                                    std::vector<std::unique_ptr<btCollisionShape>>& children);

struct SoakCase {
  int bodies = 50;          ///< on the sand, in rows of ten 0.8 m apart
  int floating_bodies = 0;  ///< of those, the last ones dropped into the pool instead
  bool water = true;        ///< a pool beside the sand (x > 8.5 m), vertical-only, walled
  std::int64_t substeps = 2000;
  double substep = 1.0 / 240;  ///< s
  double cell = 0.04;          ///< m, sand columns (bodies are 10-50 cm)
  int settled_substeps = 480;  ///< rescues after this many substeps count as "after settling"
  /// The warm-up: memory growth is measured after it (the last 90 % by default) and time
  /// per substep from it on; 0: a tenth of the run.
  std::int64_t warm_up_substeps = 0;
  /// Substeps timed at the start (after warm-up) and at the end; 0: min(10,000, a tenth).
  std::int64_t window_substeps = 0;
  /// After settling, every kick_every substeps one body (in turn) is thrown up and sideways
  /// (2 m/s up, 0.3 and 0.2 m/s across, the direction flipping each round so that bodies
  /// hop back and forth about where they lay: a steady workload, not a walk onto new ground), so the soil keeps being
  /// pressed for the whole run; 0: never.
  int kick_every = 240;
  int check_every = 100;  ///< substeps between checks of finiteness, bedrock, memory
  std::uint32_t seed = 20261201;
  std::function<void(std::int64_t substep)> progress;  ///< called at each check (may be empty)
};

struct SoakResult {
  std::int64_t substeps = 0;
  std::int64_t nan_count = 0;  ///< non-finite body poses or velocities, soil or water totals seen at checks
  int fall_throughs = 0;       ///< bodies ever found with their lowest point below bedrock - 2 cm
  std::int64_t rescues = 0;    ///< all rescues (lifted back above bedrock)
  std::int64_t rescues_after_settling = 0;
  std::int64_t lost_bodies = 0;         ///< both couplings' lost_bodies (must stay 0)
  double soil_moved_volume = 0.0;       ///< m^3, |compacted|: what the bodies pressed
  double soil_volume_drift = 0.0;       ///< m^3, |ground + compacted + airborne + lost - edited| (exactly 0 ideally)
  double water_displaced_volume = 0.0;  ///< m^3, what the bodies displaced into the water (signed, coupling's sum)
  double water_volume_drift = 0.0;      ///< m^3, |volume - displaced| of the walled pool (exactly 0 ideally)
  std::size_t soil_memory_warm = 0;     ///< bytes, the soil's own memory at the end of warm-up
  std::size_t soil_memory_max = 0;      ///< bytes, its largest afterwards
  std::size_t soil_tiles_warm = 0, soil_tiles_max = 0;      ///< the soil's tiles then and at most afterwards
  std::size_t water_memory_warm = 0, water_memory_max = 0;  ///< bytes, the same for the water
  std::size_t rss_warm = 0, rss_max = 0;                    ///< bytes, the process's resident memory (0 if unknown)
  double first_window_seconds = 0.0;                        ///< wall time of the first window after warm-up
  double last_window_seconds = 0.0;                         ///< wall time of the last window
  /// s, the median over the window's blocks of 100 substeps of the stepping thread's CPU
  /// time per substep (everything runs on it: one soil and one water thread): a measure of
  /// the work that other processes on a shared machine disturb far less than wall time.
  double first_window_cpu = 0.0;
  double last_window_cpu = 0.0;
  std::int64_t window_substeps = 0;
  std::int64_t warm_up_substeps = 0;
  double wall_seconds = 0.0;
  /// Last window over first, by the median CPU time per substep (see first_window_cpu).
  [[nodiscard]] double slowdown() const { return last_window_cpu / first_window_cpu; }
  /// The same by wall time (disturbed by whatever else runs on the machine).
  [[nodiscard]] double slowdown_wall() const { return last_window_seconds / first_window_seconds; }
  /// Relative growth after warm-up: max / warm - 1.
  [[nodiscard]] static double growth(std::size_t warm, std::size_t max) {
    return warm == 0 ? 0.0 : static_cast<double>(max) / static_cast<double>(warm) - 1.0;
  }
};

SoakResult run_soak(const SoakCase& c);

/// The process's resident set size in bytes (/proc/self/statm), 0 where unknown.
std::size_t resident_bytes();

}  // namespace shore::scenes
