// spray: what Sumner's particles (shore/terrain/spray.h) cost and how exact their volume
// stays. A driven wheel spinning at 50 % slip (the rooster tail) and the impact scene's
// oblique 8 m/s drop: spray's wall time as a share of the whole step, the peak memory spray
// holds, and the worst |ground + compacted + airborne + lost - edited| over the volume moved
// at any substep (exact conservation is the outside reference).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

#include "shore/scenes/soil_cases.h"
#include "sweep.h"

namespace shore::bench {
namespace {

/// Followed after every substep (untimed): the worst volume error, peaks of memory,
/// particles and airborne volume.
struct SprayWatch {
  double worst = 0.0, peak_airborne = 0.0;
  std::size_t peak_bytes = 0;
  std::int64_t peak_particles = 0;
  void attach(scenes::SoilRun& run) {
    run.after_substep = [this](const terrain::Terrain& soil, const bullet::TerrainCoupling&) {
      const terrain::VolumeTotals v = soil.volume();
      const terrain::SprayCounts c = soil.spray_counts();
      const double moved = v.compacted + std::abs(v.ground) + c.picked_volume;
      if (moved > 0.0) worst = std::max(worst, std::abs(v.total() - v.edited) / moved);
      peak_airborne = std::max(peak_airborne, v.airborne);
      peak_bytes = std::max(peak_bytes, c.bytes);
      peak_particles = std::max(peak_particles, c.particles);
    };
  }
};

struct SprayRow {
  std::string name;
  scenes::RunStats stats;
  SprayWatch watch;
  [[nodiscard]] double share() const { return stats.wall_seconds > 0 ? stats.spray_seconds / stats.wall_seconds : 0; }
};

SprayRow spinning_wheel(double seconds) {
  SprayRow row{.name = "wheel_50pct_slip", .stats = {}, .watch = {}};
  scenes::DrivenWheelCase c;
  c.slip = 0.5;
  c.rim_speed = 2.0;
  c.distance = (1.0 - c.slip) * c.rim_speed * seconds;
  row.watch.attach(c.run);
  row.stats = scenes::run_driven_wheel(c).stats;
  return row;
}

SprayRow impact_drop() {
  SprayRow row{.name = "drop_8m_s_oblique", .stats = {}, .watch = {}};
  scenes::SphereDropCase c;  // as the impact scene's oblique drop: 8 m/s at impact, 4 m/s of it sideways
  c.vx = 4.0;
  c.height = (64.0 - c.vx * c.vx) / (2.0 * 9.81);
  c.seconds = 1.2;
  row.watch.attach(c.run);
  row.stats = scenes::run_sphere_drop(c).stats;
  return row;
}

void run(const SweepContext& ctx, SweepResult& out) {
  const double wheel_seconds = ctx.quick ? 2.0 : 10.0;
  ctx.progress("spinning wheel at 50 % slip");
  const SprayRow wheel = spinning_wheel(wheel_seconds);
  ctx.progress("oblique 8 m/s drop");
  const SprayRow drop = impact_drop();
  Table& t = out.table("spray", {"case", "spray_share_of_step", "ms_per_substep", "particles_created", "particles_peak",
                                 "peak_bytes", "airborne_peak_m3", "volume_error_rel_max"});
  double worst_share = 0.0, worst_error = 0.0;
  for (const SprayRow* r : {&wheel, &drop}) {
    t.add({r->name, r->share(), r->stats.ms_per_substep(), double(r->stats.spray.created),
           double(r->watch.peak_particles), double(r->watch.peak_bytes), r->watch.peak_airborne, r->watch.worst});
    worst_share = std::max(worst_share, r->share());
    worst_error = std::max(worst_error, r->watch.worst);
  }
  out.figure("terrain.spray_cost_share", worst_share, "of the whole step (the larger of the wheel and the drop)");
  out.figure("terrain.spray_volume_error", worst_error, "relative to the moved volume, worst substep of both");
  out.figure("terrain.spray_wheel_peak_bytes", double(wheel.watch.peak_bytes),
             "bytes spray holds at its peak, spinning wheel");
  out.target({.key = "terrain.spray_cost_share",
              .what = "spray's wall time over the whole step (Bullet + Shore)",
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
           " s, and a 0.2 m, 10 kg ball hitting 1 cm sand at 8 m/s (4 m/s sideways). The share is "
           "Terrain::spray_seconds over the wall time of the whole substep.");
}

const SweepRegistrar kRegistered{Sweep{
    .name = "spray",
    .description = "spray: cost share of the step, peak memory and volume error (wheel at 50 % slip, 8 m/s drop)",
    .run = run,
}};

}  // namespace
}  // namespace shore::bench
