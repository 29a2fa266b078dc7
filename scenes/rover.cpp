// rover: a six-wheeled robot built as a btMultiBody (Featherstone: a chassis base and six
// wheels on revolute joints, each driven by a btMultiBodyJointMotor) climbs a sand dune,
// runs down its far side into a pool of shallow water, wades through it and climbs out.
// Every wheel is a link added to the terrain coupling (TerrainCoupling::add_link): it sinks,
// slips, pulls and leaves a rut; the chassis is a link of both couplings (it floats and drags
// in the pool and makes a wake). The wheels are open-spoked: they are not added to the water.
// The scene reports the drawbar pull and slip of the climb, checks the pull against the
// rover's weight along the slope and its change of momentum (Newton), and what the pool did.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <BulletDynamics/Featherstone/btMultiBodyJointMotor.h>

#include "shore/bullet/terrain_coupling.h"
#include "shore/bullet/water_coupling.h"
#include "shore/scenes/film.h"
#include "shore/scenes/runner.h"
#include "shore/scenes/scene.h"
#include "shore/scenes/soil_cases.h"
#include "shore/scenes/soil_view.h"
#include "shore/scenes/world.h"
#include "shore/terrain/height_source.h"
#include "shore/terrain/material.h"
#include "shore/terrain/terrain.h"
#include "shore/water/surface.h"

namespace shore::scenes {
namespace {

// The course along x: flat start, the dune's climb, its crest, the run down, the pool's bed,
// the climb out. Each slope eases in and out over a metre (blended_ramp).
constexpr double kClimbGrade = 0.15, kClimbFrom = 0.0, kClimbTo = 7.0;          // rises 0.9 m
constexpr double kDescentGrade = -0.34, kDescentFrom = 8.5, kDescentTo = 13.5;  // falls 1.36 m
constexpr double kExitGrade = 0.2, kExitFrom = 19.0, kExitTo = 22.0;            // rises 0.4 m
constexpr double kWaterLevel = -0.15;                                           // m, the pool's still water
constexpr double kPoolX0 = 11.5, kPoolX1 = 22.5;                                // m, the water surface along x
constexpr double kPoolHalfY = 3.8;                                              // m, and across (the banks close it)
constexpr double kTrackHalf = 2.5;                                  // m, the flat track's half width; banks rise beyond
constexpr double kLandX0 = -4.0, kLandX1 = 26.0, kLandHalfY = 6.0;  // m, the land shown
constexpr double kStartX = -2.0;                                    // m, where the rover starts

// The rover: a chassis box and six wheels on its sides, three a side.
constexpr double kChassisMass = 120.0;                                             // kg
constexpr double kChassisHalfX = 0.6, kChassisHalfY = 0.4, kChassisHalfZ = 0.125;  // m
constexpr double kWheelMass = 6.0;                                                 // kg each
constexpr double kWheelRadius = 0.3, kWheelWidth = 0.25;                           // m
constexpr double kWheelX = 0.7, kWheelY = 0.6, kWheelZ = -0.1;                     // m, axles from the chassis' centre
constexpr double kCruise = 1.5;         // m/s, the wheels' rim speed the motors ask for
constexpr double kMotorTorque = 120.0;  // N m, most a wheel's motor applies
constexpr int kWheels = 6;

/// The integral of a slope of 1 between a and b that eases in over [a, a + 1] and out over
/// [b - 1, b] (smoothstep), from -inf to x: 0 before a, b - a - 1 after b.
double blended_ramp(double x, double a, double b) {
  const auto eased = [](double t) {  // integral of smoothstep over [0, t], t in [0, 1]
    return t * t * t - 0.5 * t * t * t * t;
  };
  if (x <= a) return 0.0;
  if (x <= a + 1.0) return eased(x - a);
  if (x <= b - 1.0) return 0.5 + (x - a - 1.0);
  if (x <= b) return (b - a - 1.0) - eased(b - x);
  return b - a - 1.0;
}

btVector3 chassis_half() { return {btScalar(kChassisHalfX), btScalar(kChassisHalfY), btScalar(kChassisHalfZ)}; }
/// A wheel's cylinder: its axis along the link's y.
btVector3 wheel_half() { return {btScalar(kWheelRadius), btScalar(kWheelWidth / 2), btScalar(kWheelRadius)}; }

double smoothstep(double t) {
  const double u = std::clamp(t, 0.0, 1.0);
  return u * u * (3.0 - 2.0 * u);
}

/// The course: the dune and the pool along x, banks rising beside the track, lattice noise
/// on top (polynomials and lattice noise only: the same bits on every machine).
class Course final : public terrain::HeightSource {
 public:
  Course()
      : noise_(terrain::LatticeNoiseSettings{
            .seed = 11, .spacing = 3.0, .amplitude = 0.12, .mean = 0.0, .octaves = 3, .persistence = 0.5}) {}
  [[nodiscard]] double height(double x, double y) const override {
    const double banks = 1.4 * smoothstep((std::abs(y) - kTrackHalf) / 3.0);
    const double calm = 0.15 + 0.85 * smoothstep((std::abs(y) - kTrackHalf + 1.0) / 2.0);  // a smoother track
    return line(x) + banks + calm * noise_.height(x, y);
  }
  /// The course's height along the track's centre line, without noise.
  [[nodiscard]] static double line(double x) {
    return kClimbGrade * blended_ramp(x, kClimbFrom, kClimbTo) +
           kDescentGrade * blended_ramp(x, kDescentFrom, kDescentTo) + kExitGrade * blended_ramp(x, kExitFrom, kExitTo);
  }

