// tracks: a riderless bicycle (a light frame and two narrow wheels on hinges, no steering)
// launched at 3 m/s across soft ground, after Sumner et al.'s bicycle tracks and crash
// (figures 1 and 4). The wheels sink and cut a rut, the soil's compaction resistance
// slows the bicycle, and since nothing steers it, a small initial lean grows until it
// falls over and the frame slaps a print into the ground beside the rut.
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "shore/bullet/terrain_coupling.h"
#include "shore/scenes/film.h"
#include "shore/scenes/runner.h"
#include "shore/scenes/scene.h"
#include "shore/scenes/soil_view.h"
#include "shore/scenes/world.h"
#include "shore/terrain/bekker.h"
#include "shore/terrain/height_source.h"
#include "shore/terrain/material.h"
#include "shore/terrain/terrain.h"

namespace shore::scenes {
namespace {

constexpr double kSpeed = 3.0;         // m/s at launch
constexpr double kWheelRadius = 0.34;  // m
constexpr double kTyreWidth = 0.07;    // m
constexpr double kWheelMass = 2.0;     // kg
constexpr double kFrameMass = 6.0;     // kg
constexpr double kAxle = 0.52;         // m, half the wheelbase
constexpr double kFrameAbove = 0.30;   // m, frame centre above the axles
constexpr double kLean = 0.01;         // rad, initial lean to the right (-y)
constexpr double kFallenLean = 0.5;    // rad: rolling has ended once the frame leans this far
constexpr double kLyingLean = 1.0;     // rad: the bicycle has fallen over if it ends leaning this far

struct Bicycle {
  btRigidBody* frame = nullptr;
  std::array<btRigidBody*, 2> wheels{};  // rear, front
};

/// The whole bicycle leaned by kLean about the x axis through its contact line.
Bicycle build(World& world, double ground_z) {
  const btQuaternion lean(btVector3(1, 0, 0), btScalar(kLean));
  const btMatrix3x3 turn(lean);
  const double z_axle = ground_z + kWheelRadius + 0.005;  // released 5 mm above the ground
  auto placed = [&](double x, double z) {
    return turn * btVector3(btScalar(x), 0, btScalar(z - ground_z)) + btVector3(0, 0, btScalar(ground_z));
  };
  Bicycle b;
  b.frame = world.add_body(std::make_unique<btBoxShape>(btVector3(btScalar(0.45), btScalar(0.02), btScalar(0.12))),
                           kFrameMass, placed(0.0, z_axle + kFrameAbove), lean);
  for (int w = 0; w < 2; ++w) {
    auto shape = std::make_unique<btCylinderShape>(
        btVector3(btScalar(kWheelRadius), btScalar(kTyreWidth / 2), btScalar(kWheelRadius)));
    shape->setMargin(btScalar(0.005));  // the default 4 cm margin is wider than the tyre
    const double x = w == 0 ? -kAxle : kAxle;
    b.wheels[static_cast<std::size_t>(w)] = world.add_body(std::move(shape), kWheelMass, placed(x, z_axle), lean);
    btRigidBody* wheel = b.wheels[static_cast<std::size_t>(w)];
    wheel->setFriction(btScalar(1.0));
    world.add_constraint(
        std::make_unique<btHingeConstraint>(*b.frame, *wheel, btVector3(btScalar(x), 0, btScalar(-kFrameAbove)),
                                            btVector3(0, 0, 0), btVector3(0, 1, 0), btVector3(0, 1, 0)),
        true);  // no collision between frame and wheels
  }
  for (btRigidBody* body : {b.frame, b.wheels[0], b.wheels[1]}) {
    body->setActivationState(DISABLE_DEACTIVATION);  // hashes must not depend on sleeping heuristics
    body->setLinearVelocity(btVector3(btScalar(kSpeed), 0, 0));
  }
  for (btRigidBody* wheel : b.wheels)  // rolling without slip: spin v / R about the axle
    wheel->setAngularVelocity(wheel->getWorldTransform().getBasis().getColumn(1) * btScalar(kSpeed / kWheelRadius));
  return b;
}

/// Lowest point of a wheel's rim: the centre minus R along the steepest downward direction
/// in the wheel's plane.
btVector3 rim_bottom(const btRigidBody& wheel) {
  const btVector3 axis = wheel.getWorldTransform().getBasis().getColumn(1);
  const btVector3 down = btVector3(0, 0, -1) + axis * axis.z();  // -z minus its part along the axle
  return wheel.getCenterOfMassPosition() + down.normalized() * btScalar(kWheelRadius);
}

/// Mean speed of the two hubs along the launch direction.
double hub_speed(const Bicycle& b) {
  return 0.5 * (static_cast<double>(b.wheels[0]->getLinearVelocity().x()) +
                static_cast<double>(b.wheels[1]->getLinearVelocity().x()));
}

/// Lean of the frame: angle between its up axis and the vertical.
double lean_of(const Bicycle& b) { return tilt_from_vertical(*b.frame, 2); }

/// The soil of the options (the 7 cm tyre needs fine cells, smoke runs too) on a base.
terrain::TerrainSettings bumpy_soil(const SceneOptions& o, std::shared_ptr<const terrain::HeightSource> base) {
  terrain::TerrainSettings ts = soil_settings(o);
  ts.base = std::move(base);
  return ts;
}

class Tracks final : public Scene {
 public:
  explicit Tracks(const SceneOptions& o)
      : o_(o),
        ground_height_(std::make_shared<terrain::LatticeNoise>(
            terrain::LatticeNoiseSettings{.seed = 11, .spacing = 0.4, .amplitude = 0.003, .octaves = 2})),
        soil_(bumpy_soil(o, ground_height_)),
        coupling_(world_.world(), soil_),
        bike_(build(world_, ground_height_->height(0.0, 0.0) + ground_height_->settings().amplitude)),
        bodies_{bike_.frame, bike_.wheels[0], bike_.wheels[1]},
        patches_{{&soil_, {}}},
        frame_(grid_over(-1.0, -1.0, o.smoke ? 2.0 : 7.0, 1.0, o.cell)),
        baseline_(sample(patches_, frame_, Field::base)),
        last_contact_{rim_bottom(*bike_.wheels[0]), rim_bottom(*bike_.wheels[1])} {
    for (btRigidBody* b : {bike_.frame, bike_.wheels[0], bike_.wheels[1]}) coupling_.add_body(b);
  }

