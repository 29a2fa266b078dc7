// terrain_threads: the soil step on 1 thread against 2 on a loaded machine, for rollers of
// growing width (active regions from about a thousand columns, below parallel_min_columns,
// to about 160,000). No environment variable is set: the soil's rows run on Shore's own
// team (shore/core/team.h), which sleeps when idle, and the pipeline forks only above
// parallel_min_columns and while its pacer measures parallel steps faster.
#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

#include "loaded_pair.h"
#include "shore/core/envelope.h"
#include "shore/scenes/terrain_step_cases.h"
#include "shore/terrain/terrain.h"
#include "sweep.h"

namespace shore::bench {
namespace {

constexpr double kCell = 0.01, kRadius = 0.4, kSinkage = 0.03, kSpeed = 1.0, kSubstep = 1.0 / 240;

/// A cylinder `width` wide (axis along y) towed through dry sand, one Terrain::step a call.
class Roller {
 public:
  Roller(double width, int threads) : width_(width), terrain_(settings(threads)) {}

  void step() {
    const double x = kSpeed * kSubstep * static_cast<double>(steps_);
    const EnvelopeRaster env = scenes::wheel_envelope(terrain_, x, kRadius - kSinkage, kRadius, width_, kRadius);
    terrain::Imprint im{&env, 0.0, true, {kSpeed, 0.0, 0.0}};
    im.spray = false;  // the pipeline's rows are what forks; spray is measured by its own sweep
    const terrain::StepReport r = terrain_.step({&im, 1});
    columns_ += r.active_columns;
    ++steps_;
  }
  /// Steps until `steps` have been taken in all.
  void step_to(long steps) {
    while (steps_ < steps) step();
  }
  [[nodiscard]] long steps() const { return steps_; }
  [[nodiscard]] double mean_active_columns() const { return steps_ ? columns_ / static_cast<double>(steps_) : 0.0; }
  [[nodiscard]] std::uint64_t hash() const { return terrain_.state_hash(); }

 private:
  static terrain::TerrainSettings settings(int threads) {
    terrain::TerrainSettings s;  // parallel_min_columns at its default
    s.cell = kCell;
    s.material = terrain::Material::sand();
    s.threads = threads;
    return s;
  }

  double width_;
  terrain::Terrain terrain_;
  long steps_ = 0;
  double columns_ = 0.0;
};

void run(const SweepContext& ctx, SweepResult& out) {
  Table& t = out.table("terrain_threads", {"roller_width_m", "active_columns", "load_threads", "ms_per_step_1t",
                                           "ms_per_step_2t", "speed_2t_over_1t", "same_state"});
  const std::vector<double> widths =
      ctx.quick ? std::vector<double>{0.2, 3.2, 12.8} : std::vector<double>{0.2, 0.8, 1.6, 3.2, 6.4, 12.8, 25.6};
  const int load = busy_load_threads();
  const char* policy = std::getenv("OMP_WAIT_POLICY");
  double worst = 1e300;
  bool all_same = true;
  for (double w : widths) {
    ctx.progress("soil roller " + std::to_string(w).substr(0, 4) + " m wide: 1 vs 2 threads under load");
    Roller one(w, 1), two(w, 2);
    for (int k = 0; k < 20; ++k) {  // past the first bite, and the pacer's first measures
      one.step();
      two.step();
    }
    PairTiming p;
    {
      const BusyLoad busy(load);
      p = time_alternating([&] { one.step(); }, [&] { two.step(); }, ctx.quick ? 0.05 : 0.1, ctx.quick ? 11 : 21);
    }
    // The same steps give the same bits, whichever ran on how many threads.
    const long n = std::max(one.steps(), two.steps());
    one.step_to(n);
    two.step_to(n);
    const bool same = one.hash() == two.hash();
    all_same = all_same && same;
    t.add({w, one.mean_active_columns(), double(load), 1e3 * p.s_per_step_1, 1e3 * p.s_per_step_2, p.speed_2_over_1,
           same ? 1.0 : 0.0});
    worst = std::min(worst, p.speed_2_over_1);
  }
  out.figure("terrain.threads2_vs_1_min_speedup", worst,
             std::string("x, worst roller width, 2 threads over 1 on a machine loaded by busy threads "
                         "(OMP_WAIT_POLICY ") +
                 (policy ? std::string("= ") + policy : std::string("unset")) + ")");
  out.target({.key = "terrain.threads2_vs_1_min_speedup",
              .what = "soil step: 2 threads at least 0.9 x the speed of 1 at every size, loaded machine",
              .value = worst,
              .op = ">=",
              .threshold = 0.9,
              .unit = "x"});
  out.figure("terrain.threads_same_state", all_same ? 1.0 : 0.0, "1 if 1 and 2 threads gave the same state hash");
  out.target({.key = "terrain.threads_same_state",
              .what = "1 and 2 threads give bit-identical soil",
              .value = all_same ? 1.0 : 0.0,
              .op = ">=",
              .threshold = 1.0,
              .unit = ""});
  out.plot({.name = "terrain_threads_speedup",
            .title = "Soil step, 2 threads over 1 on a loaded machine",
            .table = "terrain_threads",
            .x = "active_columns",
            .y = "speed_2t_over_1t",
            .series = "",
            .x_label = "active columns per step (halo excluded)",
            .y_label = "speed, 2 threads / 1 thread",
            .log_y = false});
  out.note(std::string("Soil threads: a D 0.8 m cylinder, 3 cm deep, towed at 1 m/s through dry sand at 1 cm, 1/240 "
                       "s, spray off, of widths 0.2 to 25.6 m (active regions below and far above "
                       "parallel_min_columns = 16384, halo included); Terrain::step timed in short slices alternating "
                       "1 and 2 threads while busy threads load every core; speed = the median of the ratio of "
                       "adjacent slices; same_state: both terrains brought to the same step count give the same "
                       "state hash. No OpenMP (OMP_WAIT_POLICY ") +
           (policy ? std::string("was ") + policy : std::string("was unset")) +
           " in this run): the rows run on the pipeline's team, a region forks above parallel_min_columns and "
           "while its pacer measures parallel steps faster per column.");
}

const SweepRegistrar kRegistered{Sweep{
    .name = "terrain_threads",
    .description = "soil step, 1 against 2 threads on a machine loaded by busy threads, rollers of growing width",
    .run = run,
}};

}  // namespace
}  // namespace shore::bench
