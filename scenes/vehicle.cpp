// vehicle: a four-wheel vehicle (a 400 kg chassis on four motorised 0.6 m wheels) drives
// from rigid ground across a sand strip, then a mud strip, then rigid ground again. The
// soil is one Terrain with a material map (sand, mud, and a gravel road along the left of
// the track), one coupling over it all, so soil moves across the sand-mud border and the
// ground's mesh is one surface. The pictures show the ruts: sand slumps into wide, shallow
// ruts with low rims, mud keeps steep walls and higher rims. The benchmark runs this scene
// for the vehicle's real-time factor.
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include "shore/bullet/terrain_coupling.h"
#include "shore/scenes/film.h"
#include "shore/scenes/four_wheeler.h"
#include "shore/scenes/runner.h"
#include "shore/scenes/scene.h"
#include "shore/scenes/soil_cases.h"
#include "shore/scenes/soil_view.h"
#include "shore/scenes/world.h"
#include "shore/terrain/mesh_field.h"
#include "shore/terrain/terrain.h"

namespace shore::scenes {
namespace {

constexpr int kTileCells = 64;  // soil tile size; the strips are whole tiles long
constexpr double kWheelRadius = FourWheelerSettings{}.wheel_radius;
constexpr double kTargetSpeed = 2.0;            // m/s the wheel motors aim for
constexpr double kHalfY = 5.0;                  // m, half width of the ground and of the soil strips
constexpr double kHalfWidth = 1.1;              // m, half width of the pictured strip (wheels at +-0.65 m)
constexpr double kRoadY0 = 1.0, kRoadY1 = 1.8;  // m, the gravel road beside the track (left of it)

/// The palette: sand (entry 0), mud (1) and a road of packed gravel (2).
enum Ground : int { kSand = 0, kMud = 1, kGravel = 2 };

/// Packed gravel: sand's law, 20 times as stiff (a plate sinks 1/20^(1/n) as far, about a
/// fifteenth) and rougher (38 degrees), standing at a steeper angle.
terrain::Material gravel() {
  terrain::Material m = terrain::Material::sand();
  m.name = "gravel";
  m.bekker_kphi *= 20.0;
  m.friction_angle = 38.0 * std::numbers::pi / 180.0;
  m.theta_out = 0.6;
  return m;
}

terrain::TerrainSettings ground_soil(const SceneOptions& o) {
  terrain::TerrainSettings s = soil_settings(o);
  s.material = terrain::Material::sand();
  s.tile_columns = kTileCells;
  return s;
}

double tile_length(const SceneOptions& o) { return kTileCells * o.cell; }  // m
int strip_tiles(const SceneOptions& o) { return o.smoke ? 1 : 3; }         // tiles per strip

bullet::TerrainCouplingSettings soil_coupling(double x0, double x1) {
  bullet::TerrainCouplingSettings s;
  s.region = {x0, -kHalfY, x1, kHalfY};
  return s;
}

class Vehicle final : public Scene {
 public:
  explicit Vehicle(const SceneOptions& o)
      : o_(o),
        start_x_(o.smoke ? -1.2 : -2.0),  // smoke runs: a short drive over one tile of each soil
        sand_x1_(strip_tiles(o) * tile_length(o)),
        mud_x1_(sand_x1_ + strip_tiles(o) * tile_length(o)),
        soil_(ground_soil(o)),
        patches_{{&soil_, {0.0, -kHalfY, mud_x1_, kHalfY}}},
        // From the start on rigid ground to past the mud, where a 6 s drive ends.
        frame_(grid_over(start_x_ - 1.2, -kHalfWidth, o.smoke ? mud_x1_ + 0.4 : mud_x1_ + 2.8, kHalfWidth, o.cell)),
        baseline_(frame_.nx, frame_.ny, frame_.cell, frame_.x0, frame_.y0, 0.0) {  // every ground starts at 0
    // Rigid ground before and after the soft strips: static boxes with their top at z = 0.
    world_.add_body(std::make_unique<btBoxShape>(btVector3(10, btScalar(kHalfY), 1)), 0.0, btVector3(-10, 0, -1))
        ->setFriction(0.9f);
    world_
        .add_body(std::make_unique<btBoxShape>(btVector3(10, btScalar(kHalfY), 1)), 0.0,
                  btVector3(btScalar(mud_x1_ + 10), 0, -1))
        ->setFriction(0.9f);
    paint_ground();
    coupling_ = std::make_unique<bullet::TerrainCoupling>(world_.world(), soil_, soil_coupling(0.0, mud_x1_));

    const double z0 = kWheelRadius + 0.02;
    FourWheelerSettings car;
    car.target_speed = kTargetSpeed;
    bullet::TerrainCoupling* const couplings[] = {coupling_.get()};
    const FourWheeler v = build_four_wheeler(world_, car, btVector3(btScalar(start_x_), 0, btScalar(z0 + 0.25)),
                                             btQuaternion::getIdentity(), o.substep, couplings);
    chassis_ = v.chassis;
    bodies_.push_back(chassis_);
    for (btRigidBody* wheel : v.wheels) bodies_.push_back(wheel);
    for (btHingeConstraint* hinge : v.hinges) hinges_.push_back(hinge);
    x_ = chassis_->getCenterOfMassPosition().x();
  }