 private:
  terrain::LatticeNoise noise_;
};

double land_cell(const SceneOptions& o) { return o.smoke ? std::max(o.cell, 0.08) : o.cell; }

terrain::TerrainSettings land_settings(const SceneOptions& o) {
  terrain::TerrainSettings s = soil_settings(o);
  s.cell = land_cell(o);
  s.base = std::make_shared<Course>();
  return s;
}

water::SurfaceSettings pool_settings(const SceneOptions& o) {
  water::PhysicalParameters phys;
  phys.cell = 2.0 * land_cell(o);
  phys.depth = 0.25;  // the pool's mean depth sets the wave speed
  const int nx = static_cast<int>(std::lround((kPoolX1 - kPoolX0) / phys.cell)) + 1;
  const int ny = static_cast<int>(std::lround(2.0 * kPoolHalfY / phys.cell)) + 1;
  water::SurfaceSettings s = water::SurfaceSettings::physical(phys, nx, ny);
  s.origin_x = kPoolX0;
  s.origin_y = -kPoolHalfY;
  s.rest_height = kWaterLevel;
  s.mode = water::SurfaceMode::vertical_only;
  s.boundary = water::Boundary::vertical_only;
  s.threads = o.threads;
  return s;
}

/// The rover as a multibody: the chassis is its base, wheel k its link k (left side, +y:
/// links 0 to 2 from the front; right side: 3 to 5), each turning about its axle (y).
std::unique_ptr<btMultiBody> make_rover(const btVector3& at) {
  btVector3 chassis_inertia, wheel_inertia;
  btBoxShape(chassis_half()).calculateLocalInertia(btScalar(kChassisMass), chassis_inertia);
  btCylinderShape(wheel_half()).calculateLocalInertia(btScalar(kWheelMass), wheel_inertia);
  auto mb = std::make_unique<btMultiBody>(kWheels, btScalar(kChassisMass), chassis_inertia, false, false);
  mb->setBasePos(at);
  for (int k = 0; k < kWheels; ++k) {
    const double x = kWheelX * double(1 - k % 3), y = k < 3 ? kWheelY : -kWheelY;
    mb->setupRevolute(k, btScalar(kWheelMass), wheel_inertia, -1, btQuaternion::getIdentity(), btVector3(0, 1, 0),
                      btVector3(btScalar(x), btScalar(y), btScalar(kWheelZ)), btVector3(0, 0, 0), true);
  }
  mb->finalizeMultiDof();
  mb->setHasSelfCollision(false);
  mb->setLinearDamping(0);  // no drag but the soil's and the water's
  mb->setAngularDamping(0);
  mb->setCanSleep(false);
  return mb;
}

/// Running means of what the climb measures.
struct Climb {
  double pull = 0.0, weight_share = 0.0, slip = 0.0;  ///< sums of N, N and slip
  double v0 = 0.0, v1 = 0.0;                          ///< m/s along the heading, first and last sample
  double seconds = 0.0;                               ///< s sampled
  int samples = 0;
  [[nodiscard]] double mean(double sum) const { return sum / std::max(samples, 1); }
};

class Rover final : public Scene {
 public:
  explicit Rover(const SceneOptions& o)
      : o_(o),
        world_(9.81, {}, Dynamics::featherstone),
        land_(land_settings(o)),
        pool_(pool_settings(o)),
        ground_(world_.world(), land_),
        water_(world_.world(), pool_) {
    water_.fix_shoreline(land_);
    const double start_z = Course::line(kStartX) + kWheelRadius - kWheelZ + 0.03;
    rover_ = world_.add_multibody(make_rover(btVector3(btScalar(kStartX), 0, btScalar(start_z))));
    chassis_ = world_.add_collider(rover_, -1, std::make_unique<btBoxShape>(chassis_half()));
    for (int k = 0; k < kWheels; ++k) {
      wheels_[k] = world_.add_collider(rover_, k, std::make_unique<btCylinderShape>(wheel_half()));
      ground_.add_link(wheels_[k]);
      motors_[k] = static_cast<btMultiBodyJointMotor*>(world_.add_multibody_constraint(
          std::make_unique<btMultiBodyJointMotor>(rover_, k, btScalar(0), btScalar(kMotorTorque * o.substep))));
    }
    ground_.add_link(chassis_);  // if it bellies out on the crest
    water_.add_link(chassis_);
  }