  void step() override {
    world_.step(o_.substep);
    ++k_;
  }

  void observe() override {
    if (t_fall_ >= 0.0) return;
    if (lean_of(bike_) > kFallenLean) {
      t_fall_ = k_ * o_.substep;
      x_fall_ = static_cast<double>(bike_.frame->getCenterOfMassPosition().x());
      return;
    }
    v_end_rolling_ = hub_speed(bike_);
    for (std::size_t w = 0; w < 2; ++w) {
      const btVector3 c = rim_bottom(*bike_.wheels[w]);
      if ((c - last_contact_[w]).length() >= btScalar(o_.cell)) {
        contacts_.push_back(c);
        last_contact_[w] = c;
      }
    }
  }

  [[nodiscard]] SceneState state() const override {
    return {.soils = {&soil_}, .bodies = bodies_, .soil_heights = {sample(patches_, frame_, Field::height)}};
  }

  void measure(nlohmann::json& m) const override {
    // The rut: how far the ground under each recorded rim bottom lies below the untouched
    // surface (skipping the first 0.3 m, where the bicycle was set down).
    double rut_sum = 0.0;
    int rut_n = 0;
    for (const btVector3& c : contacts_) {
      if (c.x() < 0.3 - kAxle) continue;
      const std::int64_t i = soil_.column_i(c.x()), j = soil_.column_j(c.y());
      rut_sum += soil_.base_height(i, j) - soil_.height(i, j);
      ++rut_n;
    }
    const HeightGrid heights = sample(patches_, frame_, Field::height);
    const HeightGrid sinkage = sample(patches_, frame_, Field::sinkage);
    long fallthrough = coupling_.stats().rescues;
    for (const btRigidBody* b : bodies_) {
      const btVector3 c = b->getCenterOfMassPosition();
      if (c.z() < soil_.bedrock(soil_.column_i(c.x()), soil_.column_j(c.y()))) ++fallthrough;
    }
    m["rut_depth_m"] = rut_n > 0 ? rut_sum / rut_n : 0.0;
    m["rut_samples"] = rut_n;
    m["launch_speed_mps"] = kSpeed;
    m["speed_end_of_rolling_mps"] = v_end_rolling_;
    m["speed_loss_rel"] = (kSpeed - v_end_rolling_) / kSpeed;
    m["rolling_seconds"] = t_fall_ >= 0.0 ? t_fall_ : k_ * o_.substep;
    m["rolling_distance_m"] =
        t_fall_ >= 0.0 ? x_fall_ : static_cast<double>(bike_.frame->getCenterOfMassPosition().x());
    m["final_lean_rad"] = lean_of(bike_);
    m["fell_over"] = lean_of(bike_) > kLyingLean;
    // For comparison, not as a check: Bekker's steady rolling sinkage of a rigid wheel under
    // its share of the weight (the frame's centre lies midway between the axles). The rut
    // measured here is deeper (sand about +35 %, mud about +75 % at 1 cm cells): the tyres
    // land, bounce and lean, and the rear tyre runs in the front tyre's rut.
    const double wheel_load = (0.5 * kFrameMass + kWheelMass) * 9.81;
    m["bekker_rolling_sinkage_m"] =
        terrain::bekker::wheel_sinkage_rolling(soil_.settings().material, wheel_load, 2 * kWheelRadius, kTyreWidth);
    m["deepest_m"] = max_lowering(baseline_, heights);
    m["volume_drift_rel"] = volume_drift_rel(soil_);
    m["max_sinkage_m"] = max_of(sinkage);
    m["fallthrough_count"] = fallthrough;
  }

