// beach: sand sloping down into water. A light ball rolls down the dry sand, leaves a
// track, runs into the water and floats; a box floats off shore. The water's nodes over
// dry sand are fixed (the shoreline), so waves reflect at the shore.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include <btBulletDynamicsCommon.h>

#include "shore/bullet/terrain_coupling.h"
#include "shore/bullet/water_coupling.h"
#include "shore/cases/bullet_world.h"
#include "shore/cases/water_cases.h"
#include "shore/core/hash.h"
#include "shore/demo/mesh.h"
#include "shore/demo/render.h"
#include "shore/demo/scene.h"
#include "shore/terrain/terrain.h"
#include "water_scene_util.h"

namespace shore::demo {
namespace {

constexpr double kX0 = -2.0, kX1 = 2.0;     // m, the sand shown (x: offshore to inland)
constexpr double kY0 = -1.0, kY1 = 1.0;     // m
constexpr double kWaterX1 = 1.2;            // m, inland edge of the water grid (over dry sand: fixed nodes)
constexpr double kShoreX = 0.5;             // m, where the slope crosses the water's rest level (z = 0)
constexpr double kSlope = 0.25;             // rise per metre inland
constexpr double kDampingTime = 1.5;        // s, amplitude e-folding time of the waves
constexpr double kWaterDensity = 1000.0;    // kg/m^3
constexpr double kBallRadius = 0.1;         // m
constexpr double kBallDensity = 0.5;        // ratio to water: floats half submerged
constexpr double kBallStartX = 1.7;         // m
constexpr double kBallStartY = -0.25;       // m
constexpr double kBallPush = 1.2;           // m/s, initial speed down the slope
constexpr double kBoxRatio = 0.4;           // density ratio of the floating box
constexpr double kAfloatClearance = 0.005;  // m: a body this far above the sand counts as floating
// Filmstrip frames as fractions of the run: the roll, the entry, the rings, the end.
constexpr double kFrameAt[] = {0.0, 0.08, 0.16, 0.24, 0.4, 1.0};
constexpr double kSmokeFrameAt[] = {0.0, 0.5, 1.0};

/// Untouched sand: a plane rising inland (+x), crossing z = 0 at the shoreline.
class SlopedSand final : public terrain::HeightSource {
 public:
  [[nodiscard]] double height(double x, double /*y*/) const override { return kSlope * (x - kShoreX); }
};

using cases::Floater;
using cases::FloaterShape;

Floater ball_floater() {
  Floater f;
  f.shape = FloaterShape::sphere;
  f.size = btVector3(btScalar(2 * kBallRadius), btScalar(2 * kBallRadius), btScalar(2 * kBallRadius));
  f.density_ratio = kBallDensity;
  return f;
}

Floater box_floater() {
  Floater f;
  f.shape = FloaterShape::box;
  f.size = btVector3(0.3f, 0.3f, 0.12f);
  f.density_ratio = kBoxRatio;
  f.position = btVector3(btScalar(-1.25), btScalar(0.45), btScalar((0.5 - kBoxRatio) * 0.12));
  return f;
}

terrain::TerrainSettings sand_settings(const SceneOptions& o, double cell) {
  terrain::TerrainSettings s;
  s.cell = cell;
  s.origin_x = kX0;
  s.origin_y = kY0;
  s.material = terrain::Material::preset(o.material);
  s.base = std::make_shared<SlopedSand>();
  s.threads = o.threads;
  return s;
}

water::SurfaceSettings water_settings(double spacing, int threads) {
  water::PhysicalParameters phys;
  phys.cell = spacing;
  phys.depth = kSlope * (kShoreX - kX0) * 0.5;  // mean depth of the sloping bed sets the wave speed
  phys.density = kWaterDensity;
  phys.damping_time = kDampingTime;
  const int nx = static_cast<int>(std::lround((kWaterX1 - kX0) / spacing)) + 1;
  const int ny = static_cast<int>(std::lround((kY1 - kY0) / spacing)) + 1;
  water::SurfaceSettings s = water::SurfaceSettings::physical(phys, nx, ny);
  s.origin_x = kX0;
  s.origin_y = kY0;
  s.rest_height = 0.0;
  s.mode = water::SurfaceMode::vertical_only;
  s.boundary = water::Boundary::vertical_only;  // open-sea sides: reflecting walls
  s.threads = threads;
  return s;
}

/// The sand (and its untouched base) over the shown rectangle.
struct SandGrids {
  HeightGrid now, base;
};
SandGrids sand_grids(const terrain::Terrain& t) {
  const std::int64_t i0 = t.column_i(kX0), i1 = t.column_i(kX1), j0 = t.column_j(kY0), j1 = t.column_j(kY1);
  const int nx = static_cast<int>(i1 - i0 + 1), ny = static_cast<int>(j1 - j0 + 1);
  const double cell = t.settings().cell;
  SandGrids g{HeightGrid(nx, ny, cell, t.column_x(i0), t.column_y(j0)),
              HeightGrid(nx, ny, cell, t.column_x(i0), t.column_y(j0))};
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      g.now.at(i, j) = t.height(i0 + i, j0 + j);
      g.base.at(i, j) = t.base_height(i0 + i, j0 + j);
    }
  return g;
}

double max_sinkage(const terrain::Terrain& t) {
  double m = 0.0;
  for (std::int64_t j = t.column_j(kY0); j <= t.column_j(kY1); ++j)
    for (std::int64_t i = t.column_i(kX0); i <= t.column_i(kX1); ++i) m = std::max(m, t.sinkage(i, j));
  return m;
}

/// Sand with the water drawn over it where the water lies above the sand (what the
/// oblique views show); with no surface, the water at its rest level (their baseline).
HeightGrid scenery(const HeightGrid& sand, const water::Surface* w) {
  HeightGrid g = sand;
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i)
      if (g.x(i) <= kWaterX1) g.at(i, j) = std::max(g.at(i, j), w ? w->height_at(g.x(i), g.y(j)) : 0.0);
  return g;
}