  void step() override {
    if (!driven_) script();
    world_.step(o_.substep);
    ++k_;
  }

  void observe() override {
    const btVector3 at = rover_->getBasePos(), forward = heading();
    distance_ = std::max(distance_, double(at.x()) - kStartX);
    const double v = double(rover_->getBaseVel().dot(forward)), rim = kWheelRadius * mean_wheel_rate();
    if (at.z() < land_.bedrock(land_.column_i(at.x()), land_.column_j(at.y()))) ++fallthrough_;
    in_water_ = std::max(in_water_, water_.submerged_volume(chassis_));
    lifted_ = std::max(lifted_, double(water_.water_force(chassis_).force.z()));
    // The climb: the steady part of the dune's slope, the rover wholly on it.
    if (at.x() > kClimbFrom + 2.0 && at.x() < kClimbTo - 2.0) {
      if (climb_.samples == 0) climb_.v0 = v;
      climb_.v1 = v;
      double pull = 0.0;
      for (const btMultiBodyLinkCollider* w : wheels_) pull += double(ground_.terrain_force(w).force.dot(forward));
      climb_.pull += pull;
      climb_.weight_share += total_mass() * 9.81 * double(forward.z());
      climb_.slip += rim > 0.05 ? 1.0 - v / rim : 0.0;
      climb_.seconds += o_.substep;
      ++climb_.samples;
    }
    if (at.x() > kDescentTo + 0.5 && at.x() < kExitFrom && rim > 0.05) {  // wading, on the pool's bed
      wade_slip_ += 1.0 - v / rim;
      ++wade_samples_;
    }
  }

  [[nodiscard]] SceneState state() const override {
    return {.soils = {&land_}, .waters = {&pool_}, .multibodies = {rover_}};
  }

