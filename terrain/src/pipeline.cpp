#include "pipeline.h"

#include <algorithm>
#include <chrono>
#include <thread>

#include "capacity_bytes.h"

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

int thread_count(const TerrainSettings& s) {
  // hardware_concurrency reads the system's CPU list each call: once is enough.
  static const int hardware = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  return s.threads > 0 ? s.threads : hardware;
}

/// Whether the pacer judges a region of `columns` (halo included): more than one thread, at
/// least parallel_min_columns, and not forced (parallel_min_columns 0 always forks).
bool paced(const TerrainSettings& s, std::int64_t columns) {
  return thread_count(s) > 1 && s.parallel_min_columns > 0 && columns >= s.parallel_min_columns;
}

std::int64_t halo_columns(const GridRect& region) {
  return static_cast<std::int64_t>(region.nx + 2) * static_cast<std::int64_t>(region.ny + 2);
}

using Clock = std::chrono::steady_clock;

}  // namespace

void Pipeline::gather(TileStore& store, const TerrainSettings& s, std::span<const Material> palette,
                      const GridRect& region) {
  const int threads = thread_count(s);
  const std::int64_t columns = halo_columns(region);
  const bool parallel =
      threads > 1 && columns >= s.parallel_min_columns && (s.parallel_min_columns == 0 || pacer_.choose_parallel());
  if (parallel && (!team_ || team_->size() != threads)) team_ = std::make_unique<Team>(threads);
  region_.prepare({region.i0 - 1, region.j0 - 1, region.nx + 2, region.ny + 2}, parallel ? team_.get() : nullptr);
  // One material: no map to read, every stage takes its one-material path; no layer: no
  // layers to read.
  const bool layered = store.layered();
  region_.gather(store, BedrockDepth(palette, s.material.soil_depth), palette.size() > 1 || layered, layered);
}

void Pipeline::record(const TerrainSettings& s, std::int64_t columns, double seconds) {
  if (paced(s, columns)) pacer_.record(region_.team != nullptr, seconds / static_cast<double>(columns));
}

StepReport Pipeline::run(TileStore& store, const TerrainSettings& s, std::span<const Material> palette,
                         const GridRect& region, std::span<const Imprint> imprints) {
  const Clock::time_point t0 = Clock::now();
  gather(store, s, palette, region);
  imprint_.rasterize(region_, imprints);
  const ImprintStage::Collision collision = imprint_.collide(region_, s);  // sets region_.ht_pressed
  contour_.run(region_, imprint_.flags());
  alpha_.clear();
  for (const Material& m : palette) alpha_.push_back(m.alpha);
  const double compacted_height =
      displace_.run(region_, contour_.levels(), contour_.closed(), imprint_.displaced(), alpha_);
  StepReport report;
  report.erosion_passes = erode_.run(region_, imprint_.flags(), imprint_.body(), s, palette, false, true);
  loosen_deposits(region_);
  erode_.settle_layers(region_);  // the boundaries of the layers erosion changed, from the loosened sinkage
  region_.scatter(store);
  record(s, halo_columns(region), std::chrono::duration<double>(Clock::now() - t0).count());

  const double cell_area = s.cell * s.cell;
  report.active_columns = region.nx * region.ny;
  report.contact_columns = collision.contacts;
  report.displaced_volume = collision.displaced * cell_area;
  report.compacted_volume = compacted_height * cell_area;
  return report;
}

StepReport Pipeline::relax(TileStore& store, const TerrainSettings& s, std::span<const Material> palette,
                           const GridRect& region) {
  const Clock::time_point t0 = Clock::now();
  gather(store, s, palette, region);
  imprint_.no_bodies(region_);
  StepReport report;
  report.erosion_passes = erode_.run(region_, imprint_.flags(), imprint_.body(), s, palette, true);
  erode_.settle_layers(region_);
  region_.scatter(store);
  record(s, halo_columns(region), std::chrono::duration<double>(Clock::now() - t0).count());
  report.active_columns = region.nx * region.ny;
  return report;
}

std::size_t Pipeline::bytes() const {
  return region_.bytes() + capacity_bytes(alpha_) + imprint_.bytes() + contour_.bytes() + displace_.bytes() +
         erode_.bytes();
}

}  // namespace shore::terrain
