#include "pipeline.h"

#include <omp.h>

#include <algorithm>

namespace shore::terrain {

namespace {

// Soil that displacement or erosion lays onto a column is loose: it lowers the column's
// recorded sinkage by its height, below zero if need be (negative sinkage is loose soil on
// top of the firm level). Loose soil bears nothing: pressing it back down only brings the
// sinkage back to where it was, so
// - a body resting in a crater whose walls keep slumping under it does not pump its sinkage
//   up without end (0.55 m of recorded sinkage under a 0.15 m crater without this rule);
// - soil a rolling wheel pushes ahead of itself and then presses again does not hold the
//   wheel up: how deep a body sinks follows Bekker's law whatever share alpha goes to the rim.
void loosen_deposits(Region& region) {
  for (std::size_t k = 0; k < region.ht.size(); ++k) {
    const double deposit = region.ht[k] - region.ht_pressed[k];
    if (deposit > 0.0) region.sink[k] -= deposit;
  }
}

}  // namespace

void Pipeline::gather(TileStore& store, const TerrainSettings& s, const ColumnRect& region) {
  const int threads = s.threads > 0 ? s.threads : omp_get_max_threads();
  region_.prepare({region.i0 - 1, region.j0 - 1, region.nx + 2, region.ny + 2}, threads, s.parallel_min_columns);
  region_.gather(store, s.material.soil_depth);
}

StepReport Pipeline::run(TileStore& store, const TerrainSettings& s, const ColumnRect& region,
                         std::span<const Imprint> imprints) {
  gather(store, s, region);
  imprint_.rasterize(region_, imprints);
  const ImprintStage::Collision collision = imprint_.collide(region_, s);
  region_.ht_pressed = region_.ht;
  contour_.run(region_, imprint_.flags());
  const double compacted_height = displace_.run(region_, contour_.levels(), imprint_.displaced(), s.material.alpha);
  StepReport report;
  report.erosion_passes = erode_.run(region_, imprint_.flags(), imprint_.body(), s, false);
  loosen_deposits(region_);
  region_.scatter(store);

  const double cell_area = s.cell * s.cell;
  report.active_columns = region.nx * region.ny;
  report.contact_columns = collision.contacts;
  report.displaced_volume = collision.displaced * cell_area;
  report.compacted_volume = compacted_height * cell_area;
  return report;
}

StepReport Pipeline::relax(TileStore& store, const TerrainSettings& s, const ColumnRect& region) {
  gather(store, s, region);
  imprint_.no_bodies(region_);
  StepReport report;
  report.erosion_passes = erode_.run(region_, imprint_.flags(), imprint_.body(), s, true);
  region_.scatter(store);
  report.active_columns = region.nx * region.ny;
  return report;
}

std::size_t Pipeline::bytes() const {
  return region_.bytes() + imprint_.bytes() + contour_.bytes() + displace_.bytes() + erode_.bytes();
}

}  // namespace shore::terrain