  void measure(nlohmann::json& m) const override {
    m["distance_m"] = distance_;
    m["mean_speed_mps"] = distance_ / std::max(o_.seconds, o_.substep);
    m["fallthrough_count"] = fallthrough_ + ground_.stats().rescues;
    m["volume_drift_rel"] = volume_drift_rel(land_);
    m["deepest_rut_m"] = deepest_rut();
    m["chassis_submerged_m3"] = in_water_;
    m["chassis_lift_N"] = lifted_;
    m["water_displaced_m3"] = water_.stats().displaced_volume;
    m["skipped_links"] = ground_.stats().skipped_bodies + water_.stats().skipped_bodies;
    if (climb_.samples > 0) {
      const double pull = climb_.mean(climb_.pull), weight = climb_.mean(climb_.weight_share);
      const double accelerate = total_mass() * (climb_.v1 - climb_.v0) / std::max(climb_.seconds, o_.substep);
      m["climb_drawbar_pull_N"] = pull;
      m["climb_slip"] = climb_.mean(climb_.slip);
      m["climb_weight_along_slope_N"] = weight;
      // Newton along the heading: the soil's net push (traction less rolling resistance) is
      // what lifts the rover's weight up the slope and changes its speed.
      add_check(m, "climb_drawbar_pull_vs_weight_and_momentum", pull, weight + accelerate, 0.1 * std::max(weight, 50.0),
                "Newton's second law along the heading (m g sin(slope) + m dv/dt)");
    }
    if (wade_samples_ > 0) m["wade_slip"] = wade_slip_ / wade_samples_;
  }

  [[nodiscard]] std::vector<int> film_substeps() const override { return evenly_spread_film(o_.substeps(), o_.smoke); }
  Image film_frame(Painter& painter) override {
    return painter.paint(contents(),
                         {.region = around_rover(3.0), .elevation_deg = 30.0, .legend = false, .width = 320});
  }

  SceneContents contents() override {
    SceneContents c{.world = &world_,
                    .soils = {{&land_, &ground_, {}}},
                    .waters = {{&pool_, &water_}},
                    .bounds = {kLandX0, -kLandHalfY, kLandX1, kLandHalfY},
                    .focus = chassis_,
                    .clock = &k_};
    c.drive = [this](double forward, double turn) {
      driven_ = forward != 0.0 || turn != 0.0;
      if (driven_) drive(kCruise * forward, 0.5 * turn);
    };
    return c;
  }

  void draw(Drawing& out) const override {
    const int w = o_.smoke ? 320 : 1280;
    const std::string when = time_label(k_ * o_.substep);
    out.view("view.png", {.region = around_rover(4.0),
                          .target_z = double(rover_->getBasePos().z()) - 0.5,
                          .elevation_deg = 25.0,
                          .azimuth_deg = -135.0,
                          .ground = View::Ground::natural,
                          .width = w,
                          .title = "rover: a six-wheeled btMultiBody on sand and in water at " + when});
    out.view("course.png", {.elevation_deg = 28.0,
                            .azimuth_deg = -70.0,
                            .ground = View::Ground::natural,
                            .width = w,
                            .title = "rover: the dune, its ruts and the pool at " + when});
    out.view("ruts.png", {.camera = View::Camera::top,
                          .region = {kStartX - 1.0, -2.0, kStartX + std::max(distance_, 4.0) + 1.5, 2.0},
                          .ground = View::Ground::sinkage,
                          .bodies = false,
                          .width = w,
                          .title = "rover: sinkage of its six wheels' ruts, rover removed"});
    out.filmstrip();
  }

