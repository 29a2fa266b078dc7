// spray: what Sumner's particles (shore/terrain/spray.h) cost and how exact their volume
// stays. A driven wheel spinning at 50 % slip (the rooster tail) and the impact scene's
// oblique 8 m/s drop: spray's wall time as a share of the whole step, the peak memory spray
// holds, and the worst |ground + compacted + airborne + lost - edited| over the volume moved
// at any substep (exact conservation is the outside reference).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "shore/scenes/soil_cases.h"
#include "sweep.h"

namespace shore::bench {
namespace {

/// Followed after every substep (untimed): the worst volume error, peaks of memory,
/// particles and airborne volume, and each substep's wall time and spray time.
struct SprayWatch {
  double worst = 0.0, peak_airborne = 0.0;
  std::size_t peak_bytes = 0;
  std::int64_t peak_particles = 0;
  std::vector<double> step_seconds, spray_seconds;
  void attach(scenes::SoilRun& run) {
    run.substep_seconds = &step_seconds;
    run.after_substep = [this](const terrain::Terrain& soil, const bullet::TerrainCoupling&) {
      spray_seconds.push_back(soil.spray_seconds() - spray_so_far);
      spray_so_far = soil.spray_seconds();
      const terrain::VolumeTotals v = soil.volume();
      const terrain::SprayCounts c = soil.spray_counts();
      const double moved = v.compacted + std::abs(v.ground) + c.picked_volume;
      if (moved > 0.0) worst = std::max(worst, std::abs(v.total() - v.edited) / moved);
      peak_airborne = std::max(peak_airborne, v.airborne);
      peak_bytes = std::max(peak_bytes, c.bytes);
      peak_particles = std::max(peak_particles, c.particles);
    };
  }

 private:
  double spray_so_far = 0.0;
};

/// A case run `kRuns` times (the same simulation each time, deterministic): its share is
/// the sum over substeps of the least spray time any run took there over the sum of the
/// least whole-step time. Another program taking the core only ever adds time, to whichever
/// part was running, so the least of a few runs is the cost without it (a single run on a
/// shared machine swings by a few percentage points either way).
struct SprayRow {
  static constexpr int kRuns = 3;
  std::string name;
  scenes::RunStats stats;  ///< of the first run
  SprayWatch watch;        ///< of the first run
  double single_share = 0.0, share = 0.0;
  std::vector<double> least_step, least_spray;

  void add_run(const scenes::RunStats& run_stats, const SprayWatch& run_watch) {
    if (least_step.empty()) {
      stats = run_stats, watch = run_watch;
      single_share = stats.wall_seconds > 0 ? stats.spray_seconds / stats.wall_seconds : 0;
      least_step = watch.step_seconds, least_spray = watch.spray_seconds;
    } else {
      for (std::size_t k = 0; k < least_step.size() && k < run_watch.step_seconds.size(); ++k)
        least_step[k] = std::min(least_step[k], run_watch.step_seconds[k]);
      for (std::size_t k = 0; k < least_spray.size() && k < run_watch.spray_seconds.size(); ++k)
        least_spray[k] = std::min(least_spray[k], run_watch.spray_seconds[k]);
    }
    double step = 0.0, spray = 0.0;
    for (const double x : least_step) step += x;
    for (const double x : least_spray) spray += x;
    share = step > 0 ? spray / step : 0;
  }
};

SprayRow spinning_wheel(double seconds) {
  SprayRow row;
  row.name = "wheel_50pct_slip";
  for (int k = 0; k < SprayRow::kRuns; ++k) {
    scenes::DrivenWheelCase c;
    c.slip = 0.5;
    c.rim_speed = 2.0;
    c.distance = (1.0 - c.slip) * c.rim_speed * seconds;
    SprayWatch watch;
    watch.attach(c.run);
    const scenes::RunStats stats = scenes::run_driven_wheel(c).stats;
    row.add_run(stats, watch);
  }
  return row;
}

SprayRow impact_drop() {
  SprayRow row;
  row.name = "drop_8m_s_oblique";
  for (int k = 0; k < SprayRow::kRuns; ++k) {
    scenes::SphereDropCase c;  // as the impact scene's oblique drop: 8 m/s at impact, 4 m/s of it sideways
    c.vx = 4.0;
    c.height = (64.0 - c.vx * c.vx) / (2.0 * 9.81);
    c.seconds = 1.2;
    SprayWatch watch;
    watch.attach(c.run);
    const scenes::RunStats stats = scenes::run_sphere_drop(c).stats;
    row.add_run(stats, watch);
  }
  return row;
}

void run(const SweepContext& ctx, SweepResult& out) {
  const double wheel_seconds = ctx.quick ? 2.0 : 10.0;
  ctx.progress("spinning wheel at 50 % slip");
  const SprayRow wheel = spinning_wheel(wheel_seconds);
  ctx.progress("oblique 8 m/s drop");
  const SprayRow drop = impact_drop();
  Table& t =
      out.table("spray", {"case", "spray_share_of_step", "spray_share_one_run", "ms_per_substep", "particles_created",
                          "particles_peak", "peak_bytes", "airborne_peak_m3", "volume_error_rel_max"});
  double worst_share = 0.0, worst_error = 0.0;
  for (const SprayRow* r : {&wheel, &drop}) {
    t.add({r->name, r->share, r->single_share, r->stats.ms_per_substep(), double(r->stats.spray.created),
           double(r->watch.peak_particles), double(r->watch.peak_bytes), r->watch.peak_airborne, r->watch.worst});
    worst_share = std::max(worst_share, r->share);
    worst_error = std::max(worst_error, r->watch.worst);
  }
  out.figure("terrain.spray_cost_share", worst_share, "of the whole step (the larger of the wheel and the drop)");
  out.figure("terrain.spray_volume_error", worst_error, "relative to the moved volume, worst substep of both");
  out.figure("terrain.spray_wheel_peak_bytes", double(wheel.watch.peak_bytes),
             "bytes spray holds at its peak, spinning wheel");
  out.target({.key = "terrain.spray_cost_share",
              .what = "spray's wall time over the whole step (Bullet + Shore), least of 3 runs per substep",
              .value = worst_share,
              .op = "<=",
              .threshold = 0.15,
              .unit = ""});
  out.target({.key = "terrain.spray_volume_error",
              .what = "|ground + compacted + airborne + lost - edited| / moved, any substep",
              .value = worst_error,
              .op = "<=",
              .threshold = 1e-12,
              .unit = ""});
  out.note("Spray: a 0.6 m driven wheel (1000 N, 1 cm sand) spinning at 50 % slip with a 2 m/s rim for " +
           std::to_string(wheel_seconds) +
           " s, and a 0.2 m, 10 kg ball hitting 1 cm sand at 8 m/s (4 m/s sideways), each run 3 times. The "
           "share is Terrain::spray_seconds over the wall time of the whole substep, each substep's least of the "
           "3 runs summed (spray_share_one_run: the first run's plain ratio).");
}

const SweepRegistrar kRegistered{Sweep{
    .name = "spray",
    .description = "spray: cost share of the step, peak memory and volume error (wheel at 50 % slip, 8 m/s drop)",
    .run = run,
}};

}  // namespace
}  // namespace shore::bench
