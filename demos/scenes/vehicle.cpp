// vehicle: the four-wheel vehicle of shore::cases::run_vehicle (a 400 kg chassis on four
// motorised 0.6 m wheels) drives from rigid ground across a sand strip, then a mud strip,
// then rigid ground again. Two Terrain objects lie side by side, each with its own
// coupling and region. The pictures show both soils' ruts: sand slumps into wide, shallow
// ruts with low rims, mud keeps steep walls and higher rims.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "shore/cases/vehicle_case.h"
#include "shore/demo/mesh.h"
#include "shore/demo/render.h"
#include "shore/demo/scene.h"
#include "soil_scene_util.h"

namespace shore::demo {
namespace {

using namespace soil_scene;

constexpr double kHalfWidth = 1.1;  // m, half width of the pictured strip (wheels at +-0.65 m)

std::vector<Patch> patches_of(const std::vector<std::shared_ptr<terrain::Terrain>>& soils, double x0, double x1,
                              double x2) {
  return {{soils[0].get(), {x0, -5.0, x1, 5.0}}, {soils[1].get(), {x1, -5.0, x2, 5.0}}};
}

std::vector<const btCollisionObject*> objects_of(const cases::VehicleFrame& f) {
  std::vector<const btCollisionObject*> out = {f.chassis};
  for (const btRigidBody* w : f.wheels) out.push_back(w);
  return out;
}

SceneResult run(const SceneOptions& o, Progress& progress) {
  cases::VehicleCase c;
  c.cell = o.cell;
  c.substep = o.substep;
  c.threads = o.threads;
  c.seconds = o.seconds;
  if (o.smoke) {  // a short drive over one tile of each soil
    c.start_x = -1.2;
    c.sand_tiles = 1;
    c.mud_tiles = 1;
  }
  const double tile = 64 * c.cell;  // the case's tiles are 64 cells
  const double sand_x0 = 0.0, sand_x1 = c.sand_tiles * tile, mud_x1 = sand_x1 + c.mud_tiles * tile;
  // From the start on rigid ground to past the mud, where a 6 s drive ends.
  const HeightGrid frame =
      grid_over(c.start_x - 1.2, -kHalfWidth, o.smoke ? mud_x1 + 0.4 : mud_x1 + 2.8, kHalfWidth, c.cell);
  // A close view across the sand-mud edge.
  const HeightGrid edge = grid_over(sand_x1 - 1.2, -kHalfWidth, sand_x1 + 1.2, kHalfWidth, c.cell);
  const HeightGrid baseline(frame.nx, frame.ny, frame.cell, frame.x0, frame.y0, 0.0);  // every ground starts at 0

  const int frames = o.smoke ? 3 : 6;
  std::vector<Image> film;
  std::vector<std::string> labels;
  HeightGrid final_heights;
  BodyEnvelopes final_bodies;
  long body_nan = 0;
  int next_frame = 0;  // frame q is taken at substep round(n q / (frames - 1)), the first after substep 1
  auto on_substep = [&](const cases::VehicleFrame& f) {
    progress.update(double(f.substep) / double(f.substeps));
    const bool last = f.substep == f.substeps;
    const bool film_frame = o.write_files && next_frame < frames &&
                            f.substep >= std::lround(double(f.substeps) * double(next_frame) / double(frames - 1));
    if (!last && !film_frame) return;
    const HeightGrid heights = sample(patches_of(*f.soils, sand_x0, sand_x1, mud_x1), frame, Field::height);
    if (film_frame) {
      const BodyEnvelopes env = body_envelopes(objects_of(f), frame);
      film.push_back(oblique_frame(heights, baseline, &env, 2.0, o.smoke ? 160 : 480, ""));
      labels.push_back(time_label(f.time));
      ++next_frame;
    }
    if (last) {
      final_heights = heights;
      if (o.write_files) final_bodies = body_envelopes(objects_of(f), frame);
      std::vector<const btRigidBody*> bodies = {f.chassis};
      for (const btRigidBody* w : f.wheels) bodies.push_back(w);
      body_nan = non_finite_bodies(bodies);
    }
  };
  const cases::VehicleResult res = cases::run_vehicle(c, on_substep);

  const std::vector<Patch> patches = patches_of(res.soils, sand_x0, sand_x1, mud_x1);
  const HeightGrid sinkage = sample(patches, frame, Field::sinkage);
  const double drift_sand = volume_drift_rel(*res.soils[0]), drift_mud = volume_drift_rel(*res.soils[1]);

  SceneResult r;
  r.state_hash = res.stats.state_hash;
  const long nan_count = res.nan_count + body_nan + final_heights.non_finite_count();
  r.metrics = common_metrics("vehicle", o, static_cast<int>(res.stats.substeps), res.stats.wall_seconds, r.state_hash,
                             nan_count);
  r.metrics["fallthrough_count"] = res.fallthrough_count;
  r.metrics["volume_drift_rel"] = std::max(drift_sand, drift_mud);
  r.metrics["volume_drift_rel_sand"] = drift_sand;
  r.metrics["volume_drift_rel_mud"] = drift_mud;
  r.metrics["max_sinkage_m"] = max_of(sinkage);
  r.metrics["deepest_m"] = max_lowering(baseline, final_heights);
  r.metrics["mean_speed_sand_mps"] = res.mean_speed_sand;
  r.metrics["mean_speed_mud_mps"] = res.mean_speed_mud;
  r.metrics["target_speed_mps"] = c.target_speed;
  r.metrics["distance_m"] = res.distance;
  r.metrics["plugin_ms_per_substep"] = res.stats.plugin_ms_per_substep();
  r.metrics["note"] = "the vehicle always crosses sand then mud; --material does not apply";

  if (o.write_files) {
    ReliefStyle top;
    top.baseline = &baseline;
    top.bodies = &final_bodies.top;
    top.body_bottoms = &final_bodies.bottom;
    top.min_pixels = o.smoke ? 240 : 1200;
    top.title = "vehicle: rigid | sand | mud | rigid, ground coloured by deformation";
    r.files.push_back(write_png(o.file("top.png"), render_relief(final_heights, top)));
    r.files.push_back(
        write_png(o.file("view.png"), oblique_frame(final_heights, baseline, &final_bodies, 2.0, o.smoke ? 240 : 1400,
                                                    "vehicle across sand then mud (heights x2)", 0.0, 40.0, true)));
    const HeightGrid edge_heights = sample(patches, edge, Field::height);
    const HeightGrid edge_base(edge.nx, edge.ny, edge.cell, edge.x0, edge.y0, 0.0);
    r.files.push_back(
        write_png(o.file("ruts.png"), oblique_frame(edge_heights, edge_base, nullptr, 2.0, o.smoke ? 240 : 900,
                                                    "ruts: sand (left) to mud (right), heights x2", 0.0, 45.0, true)));
    r.files.push_back(write_png(o.file("filmstrip.png"), filmstrip(film, labels, 3)));
    r.files.push_back(write_obj(o.file("ground.obj"), final_heights));
  }
  return r;
}

const SceneRegistrar kRegistered{Scene{
    .name = "vehicle",
    .description =
        "A four-wheel vehicle (400 kg chassis, four 0.6 m wheels on hinge motors aiming at 2 m/s) drives from rigid "
        "ground across a strip of sand, then a strip of mud, then rigid ground: two Terrain objects side by side, each "
        "with its own coupling and region. Look at the ruts: sand slumps to its angle of repose (wide, shallow ruts, "
        "low rims), mud keeps steep walls and pushes more soil into the rims. The vehicle slows on both soils.",
    .defaults = {.seconds = 6.0, .substep = 1.0 / 240.0, .material = "sand", .cell = 0.02, .smoke_seconds = 1.0},
    .metric_help =
        {
            {"fallthrough_count", "wheels below bedrock at the end or lifted back by the coupling (must be 0)"},
            {"volume_drift_rel", "largest of the two soils' volume drift (must be < 1e-6)"},
            {"volume_drift_rel_sand", "|ground + compacted - edited| / moved volume of the sand"},
            {"volume_drift_rel_mud", "the same for the mud"},
            {"max_sinkage_m", "largest plastic sinkage in either soil, m"},
            {"deepest_m", "largest lowering of the ground below the untouched surface, m"},
            {"mean_speed_sand_mps", "chassis speed averaged over its time above the sand, m/s"},
            {"mean_speed_mud_mps", "chassis speed averaged over its time above the mud, m/s"},
            {"target_speed_mps", "speed the wheel motors aim for, m/s"},
            {"distance_m", "distance the chassis travelled, m"},
            {"plugin_ms_per_substep", "Shore's share of a substep (both soils), ms"},
            {"note", "what --material means here"},
        },
    .run = run,
}};

}  // namespace
}  // namespace shore::demo