 private:
  /// The rover's forward direction (its chassis' x axis), world coordinates.
  [[nodiscard]] btVector3 heading() const {
    return quatRotate(rover_->getWorldToBaseRot().inverse(), btVector3(1, 0, 0));
  }
  [[nodiscard]] double total_mass() const { return kChassisMass + kWheels * kWheelMass; }
  [[nodiscard]] double mean_wheel_rate() const {
    double sum = 0.0;
    for (int k = 0; k < kWheels; ++k) sum += double(rover_->getJointVel(k));
    return sum / kWheels;
  }
  /// Where the rover is: a square of half side `half` around it.
  [[nodiscard]] Bounds around_rover(double half) const {
    const btVector3 c = rover_->getBasePos();
    return {double(c.x()) - half, double(c.y()) - half, double(c.x()) + half, double(c.y()) + half};
  }
  /// Rim speed `speed` (m/s) on every wheel, the right side faster and the left slower by
  /// `turn` of it (turn > 0 turns left).
  void drive(double speed, double turn) {
    for (int k = 0; k < kWheels; ++k) {
      const double side = k < 3 ? -1.0 : 1.0;
      motors_[k]->setVelocityTarget(btScalar(speed * (1.0 + side * turn) / kWheelRadius));
    }
  }
  /// Straight along the track's centre line at cruise speed: steer back onto y = 0.
  void script() {
    const btVector3 at = rover_->getBasePos(), forward = heading();
    const double want = std::atan2(-double(at.y()), 3.0), have = std::atan2(forward.y(), forward.x());
    drive(kCruise, std::clamp(2.5 * (want - have), -0.4, 0.4));
  }
  [[nodiscard]] double deepest_rut() const {
    double most = 0.0;
    const double x1 = kStartX + distance_ + 1.0;
    for (std::int64_t j = land_.column_j(-1.0); j <= land_.column_j(1.0); ++j)
      for (std::int64_t i = land_.column_i(kStartX); i <= land_.column_i(x1); ++i)
        most = std::max(most, land_.base_height(i, j) - land_.height(i, j));
    return most;
  }

  SceneOptions o_;
  World world_;
  terrain::Terrain land_;
  water::Surface pool_;
  bullet::TerrainCoupling ground_;
  bullet::WaterCoupling water_;
  btMultiBody* rover_ = nullptr;
  btMultiBodyLinkCollider* chassis_ = nullptr;
  std::array<btMultiBodyLinkCollider*, kWheels> wheels_{};
  std::array<btMultiBodyJointMotor*, kWheels> motors_{};
  int k_ = 0;
  bool driven_ = false;
  double distance_ = 0.0, in_water_ = 0.0, lifted_ = 0.0, wade_slip_ = 0.0;
  int wade_samples_ = 0;
  long fallthrough_ = 0;
  Climb climb_;
};

}  // namespace

SceneType rover_scene() {
  return {
      .name = "rover",
      .description =
          "A six-wheeled rover (156 kg) built as a btMultiBody: a chassis and six wheels on revolute joints, each "
          "driven by a btMultiBodyJointMotor at 1.5 m/s rim speed. It climbs a sand dune (15 % grade), runs down its "
          "far side into a pool of shallow water, wades through it and climbs out. Every wheel is a link of the "
          "terrain coupling (add_link): it sinks, slips and leaves a rut; the chassis floats and drags in the pool "
          "and makes a wake. climb_drawbar_pull_N and climb_slip are measured on the dune's steady slope, where the "
          "pull is checked against the weight along the slope (Newton). In the viewer the arrow keys drive it.",
      .defaults = {.seconds = 26.0, .substep = 1.0 / 60.0, .material = "sand", .cell = 0.04, .smoke_seconds = 1.0},
      .metric_help =
          {
              {"distance_m", "farthest the rover got along the course, m"},
              {"mean_speed_mps", "distance over the run's time, m/s"},
              {"fallthrough_count", "times the chassis was below bedrock or a link was lifted back (must be 0)"},
              {"volume_drift_rel", "|ground + compacted + airborne - edited| / moved volume (must be < 1e-6)"},
              {"deepest_rut_m", "largest lowering of the ground below its untouched surface along the track, m"},
              {"chassis_submerged_m3", "largest volume of the chassis under water, m^3"},
              {"chassis_lift_N", "largest upward force of the water on the chassis (buoyancy and drag), N"},
              {"water_displaced_m3", "water the rover pushed aside in total (signed), m^3"},
              {"skipped_links", "link-substeps the couplings skipped (must be 0)"},
              {"climb_drawbar_pull_N", "mean soil push on the wheels along the heading on the dune's slope, N"},
              {"climb_slip", "mean slip 1 - v / (omega R) on the dune's slope"},
              {"climb_weight_along_slope_N", "mean m g sin(slope) on the dune's slope, N"},
              {"wade_slip", "mean slip on the pool's bed"},
          },
      .create = make_scene<Rover>,
  };
}

}  // namespace shore::scenes