  void step() override { world_.step(o_.substep); }

  void observe() override {
    ++times_.substeps;
    times_.add_coupling_times(coupling_->stats());
    const double x = chassis_->getCenterOfMassPosition().x();
    if (x >= 0.0 && x < sand_x1_) {
      sand_time_ += o_.substep;
      sand_dist_ += x - x_;
    } else if (x >= sand_x1_ && x < mud_x1_) {
      mud_time_ += o_.substep;
      mud_dist_ += x - x_;
    }
    x_ = x;
  }

  [[nodiscard]] SceneState state() const override {
    return {.soils = {&soil_},
            .bodies = bodies_,
            .soil_heights = {sample(patches_, frame_, Field::height)},
            .layout = HashLayout::positions};
  }

  void measure(nlohmann::json& m) const override {
    const HeightGrid heights = sample(patches_, frame_, Field::height);
    const HeightGrid sinkage = sample(patches_, frame_, Field::sinkage);
    long fallthrough = static_cast<long>(coupling_->stats().rescues);
    for (const btRigidBody* b : bodies_)
      if (b->getWorldTransform().getOrigin().z() < -1.0) ++fallthrough;  // below any bedrock of this scene
    m["fallthrough_count"] = fallthrough;
    m["volume_drift_rel"] = volume_drift_rel(soil_);
    m["max_sinkage_m"] = max_of(sinkage);
    m["deepest_m"] = max_lowering(baseline_, heights);
    m["mean_speed_sand_mps"] = sand_time_ > 0 ? sand_dist_ / sand_time_ : 0.0;
    m["mean_speed_mud_mps"] = mud_time_ > 0 ? mud_dist_ / mud_time_ : 0.0;
    m["target_speed_mps"] = kTargetSpeed;
    m["distance_m"] = chassis_->getCenterOfMassPosition().x() - start_x_;
    m["plugin_ms_per_substep"] = times_.plugin_ms_per_substep();
    m["note"] = "the vehicle always crosses sand then mud (a gravel road beside them); --material does not apply";
  }

  /// Frame q at the first substep (1, 2, ...) after the one before it that reaches
  /// round(n q / (frames - 1)).
  [[nodiscard]] std::vector<int> film_substeps() const override {
    const int frames = o_.smoke ? 3 : 6, n = o_.substeps();
    std::vector<int> at;
    int k = 1;
    for (int q = 0; q < frames; ++q, ++k) {
      while (k <= n && k < std::lround(double(n) * double(q) / double(frames - 1))) ++k;
      if (k > n) break;
      at.push_back(k);
    }
    return at;
  }

  Image film_frame(Painter& painter) override {
    return painter.paint(contents(), {.legend = false, .width = o_.smoke ? 240 : 480});
  }

  SceneContents contents() override {
    return {.world = &world_,
            .soils = {{&soil_, coupling_.get(), patches_[0].region}},
            .bounds = {start_x_ - 1.2, -2.0, mud_x1_ + 1.5, 2.0},
            .focus = chassis_,
            .drive = [this](double forward, double turn) { drive(forward, turn); }};
  }

  void draw(Drawing& out) const override {
    const HeightGrid heights = sample(patches_, frame_, Field::height);
    const int w = o_.smoke ? 320 : 1280;
    out.view("top.png", {.camera = View::Camera::top,
                         .width = w,
                         .title = "vehicle: rigid | sand | mud | rigid, ground coloured by deformation"});
    out.view("materials.png", {.camera = View::Camera::top,
                               .ground = View::Ground::natural,
                               .legend = false,
                               .width = w,
                               .title = "vehicle: the material map (sand, mud, a gravel road)"});
    out.view("view.png", {.elevation_deg = 40.0, .width = w, .title = "vehicle across sand then mud"});
    // A close view across the sand-mud edge.
    const Bounds edge{sand_x1_ - 1.2, -kHalfWidth, sand_x1_ + 1.2, kHalfWidth};
    out.view("ruts.png", {.region = edge,
                          .elevation_deg = 45.0,
                          .width = o_.smoke ? 320 : 960,
                          .title = "ruts: sand (left) to mud (right)"});
    out.filmstrip();
    out.obj("ground.obj", heights);
    // The ruts at the edge as the renderer draws them: each soil's mesh simplified to 1
    // pixel of this picture, its triangles outlined.
    out.view("lod.png", {.region = {sand_x1_ - 0.9, -0.7, sand_x1_ + 0.9, 0.7},
                         .elevation_deg = 30.0,
                         .azimuth_deg = -110.0,
                         .mesh_edges = true,
                         .width = o_.smoke ? 320 : 960,
                         .title = "ground mesh at 1 px"});
  }

