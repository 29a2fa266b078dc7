// Floating bodies on a 256 x 256 water grid: what the coupling costs per substep for 1, 16
// and 64 boxes, apart from the water's own step, and how well they float (Archimedes).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "shore/scenes/pool_cases.h"
#include "sweep.h"

namespace shore::bench {
namespace {

scenes::PoolRun floaters_run(int count, bool quick) {
  scenes::PoolRun run;
  run.pool.nodes = 256;  // 12.8 m at 5 cm
  run.pool.damping_time = 1.0;
  run.seconds = quick ? 1.5 : 3.0;
  run.record_every = 1000000;  // no per-substep records: only the timings and the drafts
  const int side = int(std::ceil(std::sqrt(double(count))));
  for (int k = 0; k < count; ++k) {
    scenes::Floater f;
    f.size = btVector3(0.3f, 0.3f, 0.2f);
    f.density_ratio = 0.5;
    // Spread over the pool, resting at their Archimedes level, off the water nodes.
    f.position = btVector3(btScalar(-5.0 + 10.0 * ((k % side) + 0.5) / side + 0.013),
                           btScalar(-5.0 + 10.0 * ((k / side) + 0.5) / side - 0.021), 0.0f);
    run.floaters.push_back(f);
  }
  return run;
}

void run(const SweepContext& ctx, SweepResult& out) {
  Table& t =
      out.table("floaters_256", {"boxes", "coupling_ms_per_substep", "water_ms_per_substep", "draft_error_rel_max"});
  for (int count : {1, 16, 64}) {
    ctx.progress(std::to_string(count) + " floating boxes on 256 x 256 water");
    const scenes::PoolRun pool_run = floaters_run(count, ctx.quick);
    const scenes::PoolResult r = scenes::run_pool(pool_run);
    double worst = 0.0;
    for (std::size_t n = 0; n < r.final_draft.size(); ++n) {
      const double ref = scenes::archimedes_draft(pool_run.floaters[n]);
      worst = std::max(worst, std::abs(r.final_draft[n] - ref) / ref);
    }
    const double coupling_ms = 1e3 * r.coupling_seconds / double(r.substeps);
    const double water_ms = 1e3 * r.water_seconds / double(r.substeps);
    t.add({double(count), coupling_ms, water_ms, worst});
    out.figure("coupling.floaters_" + std::to_string(count) + "_coupling_ms_per_substep", coupling_ms, "ms");
    out.figure("coupling.floaters_" + std::to_string(count) + "_draft_error_rel", worst, "1");
  }
  out.note(
      "floaters: boxes 0.3 x 0.3 x 0.2 m of density 0.5 on a 256 x 256 vertical-only surface (5 cm, "
      "0.5 m deep) at 1/240 s substeps; coupling = envelopes, buoyancy, drag and displacement; water = "
      "the surface's own step; draft error against Archimedes over the last second.");
}

const SweepRegistrar kRegistered{
    {.name = "floaters", .description = "coupling cost for 1, 16, 64 floating boxes on 256^2 water", .run = run}};

}  // namespace
}  // namespace shore::bench
