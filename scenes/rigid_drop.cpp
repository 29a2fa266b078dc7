// rigid_drop: a tilted, spinning box dropped onto a rigid heightfield tile (plain Bullet,
// no soil). It exercises the whole scene pipeline and shows what rigid ground does: the
// box bounces, settles and leaves no trace.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "shore/scenes/film.h"
#include "shore/scenes/rigid_ground.h"
#include "shore/scenes/runner.h"
#include "shore/scenes/scene.h"
#include "shore/scenes/world.h"
#include "shore/terrain/material.h"

namespace shore::scenes {
namespace {

constexpr double kExtent = 1.28;                                       // m, side of the square tile
constexpr double kPlateau = 0.30;                                      // m, radius of the flat centre the box lands on
constexpr double kDropHeight = 0.45;                                   // m, box centre above the plateau at the start
constexpr double kMass = 10.0;                                         // kg
const btVector3 kHalf(btScalar(0.15), btScalar(0.15), btScalar(0.1));  // m, box half extents

double smoothstep(double t) {
  t = std::clamp(t, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

/// A flat plateau at z = 0 inside a shallow rippled bowl.
double bowl(double x, double y) {
  const double r = std::hypot(x, y);
  const double blend = smoothstep((r - kPlateau) / 0.2);
  const double ripple = 0.02 * std::sin(11.0 * x + 1.0) * std::cos(9.0 * y);
  return blend * (0.1 * (r - kPlateau) + ripple);
}

bullet::HeightfieldTileSettings tile_settings(const SceneOptions& o) {
  bullet::HeightfieldTileSettings s;
  s.columns = std::clamp(static_cast<int>(std::lround(kExtent / o.cell)) + 1, 9, 1025);
  s.cell = kExtent / (s.columns - 1);
  s.origin_x = s.origin_y = -0.5 * kExtent;
  s.min_height = -0.5;
  s.max_height = 0.5;
  s.friction = terrain::Material::preset(o.material).friction;
  return s;
}

btRigidBody* drop_box(World& world) {
  const btQuaternion tilt(btVector3(1, btScalar(0.6), 0).normalized(), btScalar(0.35));
  btRigidBody* box = world.add_body(std::make_unique<btBoxShape>(kHalf), kMass,
                                    btVector3(btScalar(0.03), btScalar(-0.02), btScalar(kDropHeight)), tilt);
  box->setAngularVelocity(btVector3(0, 0, btScalar(2.0)));
  box->setActivationState(DISABLE_DEACTIVATION);  // the hash must not depend on sleeping heuristics
  return box;
}

class RigidDrop final : public Scene {
 public:
  explicit RigidDrop(const SceneOptions& o)
      : o_(o), ground_(world_, tile_settings(o), bowl), box_(drop_box(world_)), initial_clearance_(clearance()) {}

  void step() override {
    world_.step(o_.substep);
    ++k_;
  }

  void observe() override {
    const double gap = clearance();
    max_penetration_ = std::max(max_penetration_, -gap);
    if (landing_time_ < 0.0 && gap < 1e-3) landing_time_ = k_ * o_.substep;
    const btVector3 c = box_->getWorldTransform().getOrigin();
    if (c.z() < ground_.height_at(c.x(), c.y())) ++fallthrough_;
  }

  [[nodiscard]] SceneState state() const override {
    return {.bodies = {box_}, .rigid_grounds = {&ground_.tile()}, .layout = HashLayout::bullet_scalars};
  }

  void measure(nlohmann::json& m) const override {
    const double rest_gap = clearance();
    const btVector3 up = box_->getWorldTransform().getBasis().getColumn(2);
    const int columns = ground_.tile().columns();
    m["ground"] = "rigid heightfield tile, " + std::to_string(columns) + " x " + std::to_string(columns) + " vertices";
    m["box_mass_kg"] = kMass;
    m["landing_time_s"] = landing_time_;
    m["max_penetration_m"] = max_penetration_;
    m["rest_gap_m"] = rest_gap;
    m["rest_speed_mps"] = box_->getLinearVelocity().length();
    m["rest_tilt_rad"] = std::acos(std::clamp(static_cast<double>(std::abs(up.z())), 0.0, 1.0));
    m["fallthrough_count"] = fallthrough_;
    // Free fall from rest (spin about the vertical keeps corner heights): the lowest corner
    // reaches 1 mm above the plateau after sqrt(2 (d0 - 1 mm) / g), to within a substep.
    add_check(m, "landing_time_s", landing_time_, std::sqrt(2.0 * (initial_clearance_ - 1e-3) / 9.81), 1.5 * o_.substep,
              "free fall from rest: t = sqrt(2 d / g)");
    add_check(m, "rest_gap_m", rest_gap, 0.0, 0.005, "rigid contact: a box at rest touches the ground");
  }

  [[nodiscard]] std::vector<int> film_substeps() const override { return evenly_spread_film(o_.substeps(), o_.smoke); }
  Image film_frame(Painter& painter) override {
    return painter.paint(contents(), {.elevation_deg = 30.0, .legend = false, .width = 320});
  }

  SceneContents contents() override { return {.world = &world_, .bounds = bounds_of(ground_.grid()), .clock = &k_}; }

  void draw(Drawing& out) const override {
    out.view("top.png",
             {.camera = View::Camera::top, .width = 640, .title = "rigid_drop: the box on the rigid ground"});
    out.view("view.png",
             {.elevation_deg = 30.0, .width = 640, .title = "rigid_drop at " + time_label(k_ * o_.substep)});
    out.filmstrip();
    out.obj("ground.obj", ground_.grid());
  }

 private:
  /// Smallest height of a box corner above the ground under it (negative: penetration).
  [[nodiscard]] double clearance() const {
    double gap = 1e9;
    const btTransform& t = box_->getWorldTransform();
    for (int c = 0; c < 8; ++c) {
      const btVector3 local((c & 1) ? kHalf.x() : -kHalf.x(), (c & 2) ? kHalf.y() : -kHalf.y(),
                            (c & 4) ? kHalf.z() : -kHalf.z());
      const btVector3 p = t * local;
      gap = std::min(gap, static_cast<double>(p.z()) - ground_.height_at(p.x(), p.y()));
    }
    return gap;
  }

  SceneOptions o_;
  World world_;
  RigidGround ground_;
  btRigidBody* box_;
  double initial_clearance_;
  int k_ = 0;
  double max_penetration_ = 0.0, landing_time_ = -1.0;
  long fallthrough_ = 0;
};

}  // namespace

SceneType rigid_drop_scene() {
  return {
      .name = "rigid_drop",
      .description =
          "A 0.3 x 0.3 x 0.2 m, 10 kg box, tilted and spinning, is dropped from 0.45 m onto a rigid Bullet "
          "heightfield tile (a flat plateau inside a rippled bowl). Plain Bullet, no soil: the box bounces, "
          "settles on the plateau and leaves no trace. It exercises the whole scene pipeline (pictures, mesh, "
          "metrics, hash) and is the rigid-ground reference for the deformable scenes.",
      .defaults = {.seconds = 2.0, .substep = 1.0 / 240.0, .material = "sand", .cell = 0.01, .smoke_seconds = 1.0},
      .metric_help =
          {
              {"ground", "what the box lands on"},
              {"box_mass_kg", "mass of the box, kg"},
              {"landing_time_s", "first time a box corner is within 1 mm of the ground, s"},
              {"max_penetration_m", "deepest a box corner went below the ground surface, m"},
              {"rest_gap_m", "at the end: lowest box corner minus the ground under it, m (0 when resting)"},
              {"rest_speed_mps",
               "at the end: speed of the box centre, m/s (Bullet's box-on-heightfield contact jitters)"},
              {"rest_tilt_rad", "at the end: angle between the box's up axis and the vertical, rad"},
              {"fallthrough_count", "substeps with the box centre below the ground (must be 0)"},
          },
      .create = make_scene<RigidDrop>,
  };
}

}  // namespace shore::scenes