  [[nodiscard]] std::vector<int> film_substeps() const override { return evenly_spread_film(o_.substeps(), o_.smoke); }
  Image film_frame(Painter& painter) override {
    return painter.paint(contents(), {.legend = false, .width = o_.smoke ? 240 : 480});
  }

  SceneContents contents() override {
    return {.world = &world_,
            .soils = {{&soil_, &coupling_, {}}},
            .bounds = bounds_of(frame_),
            .focus = bike_.frame,
            .clock = &k_};
  }

  void draw(Drawing& out) const override {
    const HeightGrid heights = sample(patches_, frame_, Field::height);
    const int w = o_.smoke ? 320 : 1280;
    out.view("top.png",
             {.camera = View::Camera::top, .width = w, .title = "tracks in " + o_.material + ": rut, then the fall"});
    out.view("view.png", {.elevation_deg = 40.0,
                          .width = w,
                          .title = "bicycle in " + o_.material + " at " + time_label(k_ * o_.substep)});
    out.filmstrip();
    out.obj("ground.obj", heights);
  }

 private:
  SceneOptions o_;
  std::shared_ptr<terrain::LatticeNoise> ground_height_;
  terrain::Terrain soil_;
  World world_;
  bullet::TerrainCoupling coupling_;
  Bicycle bike_;
  std::vector<const btRigidBody*> bodies_;
  std::vector<Patch> patches_;
  HeightGrid frame_;
  HeightGrid baseline_;
  int k_ = 0;
  double v_end_rolling_ = kSpeed, t_fall_ = -1.0, x_fall_ = 0.0;
  std::vector<btVector3> contacts_;  // rim bottoms along the path while rolling, >= one cell apart
  std::array<btVector3, 2> last_contact_;
};

}  // namespace

SceneType tracks_scene() {
  return {
      .name = "tracks",
      .description =
          "A riderless bicycle (6 kg frame, two 0.68 m wheels with 7 cm tyres on hinges, no steering) is launched at "
          "3 m/s across the soil with a slight lean, after Sumner et al.'s bicycle tracks and crash. The tyres cut a "
          "rut, compaction resistance slows the bicycle, and with nothing steering it the lean grows until it falls "
          "over and the frame and wheels slap prints beside the rut.",
      .defaults = {.seconds = 3.5, .substep = 1.0 / 240.0, .material = "sand", .cell = 0.01, .smoke_seconds = 0.4},
      .metric_help =
          {
              {"rut_depth_m",
               "mean depth of the ground below the untouched surface under the rim's path while rolling, m"},
              {"rut_samples", "points of the rim path the rut depth averages"},
              {"launch_speed_mps", "speed at launch, m/s"},
              {"speed_end_of_rolling_mps", "mean hub speed when the frame's lean first passed 0.5 rad, m/s"},
              {"speed_loss_rel", "(launch speed - speed at the end of rolling) / launch speed"},
              {"rolling_seconds", "time until the lean passed 0.5 rad (the whole run if it never did), s"},
              {"rolling_distance_m", "frame x at that time, m"},
              {"final_lean_rad", "frame lean at the end, rad"},
              {"fell_over", "the frame ends leaning more than 1 rad"},
              {"volume_drift_rel", "|ground + compacted + airborne - edited| / moved volume (must be < 1e-6)"},
              {"bekker_rolling_sinkage_m", "Bekker's rolling sinkage of one wheel under its share of the weight, m"},
              {"deepest_m", "largest lowering of the ground below the untouched surface, m"},
              {"max_sinkage_m",
               "largest plastic sinkage of any soil column (accumulates where slumping refills a "
               "pressed column), m"},
              {"fallthrough_count", "bodies below bedrock at the end or lifted back by the coupling (must be 0)"},
          },
      .create = make_scene<Tracks>,
  };
}

}  // namespace shore::scenes
