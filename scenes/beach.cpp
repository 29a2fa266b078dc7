// beach: sand sloping down into water. A light ball rolls down the dry sand, leaves a
// track, runs into the water and floats; a box floats off shore. The water's nodes over
// dry sand are fixed (the shoreline), so waves reflect at the shore.
#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include <btBulletDynamicsCommon.h>

#include "shore/bullet/terrain_coupling.h"
#include "shore/bullet/water_coupling.h"
#include "shore/scenes/film.h"
#include "shore/scenes/pool_cases.h"
#include "shore/scenes/runner.h"
#include "shore/scenes/scene.h"
#include "shore/scenes/soil_view.h"
#include "shore/scenes/water_view.h"
#include "shore/scenes/world.h"
#include "shore/terrain/terrain.h"

namespace shore::scenes {
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
  terrain::TerrainSettings s = soil_settings(o);
  s.cell = cell;
  s.origin_x = kX0;
  s.origin_y = kY0;
  s.base = std::make_shared<SlopedSand>();
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

double sand_cell(const SceneOptions& o) { return o.smoke ? std::max(o.cell, 0.05) : o.cell; }

class Beach final : public Scene {
 public:
  explicit Beach(const SceneOptions& o)
      : o_(o),
        sand_(sand_settings(o, sand_cell(o))),
        sea_(water_settings(2.0 * sand_cell(o), 0)),  // 0: the surface's own thread choice (small grid)
        ground_(world_.world(), sand_),
        water_(world_.world(), sea_),
        shoreline_nodes_(water_.fix_shoreline(sand_)),
        window_start_(o.substeps() -
                      std::max(1, static_cast<int>(std::lround(std::min(1.0, 0.5 * o.seconds) / o.substep)))) {
    const double ball_mass = kBallDensity * kWaterDensity * 4.0 / 3.0 * std::numbers::pi * std::pow(kBallRadius, 3);
    const double start_z = kSlope * (kBallStartX - kShoreX) + kBallRadius / std::cos(std::atan(kSlope)) + 0.002;
    ball_ = world_.add_body(std::make_unique<btSphereShape>(btScalar(kBallRadius)), ball_mass,
                            btVector3(btScalar(kBallStartX), btScalar(kBallStartY), btScalar(start_z)));
    const double dir = -1.0 / std::sqrt(1.0 + kSlope * kSlope);  // down the slope, unit (dir, 0, kSlope * dir)
    ball_->setLinearVelocity(btVector3(btScalar(kBallPush * dir), 0, btScalar(kBallPush * kSlope * dir)));
    ball_->setAngularVelocity(btVector3(0, btScalar(kBallPush * dir / kBallRadius), 0));  // rolling, not sliding
    ball_->setActivationState(DISABLE_DEACTIVATION);
    ball_->setFriction(btScalar(terrain::Material::preset(o.material).friction));
    ground_.add_body(ball_);
    water_.add_body(ball_);

    box_ = world_.add_body(std::make_unique<btBoxShape>(box_f_.size * btScalar(0.5)),
                           kBoxRatio * kWaterDensity * 0.3 * 0.3 * 0.12, box_f_.position);
    box_->setActivationState(DISABLE_DEACTIVATION);
    water_.add_body(box_);
    drawn_ = {ball_, box_};
  }

  void step() override {
    world_.step(o_.substep);
    ++k_;
  }

  void observe() override {
    if (entered_water_ < 0.0 && water_.submerged_volume(ball_) > 0.0) entered_water_ = k_ * o_.substep;
    if (k_ <= window_start_) return;
    // The level each body sits in: the water on a circle 0.15 m outside its footprint.
    const btVector3 pb = box_->getWorldTransform().getOrigin(), pl = ball_->getWorldTransform().getOrigin();
    const btTransform& tb = box_->getWorldTransform();  // bottom-face centre: unbiased by a small heel
    const double box_bottom = (pb - tb.getBasis().getColumn(2) * (btScalar(0.5) * box_f_.size.z())).z();
    box_draft_sum_ += sea_.level_around(pb.x(), pb.y(), 0.36) - box_bottom;
    const double ball_bottom = pl.z() - kBallRadius;
    ball_draft_sum_ += sea_.level_around(pl.x(), pl.y(), kBallRadius + 0.15) - ball_bottom;
    const double bed = sand_.height(sand_.column_i(pl.x()), sand_.column_j(pl.y()));
    if (ball_bottom - bed < kAfloatClearance) ball_afloat_ = false;
    ++samples_;
  }

  [[nodiscard]] SceneState state() const override {
    return {.soils = {&sand_},
            .waters = {&sea_},
            .bodies = drawn_,
            .soil_heights = {sand_grids(sand_).now},
            .layout = HashLayout::velocities_by_axis};
  }