SceneResult run(const SceneOptions& o, Progress& progress) {
  const double cell = o.smoke ? std::max(o.cell, 0.05) : o.cell;
  terrain::Terrain sand(sand_settings(o, cell));
  water::Surface sea(water_settings(2.0 * cell, 0));  // 0: the surface's own thread choice (small grid)

  cases::BulletWorld world(9.81);
  bullet::TerrainCoupling ground(world.world(), sand);
  bullet::WaterCoupling water(world.world(), sea);
  const int shoreline_nodes = water.fix_shoreline(sand);

  const Floater ball_f = ball_floater();
  const double ball_mass = kBallDensity * kWaterDensity * 4.0 / 3.0 * std::numbers::pi * std::pow(kBallRadius, 3);
  const double start_z = kSlope * (kBallStartX - kShoreX) + kBallRadius / std::cos(std::atan(kSlope)) + 0.002;
  btRigidBody* ball = world.add_body(std::make_unique<btSphereShape>(btScalar(kBallRadius)), ball_mass,
                                     btVector3(btScalar(kBallStartX), btScalar(kBallStartY), btScalar(start_z)));
  const double dir = -1.0 / std::sqrt(1.0 + kSlope * kSlope);  // down the slope, unit (dir, 0, kSlope * dir)
  ball->setLinearVelocity(btVector3(btScalar(kBallPush * dir), 0, btScalar(kBallPush * kSlope * dir)));
  ball->setAngularVelocity(btVector3(0, btScalar(kBallPush * dir / kBallRadius), 0));  // rolling, not sliding
  ball->setActivationState(DISABLE_DEACTIVATION);
  ball->setFriction(btScalar(terrain::Material::preset(o.material).friction));
  ground.add_body(ball);
  water.add_body(ball);

  const Floater box_f = box_floater();
  btRigidBody* box = world.add_body(std::make_unique<btBoxShape>(box_f.size * btScalar(0.5)),
                                    kBoxRatio * kWaterDensity * 0.3 * 0.3 * 0.12, box_f.position);
  box->setActivationState(DISABLE_DEACTIVATION);
  water.add_body(box);

  const std::vector<const btRigidBody*> drawn{ball, box};
  const int n = o.substeps();
  const double window = std::min(1.0, 0.5 * o.seconds);
  const int window_start = n - std::max(1, static_cast<int>(std::lround(window / o.substep)));
  std::vector<int> frame_steps;
  for (double f : o.smoke ? std::span<const double>(kSmokeFrameAt) : std::span<const double>(kFrameAt))
    frame_steps.push_back(std::clamp(static_cast<int>(std::lround(f * n)), 0, n));
  std::vector<Image> film;
  std::vector<std::string> labels;
  auto frame = [&](int min_pixels, const std::string& title) {
    const SandGrids g = sand_grids(sand);
    const HeightGrid now = scenery(g.now, &sea), before = scenery(g.base, nullptr);
    const water_scene::BodyEnvelopes b = water_scene::body_envelopes(drawn, now);
    ReliefStyle style;
    style.baseline = &before;  // blue: track and troughs, red: rims and crests
    style.bodies = &b.top;
    style.body_bottoms = &b.bottom;
    style.min_pixels = min_pixels;
    style.title = title;
    style.legend = !title.empty();
    return render_oblique(now, style, 30.0);
  };
  auto capture = [&](int k) {
    if (!o.write_files || std::find(frame_steps.begin(), frame_steps.end(), k) == frame_steps.end()) return;
    film.push_back(frame(o.smoke ? 160 : 240, ""));
    labels.push_back(water_scene::time_label(k * o.substep));
  };
  capture(0);

  double wall = 0.0, box_draft_sum = 0.0, ball_draft_sum = 0.0, entered_water = -1.0;
  long samples = 0;
  bool ball_afloat = true;  // over the whole measuring window
  for (int k = 1; k <= n; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    world.step(o.substep);
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (entered_water < 0.0 && water.submerged_volume(ball) > 0.0) entered_water = k * o.substep;
    if (k > window_start) {
      // The level each body sits in: the water on a circle 0.15 m outside its footprint.
      const btVector3 pb = box->getWorldTransform().getOrigin(), pl = ball->getWorldTransform().getOrigin();
      const btTransform& tb = box->getWorldTransform();  // bottom-face centre: unbiased by a small heel
      const double box_bottom = (pb - tb.getBasis().getColumn(2) * (btScalar(0.5) * box_f.size.z())).z();
      box_draft_sum += water_scene::level_around(sea, pb.x(), pb.y(), 0.36) - box_bottom;
      const double ball_bottom = pl.z() - kBallRadius;
      ball_draft_sum += water_scene::level_around(sea, pl.x(), pl.y(), kBallRadius + 0.15) - ball_bottom;
      const double bed = sand.height(sand.column_i(pl.x()), sand.column_j(pl.y()));
      if (ball_bottom - bed < kAfloatClearance) ball_afloat = false;
      ++samples;
    }
    capture(k);
    progress.update(static_cast<double>(k) / n);
  }

  const SandGrids grids = sand_grids(sand);
  long nan_count = grids.now.non_finite_count() + water_scene::non_finite_heights(sea) +
                   water_scene::non_finite_state(*ball) + water_scene::non_finite_state(*box);
  StateHash hash;
  hash.add(sand.state_hash());
  hash.add(sea.state_hash());
  water_scene::hash_body(hash, *ball);
  water_scene::hash_body(hash, *box);

  SceneResult r;
  r.state_hash = hash.value();
  r.metrics = common_metrics("beach", o, n, wall, r.state_hash, nan_count);
  r.metrics["sand"] = std::to_string(grids.now.nx) + " x " + std::to_string(grids.now.ny) + " columns shown, slope " +
                      std::to_string(kSlope);
  r.metrics["water"] = std::to_string(sea.nx()) + " x " + std::to_string(sea.ny()) + " nodes, vertical-only, spacing " +
                       std::to_string(sea.spacing()) + " m";
  r.metrics["shoreline_nodes"] = shoreline_nodes;
  // The untouched slope rises above the rest level exactly inland of x = kShoreX.
  int inland = 0;
  for (int i = 0; i < sea.nx(); ++i)
    if (sea.node_x(i) > kShoreX) inland += sea.ny();
  add_check(r.metrics, "shoreline_nodes", shoreline_nodes, inland, 0.0,
            "geometry: water nodes inland of the line where the slope crosses the rest level");

  // Volume bookkeeping of the sand: ground + compacted + airborne must equal the edits.
  const terrain::VolumeTotals v = sand.volume();
  double moved = 0.0;
  for (std::size_t k = 0; k < grids.now.z.size(); ++k) moved += std::abs(grids.now.z[k] - grids.base.z[k]);
  moved *= cell * cell;
  const double scale = v.compacted + moved;
  r.metrics["volume_drift_rel"] = scale > 0.0 ? std::abs(v.total() - v.edited) / scale : 1e-12;
  r.metrics["compacted_volume_m3"] = v.compacted;
  r.metrics["max_sinkage_m"] = max_sinkage(sand);
  const std::int64_t rescues = ground.stats().rescues;
  r.metrics["rescues"] = rescues;

  const double box_draft = box_draft_sum / double(std::max(samples, 1L));
  const double box_ref = cases::archimedes_draft(box_f);
  const double box_err = std::abs(box_draft - box_ref) / box_ref;
  r.metrics["box_draft_m"] = box_draft;
  r.metrics["box_archimedes_m"] = box_ref;
  add_check(r.metrics, "box_draft_m", box_draft, box_ref, 0.05 * box_ref,
            "Archimedes: a box of density ratio r floats with draft r * height");
  double worst = box_err;
  const double ball_draft = ball_draft_sum / double(std::max(samples, 1L));
  const double ball_ref = cases::archimedes_draft(ball_f);
  r.metrics["ball_afloat"] = ball_afloat;
  r.metrics["ball_draft_m"] = ball_draft;
  r.metrics["ball_archimedes_m"] = ball_ref;
  r.metrics["ball_entered_water_s"] = entered_water;
  r.metrics["ball_final_x_m"] = ball->getWorldTransform().getOrigin().x();
  if (ball_afloat) {
    worst = std::max(worst, std::abs(ball_draft - ball_ref) / ball_ref);
    add_check(r.metrics, "ball_draft_m", ball_draft, ball_ref, 0.05 * ball_ref,
              "Archimedes: a sphere of density ratio r floats with a cap of r times its volume submerged");
  }
  r.metrics["draft_error_rel"] = worst;

  if (o.write_files) {
    ReliefStyle top;
    top.baseline = &grids.base;
    const water_scene::BodyEnvelopes b = water_scene::body_envelopes(drawn, grids.now);
    top.bodies = &b.top;
    top.body_bottoms = &b.bottom;
    top.title = "beach: sand, coloured by deformation";
    r.files.push_back(write_png(o.file("relief.png"), render_relief(grids.now, top)));
    const terrain::Terrain* s = &sand;
    const water::Surface* w = &sea;
    const water_scene::WaterOverlay overlay{
        [s, w](double x, double y) { return s->height(s->column_i(x), s->column_j(y)) > w->settings().rest_height; },
        drawn};
    r.files.push_back(write_png(o.file("water.png"),
                                water_scene::render_water_scene(sea, overlay, 0.0, "beach: water (sand: dry land)")));
    r.files.push_back(write_png(o.file("view.png"), frame(480, "beach at " + water_scene::time_label(n * o.substep))));
    r.files.push_back(write_png(o.file("filmstrip.png"), filmstrip(film, labels, 3)));
    r.files.push_back(write_obj(o.file("sand.obj"), grids.now));
  }
  return r;
}

