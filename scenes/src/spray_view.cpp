#include "shore/scenes/spray_view.h"

#include <algorithm>
#include <cmath>

namespace shore::scenes {

void SprayMeter::observe() {
  long particles = 0;
  double airborne = 0.0;
  for (const terrain::Terrain* soil : soils_) {
    const terrain::VolumeTotals v = soil->volume();
    const terrain::SprayCounts c = soil->spray_counts();
    particles += static_cast<long>(c.particles);
    airborne += v.airborne;
    const double moved = v.compacted + std::abs(v.ground) + c.picked_volume;
    if (moved > 0.0) worst_error_ = std::max(worst_error_, std::abs(v.total() - v.edited) / moved);
  }
  peak_particles_ = std::max(peak_particles_, particles);
  peak_airborne_ = std::max(peak_airborne_, airborne);
}

void SprayMeter::report(nlohmann::json& m) const {
  terrain::SprayCounts sum;
  double lost = 0.0;
  for (const terrain::Terrain* soil : soils_) {
    const terrain::SprayCounts c = soil->spray_counts();
    sum.created += c.created, sum.landed += c.landed, sum.lost += c.lost, sum.clumps += c.clumps;
    sum.limited += c.limited, sum.particles += c.particles, sum.picked_volume += c.picked_volume;
    lost += soil->volume().lost;
  }
  m["spray_particles_created"] = sum.created;
  m["spray_particles_landed"] = sum.landed;
  m["spray_particles_peak"] = peak_particles_;
  m["spray_particles_in_flight"] = sum.particles;
  m["spray_clumps"] = sum.clumps;
  m["spray_limited"] = sum.limited;
  m["spray_picked_m3"] = sum.picked_volume;
  m["spray_airborne_peak_m3"] = peak_airborne_;
  m["spray_lost_m3"] = lost;
  m["spray_particles_lost"] = sum.lost;
  m["spray_volume_error_rel_max"] = worst_error_;
}

const std::vector<MetricHelp>& spray_metric_help() {
  static const std::vector<MetricHelp> help{
      {"spray_particles_created", "spray particles thrown by the bodies (Sumner's particles), in all"},
      {"spray_particles_landed", "of them, landed on a column (their volume added there)"},
      {"spray_particles_peak", "most particles in flight at once"},
      {"spray_particles_in_flight", "particles still in flight at the end"},
      {"spray_clumps", "shed soil too slow to fly (Sumner's speed test), dropped onto the column below"},
      {"spray_limited", "particles laid at once because the particle limit was reached"},
      {"spray_picked_m3", "soil the bodies carried away from the ground, m^3"},
      {"spray_airborne_peak_m3", "largest volume off the ground at once (in flight or clinging to bodies), m^3"},
      {"spray_lost_m3", "spray that left its soil's region or the world, m^3 (counted apart, never dropped)"},
      {"spray_particles_lost", "particles that left their soil's region or the world"},
      {"spray_volume_error_rel_max",
       "largest |ground + compacted + airborne + lost - edited| over the volume moved, any soil, any substep"},
  };
  return help;
}

std::vector<MetricHelp> with_spray_metrics(std::vector<MetricHelp> own) {
  const std::vector<MetricHelp>& spray = spray_metric_help();
  own.insert(own.end(), spray.begin(), spray.end());
  return own;
}

}  // namespace shore::scenes