  void measure(nlohmann::json& m) const override {
    const SandGrids grids = sand_grids(sand_);
    m["sand"] = std::to_string(grids.now.nx) + " x " + std::to_string(grids.now.ny) + " columns shown, slope " +
                std::to_string(kSlope);
    m["water"] = std::to_string(sea_.nx()) + " x " + std::to_string(sea_.ny()) + " nodes, vertical-only, spacing " +
                 std::to_string(sea_.spacing()) + " m";
    m["shoreline_nodes"] = shoreline_nodes_;
    // The untouched slope rises above the rest level exactly inland of x = kShoreX.
    int inland = 0;
    for (int i = 0; i < sea_.nx(); ++i)
      if (sea_.node_x(i) > kShoreX) inland += sea_.ny();
    add_check(m, "shoreline_nodes", shoreline_nodes_, inland, 0.0,
              "geometry: water nodes inland of the line where the slope crosses the rest level");

    // Volume bookkeeping of the sand: ground + compacted + airborne must equal the edits.
    const terrain::VolumeTotals v = sand_.volume();
    double moved = 0.0;
    for (std::size_t k = 0; k < grids.now.z.size(); ++k) moved += std::abs(grids.now.z[k] - grids.base.z[k]);
    moved *= sand_.settings().cell * sand_.settings().cell;
    const double scale = v.compacted + moved;
    m["volume_drift_rel"] = scale > 0.0 ? std::abs(v.total() - v.edited) / scale : 1e-12;
    m["compacted_volume_m3"] = v.compacted;
    m["max_sinkage_m"] = max_sinkage(sand_);
    m["rescues"] = ground_.stats().rescues;

    const double box_draft = box_draft_sum_ / double(std::max(samples_, 1L));
    const double box_ref = archimedes_draft(box_f_);
    const double box_err = std::abs(box_draft - box_ref) / box_ref;
    m["box_draft_m"] = box_draft;
    m["box_archimedes_m"] = box_ref;
    add_check(m, "box_draft_m", box_draft, box_ref, 0.05 * box_ref,
              "Archimedes: a box of density ratio r floats with draft r * height");
    double worst = box_err;
    const double ball_draft = ball_draft_sum_ / double(std::max(samples_, 1L));
    const double ball_ref = archimedes_draft(ball_floater());
    m["ball_afloat"] = ball_afloat_;
    m["ball_draft_m"] = ball_draft;
    m["ball_archimedes_m"] = ball_ref;
    m["ball_entered_water_s"] = entered_water_;
    m["ball_final_x_m"] = ball_->getWorldTransform().getOrigin().x();
    if (ball_afloat_) {
      worst = std::max(worst, std::abs(ball_draft - ball_ref) / ball_ref);
      add_check(m, "ball_draft_m", ball_draft, ball_ref, 0.05 * ball_ref,
                "Archimedes: a sphere of density ratio r floats with a cap of r times its volume submerged");
    }
    m["draft_error_rel"] = worst;
  }

  [[nodiscard]] std::vector<int> film_substeps() const override {
    return at_fractions(o_.substeps(),
                        o_.smoke ? std::span<const double>(kSmokeFrameAt) : std::span<const double>(kFrameAt), 0);
  }
  Image film_frame(Painter& painter) override {
    return painter.paint(contents(), {.elevation_deg = 30.0, .legend = false, .width = o_.smoke ? 240 : 400});
  }

  SceneContents contents() override {
    return {.world = &world_,
            .soils = {{&sand_, &ground_, {}}},
            .waters = {{&sea_, &water_}},
            .bounds = {kX0, kY0, kX1, kY1},
            .focus = ball_,
            .clock = &k_};
  }

  void draw(Drawing& out) const override {
    const SandGrids grids = sand_grids(sand_);
    out.view("relief.png", {.camera = View::Camera::top,
                            .water = View::Water::natural,
                            .width = 960,
                            .title = "beach: sand coloured by deformation, the water over it"});
    out.view("water.png", {.camera = View::Camera::top,
                           .ground = View::Ground::natural,
                           .water = View::Water::height,
                           .width = 960,
                           .title = "beach: water coloured by height (sand: natural)"});
    // Blue: the track, red: its rims; the water over the sand.
    out.view("view.png", {.elevation_deg = 30.0, .width = 960, .title = "beach at " + time_label(k_ * o_.substep)});
    out.filmstrip();
    out.obj("sand.obj", grids.now);
  }

 private:
  SceneOptions o_;
  terrain::Terrain sand_;
  water::Surface sea_;
  World world_;
  bullet::TerrainCoupling ground_;  // before the water: the soil works first in each substep
  bullet::WaterCoupling water_;
  int shoreline_nodes_;
  int window_start_;
  const Floater box_f_ = box_floater();
  btRigidBody* ball_ = nullptr;
  btRigidBody* box_ = nullptr;
  std::vector<const btRigidBody*> drawn_;  // ball, box
  int k_ = 0;
  double box_draft_sum_ = 0.0, ball_draft_sum_ = 0.0, entered_water_ = -1.0;
  long samples_ = 0;
  bool ball_afloat_ = true;  // over the whole measuring window
};

}  // namespace

SceneType beach_scene() {
  return {
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
      .create = make_scene<Beach>,
  };
}

}  // namespace shore::scenes