 private:
  /// Sand where nothing is painted; mud over the second strip; the gravel road beside the
  /// track over both strips.
  void paint_ground() {
    soil_.set_palette({terrain::Material::sand(), terrain::Material::mud(), gravel()});
    const std::int64_t j0 = soil_.column_j(-kHalfY), j1 = soil_.column_j(kHalfY);
    const std::int64_t mud_i0 = soil_.column_i(sand_x1_), end_i = soil_.column_i(mud_x1_);
    soil_.paint_rect(GridRect::spanning(mud_i0, j0, end_i - 1, j1 - 1), kMud);
    const std::int64_t road_j0 = soil_.column_j(kRoadY0), road_j1 = soil_.column_j(kRoadY1);
    soil_.paint_rect(GridRect::spanning(0, road_j0, end_i - 1, road_j1 - 1), kGravel);
  }

  /// Skid steering: each side's wheels aim at (forward -+ turn) times the target speed
  /// (left wheels first in mounts); (0, 0) restores the scene's own straight drive.
  void drive(double forward, double turn) {
    if (forward == 0.0 && turn == 0.0) forward = 1.0;
    for (std::size_t w = 0; w < hinges_.size(); ++w) {
      const double side = w % 2 == 0 ? forward - turn : forward + turn;  // mounts alternate left, right
      hinges_[w]->enableAngularMotor(true, btScalar(-kTargetSpeed * std::clamp(side, -1.5, 1.5) / kWheelRadius),
                                     btScalar(FourWheelerSettings{}.motor_torque * o_.substep));
    }
    chassis_->activate(true);
  }

  SceneOptions o_;
  double start_x_, sand_x1_, mud_x1_;  // m: the chassis centre at the start; strip edges (sand from x = 0)
  World world_;
  terrain::Terrain soil_;                              // sand, mud and the gravel road (paint_ground)
  std::unique_ptr<bullet::TerrainCoupling> coupling_;  // after the soil and the world
  std::vector<Patch> patches_;
  HeightGrid frame_, baseline_;
  btRigidBody* chassis_ = nullptr;
  std::vector<btHingeConstraint*> hinges_;  // wheel motors, in mount order
  std::vector<const btRigidBody*> bodies_;  // chassis, then the wheels
  RunStats times_;                          // Shore's share of the substeps
  double x_ = 0.0;                          // chassis x after the last substep
  double sand_time_ = 0, sand_dist_ = 0, mud_time_ = 0, mud_dist_ = 0;
};

}  // namespace

SceneType vehicle_scene() {
  return {
      .name = "vehicle",
      .description =
          "A four-wheel vehicle (400 kg chassis, four 0.6 m wheels on hinge motors aiming at 2 m/s) drives from rigid "
          "ground across a strip of sand, then a strip of mud, then rigid ground: one Terrain painted sand, mud and a "
          "gravel road beside the track (a material map), one coupling. Look at the ruts: sand slumps to its angle of "
          "repose (wide, shallow ruts, low rims), mud keeps steep walls and pushes more soil into the rims. The "
          "vehicle slows on both soils.",
      .defaults = {.seconds = 6.0, .substep = 1.0 / 240.0, .material = "sand", .cell = 0.02, .smoke_seconds = 1.0},
      .metric_help =
          {
              {"fallthrough_count", "wheels below bedrock at the end or lifted back by the coupling (must be 0)"},
              {"volume_drift_rel", "|ground + compacted - edited| / moved volume of the soil (must be < 1e-6)"},
              {"max_sinkage_m", "largest plastic sinkage, m"},
              {"deepest_m", "largest lowering of the ground below the untouched surface, m"},
              {"mean_speed_sand_mps", "chassis speed averaged over its time above the sand, m/s"},
              {"mean_speed_mud_mps", "chassis speed averaged over its time above the mud, m/s"},
              {"target_speed_mps", "speed the wheel motors aim for, m/s"},
              {"distance_m", "distance the chassis travelled, m"},
              {"plugin_ms_per_substep", "Shore's share of a substep, ms"},
              {"note", "what --material means here"},
          },
      .create = make_scene<Vehicle>,
  };
}

}  // namespace shore::scenes
