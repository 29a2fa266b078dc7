// Floating bodies on a 256 x 256 water grid: what the coupling costs per body and substep
// for 1 to 256 boxes and for 64 convex hulls, apart from the water's own step, and how well
// they float (Archimedes' draft). One thread.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "shore/scenes/pool_cases.h"
#include "sweep.h"

namespace shore::bench {
namespace {

scenes::PoolRun floaters_run(scenes::FloaterShape shape, int count, bool quick) {
  scenes::PoolRun run;
  run.pool.nodes = 256;  // 12.8 m at 5 cm
  run.pool.damping_time = 1.0;
  run.seconds = quick ? 2.0 : 4.0;
  run.record_every = 1000000;  // no per-substep records: only the timings and the drafts
  const int side = int(std::ceil(std::sqrt(double(count))));
  for (int k = 0; k < count; ++k) {
    scenes::Floater f;
    f.shape = shape;
    f.size = btVector3(0.3f, 0.3f, 0.2f);
    f.density_ratio = 0.5;
    // Spread over the pool, resting at their Archimedes level, off the water nodes.
    f.position = btVector3(btScalar(-5.6 + 11.2 * ((k % side) + 0.5) / side + 0.013),
                           btScalar(-5.6 + 11.2 * ((k / side) + 0.5) / side - 0.021), 0.0f);
    run.floaters.push_back(f);
  }
  return run;
}

struct FloatersRow {
  double coupling_us_per_body = 0.0, water_ms = 0.0, total_ms = 0.0, draft_error = 0.0;
};

FloatersRow run_floaters(scenes::FloaterShape shape, int count, bool quick) {
  const scenes::PoolRun pool_run = floaters_run(shape, count, quick);
  const scenes::PoolResult r = scenes::run_pool(pool_run);
  FloatersRow row;
  for (std::size_t n = 0; n < r.final_draft.size(); ++n) {
    const double ref = scenes::archimedes_draft(pool_run.floaters[n]);
    row.draft_error = std::max(row.draft_error, std::abs(r.final_draft[n] - ref) / ref);
  }
  const double substeps = double(std::max<std::int64_t>(r.substeps, 1));
  row.coupling_us_per_body = 1e6 * r.coupling_seconds / substeps / count;
  row.water_ms = 1e3 * r.water_seconds / substeps;
  row.total_ms = 1e3 * (r.coupling_seconds + r.water_seconds) / substeps;
  return row;
}

void run(const SweepContext& ctx, SweepResult& out) {
  Table& t = out.table("floaters_256", {"shape", "bodies", "coupling_us_per_body", "coupling_ms_per_substep",
                                        "water_ms_per_substep", "total_ms_per_substep", "draft_error_rel_max"});
  struct Case {
    scenes::FloaterShape shape;
    const char* name;
    int count;
  };
  const std::vector<Case> cases = {{scenes::FloaterShape::box, "box", 1},
                                   {scenes::FloaterShape::box, "box", 16},
                                   {scenes::FloaterShape::box, "box", 64},
                                   {scenes::FloaterShape::box, "box", 256},
                                   {scenes::FloaterShape::hull, "hull", 64}};
  const auto at_most = [&](const char* key, const char* what, double value, double threshold, const char* unit) {
    out.target({.key = key, .what = what, .value = value, .op = "<=", .threshold = threshold, .unit = unit});
  };
  for (const Case& c : cases) {
    ctx.progress(std::to_string(c.count) + " floating " + (c.shape == scenes::FloaterShape::box ? "box" : "hull") +
                 (c.count > 1 ? (c.shape == scenes::FloaterShape::box ? "es" : "s") : "") + " on 256 x 256 water");
    const FloatersRow r = run_floaters(c.shape, c.count, ctx.quick);
    t.add({std::string(c.name), double(c.count), r.coupling_us_per_body, 1e-3 * r.coupling_us_per_body * c.count,
           r.water_ms, r.total_ms, r.draft_error});
    const std::string key =
        std::string(c.name == std::string("box") ? "floaters_" : "hulls_") + std::to_string(c.count);
    out.figure("coupling." + key + "_coupling_us_per_body", r.coupling_us_per_body, "us per body and substep");
    out.figure("coupling." + key + "_draft_error_rel", r.draft_error, "1 (worst body, against Archimedes)");
    if (c.shape == scenes::FloaterShape::box && c.count == 64) {
      out.figure("coupling.floater_us_per_body", r.coupling_us_per_body, "us per box and substep (64 boxes, 1 thread)");
      at_most("coupling.floater_us_per_body", "coupling cost per floating box (64 boxes on 256^2 water)",
              r.coupling_us_per_body, 5.0, "us/substep");
      at_most("coupling.floaters_64_draft_error_rel", "draft of 64 resting boxes against Archimedes", r.draft_error,
              1e-3, "");
    }
    if (c.shape == scenes::FloaterShape::hull) {
      out.figure("coupling.hull_us_per_body", r.coupling_us_per_body, "us per hull and substep (64 octagonal prisms)");
      at_most("coupling.hull_us_per_body", "coupling cost per floating convex hull (64 on 256^2 water)",
              r.coupling_us_per_body, 10.0, "us/substep");
    }
    if (c.count == 256) {
      out.figure("coupling.floaters_256_ms_per_substep", r.total_ms, "ms (coupling + water step, 256 boxes, 256^2)");
      at_most("coupling.floaters_256_ms_per_substep", "256 floating boxes on 256^2 water, coupling and water step",
              r.total_ms, 2.0, "ms/substep");
    }
  }
  out.note(
      "floaters: boxes 0.3 x 0.3 x 0.2 m (and octagonal prisms as convex hulls of 16 points, 0.3 m across, 0.2 m "
      "high) of density 0.5, released at rest at their Archimedes level over a 256 x 256 vertical-only surface "
      "(5 cm, 0.5 m deep, walls) at 1/240 s substeps, one thread. coupling = water plane fit, exact submerged part, "
      "buoyancy, drag and displacement per body; water = the surface's own step (sleeping tiles where the water "
      "is still); draft error against Archimedes, mean over the last second, worst body.");
}

const SweepRegistrar kRegistered{{.name = "floaters",
                                  .description = "coupling cost per body for 1 to 256 floating boxes and 64 hulls on "
                                                 "256^2 water",
                                  .run = run}};

}  // namespace
}  // namespace shore::bench
