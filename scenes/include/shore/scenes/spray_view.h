#pragma once
// Spray as the soil scenes see it: what their soils threw, followed over the run for the
// metrics (SprayMeter). (The pictures draw the particles in flight from the soils.)

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "shore/scenes/scene.h"
#include "shore/scenes/soil_view.h"
#include "shore/terrain/terrain.h"

namespace shore::scenes {

/// Follows the spray of some soils after every substep (Scene::observe) and reports it.
class SprayMeter {
 public:
  explicit SprayMeter(std::vector<const terrain::Terrain*> soils) : soils_(std::move(soils)) {}
  void observe();
  /// Adds the spray_* metrics (spray_metric_help) to a scene's metrics.
  void report(nlohmann::json& metrics) const;

 private:
  std::vector<const terrain::Terrain*> soils_;
  long peak_particles_ = 0;
  double peak_airborne_ = 0.0;  // m^3, all soils together
  double worst_error_ = 0.0;    // largest |ground + compacted + airborne + lost - edited| / moved of a soil
};

/// What the spray_* metrics mean.
const std::vector<MetricHelp>& spray_metric_help();
/// A soil scene's own metric help followed by the spray_* metrics'.
std::vector<MetricHelp> with_spray_metrics(std::vector<MetricHelp> own);

}  // namespace shore::scenes