const SceneRegistrar kRegistered{Scene{
    .name = "beach",
    .description =
        "Sand sloping down (1 in 4) into water. A light ball (density 0.5) rolls down the dry sand leaving a track, "
        "runs into the water and floats off; a box (density 0.4) floats off shore. Water nodes over dry sand are "
        "fixed (the shoreline, from the sand's heights), so the ball's rings reflect at the shore. The ball is "
        "coupled to both the sand and the water. Look at the relief for the track and at the filmstrip.",
    .defaults = {.seconds = 5.0, .substep = 1.0 / 240.0, .material = "sand", .cell = 0.02, .smoke_seconds = 1.0},
    .metric_help =
        {
            {"sand", "the sand grid shown"},
            {"water", "the water grid"},
            {"shoreline_nodes", "water nodes fixed because the sand under them is above the water's rest level"},
            {"volume_drift_rel", "|ground + compacted + airborne - edited| / (compacted + sum |height change|)"},
            {"compacted_volume_m3", "sand volume removed by compaction, m^3"},
            {"max_sinkage_m", "deepest plastic sinkage of the sand, m"},
            {"rescues", "bodies lifted back above bedrock (should be 0)"},
            {"box_draft_m",
             "mean draft of the box over the last second (below the water level on a circle 0.15 m outside it), m"},
            {"box_archimedes_m", "Archimedes' draft of the box, m"},
            {"ball_afloat", "the ball stayed clear of the sand over the whole last second"},
            {"ball_draft_m", "mean draft of the ball over the last second, m"},
            {"ball_archimedes_m", "Archimedes' draft of the ball, m"},
            {"ball_entered_water_s", "first time the ball touched the water, s (-1: never)"},
            {"ball_final_x_m", "where the ball ended, m (shoreline at x = 0.5, water inland to the left)"},
            {"draft_error_rel", "worst relative draft error against Archimedes: the box, and the ball if afloat"},
        },
    .run = run,
}};

}  // namespace
}  // namespace shore::demo
