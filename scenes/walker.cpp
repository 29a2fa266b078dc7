// walker: a stock btKinematicCharacterController (Bullet's CharacterDemo set-up: a capsule on
// a btPairCachingGhostObject filtered to StaticFilter | DefaultFilter) walks by a script up a
// winding trail, over sand, then snow: one terrain with a material map, on a hillside. It is
// the README's recipe for characters ("Cars and characters"): the controller walks on the
// coupling's tiles as Bullet's controller walks on any static heightfield, and its two feet
// are kinematic boxes added to the coupling, animated by the scene as a game animates them.
// Each foot is planted under the capsule, heel first, rolls flat, rolls onto the toe and
// lifts off, pressed as deep as Bekker's plate sinkage for the character's weight on one
// foot in the material under it: a few centimetres in sand, a quarter of a metre in snow.
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <BulletCollision/CollisionDispatch/btGhostObject.h>
#include <BulletDynamics/Character/btKinematicCharacterController.h>

#include "shore/bullet/terrain_coupling.h"
#include "shore/core/det_math.h"
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

// ---- the character ----------------------------------------------------------------------------
constexpr double kMass = 75.0;                         // kg: its weight rests on one foot in single stance
constexpr double kGravity = 9.81;                      // m/s^2, World's
constexpr double kRadius = 0.25;                       // m, the capsule's
constexpr double kCylinder = 1.2;                      // m, the capsule's straight part (1.7 m tall in all)
constexpr double kStepHeight = 0.3;                    // m, the controller's step height
constexpr double kSpeed = 1.3;                         // m/s the script walks at
constexpr double kStandZ = kRadius + 0.5 * kCylinder;  // m, capsule centre above its lowest point

// ---- the feet and the gait ----------------------------------------------------------------------
constexpr double kFootLength = 0.26;  // m
constexpr double kFootWidth = 0.10;   // m (Bekker's smaller plate width b)
constexpr double kFootHeight = 0.07;  // m
constexpr double kStepWidth = 0.09;   // m, each foot's offset from the capsule's line
constexpr double kReach = 0.30;       // m a print lands ahead of the capsule's centre at heel strike
constexpr double kStart = 0.30;       // s, the first heel strike (the controller has landed)
constexpr double kStepTime = 0.50;    // s between heel strikes (left, right, left, ...)
constexpr double kHeelUp = 0.30;      // rad, toe-up pitch at heel strike
constexpr double kToeDown = 0.45;     // rad, heel-up pitch when the toe lifts
constexpr double kClearance = 0.05;   // m the sole passes above the ground when swinging
// Stance phases, s: land on the heel, roll flat, stand, roll onto the toe, lift. Their sum
// is longer than a step: both feet are down for a moment.
constexpr std::array<double, 5> kPhase = {0.06, 0.08, 0.28, 0.14, 0.06};
constexpr double kStance = kPhase[0] + kPhase[1] + kPhase[2] + kPhase[3] + kPhase[4];

// ---- the place --------------------------------------------------------------------------------
constexpr double kX0 = -1.5, kX1 = 13.0;       // m, the land along the trail
constexpr double kHalfY = 4.0;                 // m, the land across it
constexpr double kGrade = 0.06;                // the hillside's rise along x
constexpr double kSnowX = 5.0;                 // m, where the snow begins (the edge winds around it)
constexpr double kSmokeStartX = kSnowX - 1.0;  // m: a smoke run starts just below the snow
constexpr int kFeetFilter = 1 << 12;           // the feet's broadphase group: the capsule's mask leaves it out

double smooth(double u) {
  u = std::clamp(u, 0.0, 1.0);
  return u * u * (3.0 - 2.0 * u);
}

double bump(double r, double radius) {  // 1 at the centre, 0 from radius on, smooth (polynomial)
  const double u = std::clamp(1.0 - (r * r) / (radius * radius), 0.0, 1.0);
  return u * u;
}

/// y of the trail's middle at x: it winds gently up the hillside.
double trail_y(double x) { return 0.9 * (bump(x - 2.5, 4.0) - bump(x - 9.0, 4.0)); }
double trail_slope(double x) { return (trail_y(x + 1e-3) - trail_y(x - 1e-3)) / 2e-3; }

/// x of the snow's lower edge at y: it winds too.
double snow_edge(double y) { return kSnowX + 0.6 * (bump(y - 2.0, 2.5) - bump(y + 1.5, 2.0)); }

/// The hillside: rising 6 % along x, low hills each side of the trail, dunes and drifts of
/// lattice noise (calmer on the trail), and the trail itself a shallow trough, flat 0.6 m
/// across. Polynomials and lattice noise only: the same bits on every machine.
class Hillside final : public terrain::HeightSource {
 public:
  Hillside()
      : noise_(terrain::LatticeNoiseSettings{
            .seed = 11, .spacing = 1.6, .amplitude = 0.12, .mean = 0.0, .octaves = 3, .persistence = 0.45}) {}
  [[nodiscard]] double height(double x, double y) const override {
    const double off = y - trail_y(x), across = std::abs(off) / kHalfY;
    const double sides = 0.9 * across * across * (3.0 - 2.0 * across);
    const double trail = 1.0 - smooth((std::abs(off) - 0.3) / 0.5);  // 1 on the trail, 0 off it
    const double calm = 1.0 - 0.85 * trail;
    return kGrade * x + sides + calm * noise_.height(x, y) - 0.04 * trail;
  }

 private:
  terrain::LatticeNoise noise_;
};

/// Where a foot presses one print: the sole's centre at depth, its heading, the ground's
/// slope under it, and the depth.
struct Print {
  double x = 0.0, y = 0.0, z = 0.0;  // m, the pressed sole's centre
  double heading = 0.0;              // rad from +x
  double pitch = 0.0, roll = 0.0;    // rad, the ground's slope along and across the foot
  double depth = 0.0;                // m below the untouched ground
  double base = 0.0;                 // m, the untouched ground at the centre
  int material = 0;                  // palette entry under the centre
};

/// A pose in a print's own frame: u forward, w up from the pressed sole, pitch toe-up.
struct SolePose {
  double u = 0.0, w = 0.0, pitch = 0.0;  // the box's centre
};
SolePose from_heel(double u, double w, double pitch) {  // the sole's heel edge at (u, w)
  const double c = det::cos(pitch), s = det::sin(pitch), a = 0.5 * kFootLength, b = 0.5 * kFootHeight;
  return {u + a * c - b * s, w + a * s + b * c, pitch};
}
SolePose from_toe(double u, double w, double pitch) {  // the sole's toe edge at (u, w)
  const double c = det::cos(pitch), s = det::sin(pitch), a = 0.5 * kFootLength, b = 0.5 * kFootHeight;
  return {u - a * c - b * s, w - a * s + b * c, pitch};
}

/// Stance of a print, t in [0, kStance] s after the heel strike began.
SolePose stance(const Print& p, double t) {
  const double heel = -0.5 * kFootLength, toe = 0.5 * kFootLength;
  if (t < kPhase[0]) {  // the heel comes down and forward through the soil, toe up
    const double s = smooth(t / kPhase[0]);
    return from_heel(heel - 0.05 * (1 - s), (p.depth + kClearance) * (1 - s), kHeelUp);
  }
  t -= kPhase[0];
  if (t < kPhase[1]) return from_heel(heel, 0.0, kHeelUp * (1 - smooth(t / kPhase[1])));  // roll flat
  t -= kPhase[1];
  if (t < kPhase[2]) return from_heel(heel, 0.0, 0.0);  // stand
  t -= kPhase[2];
  if (t < kPhase[3]) return from_toe(toe, 0.0, -kToeDown * smooth(t / kPhase[3]));  // roll onto the toe
  t -= kPhase[3];
  const double s = smooth(t / kPhase[4]);  // the toe lifts out of the print, up first
  return from_toe(toe + 0.03 * s, (p.depth + kClearance) * s, -kToeDown);
}

btQuaternion rotation(double heading, double pitch, double roll) {
  // Heading about z, then toe-up pitch (about the foot's y, negative lifts its +x end), then
  // roll about the foot's x.
  return btQuaternion(btVector3(0, 0, 1), btScalar(heading)) * btQuaternion(btVector3(0, 1, 0), btScalar(-pitch)) *
         btQuaternion(btVector3(1, 0, 0), btScalar(roll));
}

btTransform world_pose(const Print& p, const SolePose& s) {
  const btQuaternion frame = rotation(p.heading, p.pitch, p.roll);
  const btVector3 local(btScalar(s.u), 0, btScalar(s.w));
  return btTransform(frame * btQuaternion(btVector3(0, 1, 0), btScalar(-s.pitch)),
                     btVector3(btScalar(p.x), btScalar(p.y), btScalar(p.z)) + quatRotate(frame, local));
}

/// Smoke runs (the tests) use 3 cm columns at least: the capsule's sweeps and contacts, which
/// take most of a substep, meet half as many heightfield triangles.
double land_cell(const SceneOptions& o) { return o.smoke ? std::max(o.cell, 0.03) : o.cell; }

terrain::TerrainSettings land_settings(const SceneOptions& o) {
  terrain::TerrainSettings s = soil_settings(o);
  s.cell = land_cell(o);
  s.material = terrain::Material::sand();
  s.base = std::make_shared<Hillside>();
  return s;
}

/// The capsule meets the soil's surface sampled every second column (4 cm triangles on the
/// scene's 2 cm columns): its sweeps and contacts are most of a substep, and meet a quarter
/// as many triangles (3.7 x faster, the capsule 1 mm lower on average; every fourth column
/// drops it into the 10 cm prints, 2 cm deeper: docs/BENCHMARKS.md). The feet, added to
/// the coupling, press and feel every column.
bullet::TerrainCouplingSettings ground_settings() {
  bullet::TerrainCouplingSettings s;
  s.tiles.contact_stride = 2;
  return s;
}

class Walker final : public Scene {
 public:
  explicit Walker(const SceneOptions& o)
      : o_(o),
        start_x_(o.smoke ? kSmokeStartX : 0.0),
        land_(land_settings(o)),
        ground_(world_.world(), land_, ground_settings()),
        prints_(planned_prints(o)),
        capsule_(btScalar(kRadius), btScalar(kCylinder)) {
    land_.set_palette({terrain::Material::sand(), terrain::Material::snow()});
    const GridRect land =
        GridRect::spanning(land_.column_i(kX0), land_.column_j(-kHalfY), land_.column_i(kX1), land_.column_j(kHalfY));
    land_.paint_where(
        land, [](double x, double y) { return x >= snow_edge(y); }, 1);
    add_character();
    add_feet();
    frame_ = grid_over(start_x_ - 1.0, -1.8, walk_end_x() + 1.0, 1.8, land_cell(o));
  }

  ~Walker() override {
    world_.world().removeAction(character_.get());
    world_.world().removeCollisionObject(&ghost_);
    world_.world().getBroadphase()->getOverlappingPairCache()->setInternalGhostPairCallback(nullptr);
  }
  Walker(const Walker&) = delete;
  Walker& operator=(const Walker&) = delete;

  void step() override {
    const double t = (k_ + 1) * o_.substep;
    if (!driven_) heading_ = steer();
    character_->setWalkDirection(btVector3(btScalar(det::cos(heading_)), btScalar(det::sin(heading_)), 0) *
                                 btScalar(speed_ * o_.substep));
    for (int f = 0; f < 2; ++f) {
      btRigidBody* foot = feet_[static_cast<std::size_t>(f)];
      foot->getMotionState()->setWorldTransform(foot_pose(f, t));
    }
    world_.step(o_.substep);
    ++k_;
  }

  void observe() override {
    const btVector3 c = ghost_.getWorldTransform().getOrigin();
    const std::int64_t i = land_.column_i(c.x()), j = land_.column_j(c.y());
    const double bottom = double(c.z()) - kStandZ, gap = bottom - land_.height(i, j);
    // Through the ground: below bedrock, or deeper into the soil than the controller's
    // sweeps allow (the world's allowed CCD penetration) and a centimetre more.
    const double allowed = world_.world().getDispatchInfo().m_allowedCcdPenetration;
    if (bottom < land_.bedrock(i, j) || gap < -allowed - 0.01) ++fallthrough_;
    if (k_ * o_.substep < kStart) return;  // landing from the start height
    gap_min_ = std::min(gap_min_, gap);
    gap_max_ = std::max(gap_max_, gap);
    gap_sum_ += gap;
    ++walked_;
    if (!character_->onGround()) ++airborne_;
    // Each print's depth at the first substep past the middle of its stance (the foot flat).
    const double t = k_ * o_.substep;
    for (std::size_t k = 0; k < planted_.size(); ++k) {
      const double since = t - strike_time(static_cast<int>(k));
      const double flat_mid = kPhase[0] + kPhase[1] + 0.5 * kPhase[2];
      if (standing_depth_[k] == 0.0 && since >= flat_mid) {
        standing_depth_[k] = print_depth(planted_[k]);
        standing_sinkage_[k] = print_depth(planted_[k], true);
      }
    }
  }

  [[nodiscard]] SceneState state() const override {
    return {
        .soils = {&land_}, .bodies = {feet_[0], feet_[1]}, .soil_heights = {sample(patches(), frame_, Field::height)}};
  }

  void measure(nlohmann::json& m) const override {
    const double pressure = kMass * kGravity / (kFootLength * kFootWidth);
    m["foot_pressure_Pa"] = pressure;
    m["planned_prints"] = prints_;
    m["fallthrough_count"] = fallthrough_ + ground_.stats().rescues;
    m["volume_drift_rel"] = volume_drift_rel(land_);
    m["distance_m"] = double(ghost_.getWorldTransform().getOrigin().x()) - start_x_;
    m["capsule_gap_mean_m"] = walked_ > 0 ? gap_sum_ / double(walked_) : 0.0;
    m["capsule_gap_min_m"] = walked_ > 0 ? gap_min_ : 0.0;
    m["capsule_gap_max_m"] = walked_ > 0 ? gap_max_ : 0.0;
    m["airborne_share"] = walked_ > 0 ? double(airborne_) / double(walked_) : 0.0;
    int found = 0;
    const double t = k_ * o_.substep;
    for (const char* name : {"sand", "snow"}) {
      const int entry = std::string(name) == "sand" ? 0 : 1;
      const terrain::Material& mat = land_.palette()[static_cast<std::size_t>(entry)];
      const double bekker = terrain::bekker::plate_sinkage(mat, kFootWidth, pressure);
      double standing = 0.0, left = 0.0, sunk = 0.0;
      int n = 0, lifted = 0;
      for (std::size_t k = 0; k < planted_.size(); ++k) {
        if (planted_[k].material != entry || standing_depth_[k] <= 0.0) continue;
        standing += standing_depth_[k];
        sunk += standing_sinkage_[k];
        ++n;
        if (t < strike_time(static_cast<int>(k)) + kStance) continue;
        const double d = print_depth(planted_[k]);
        left += d;
        ++lifted;
        if (d > 0.5 * bekker) ++found;
      }
      const std::string p = std::string(name) + "_";
      m[p + "prints"] = n;
      m[p + "bekker_sinkage_m"] = bekker;
      m[p + "standing_depth_m"] = n > 0 ? standing / n : 0.0;
      m[p + "print_depth_m"] = lifted > 0 ? left / lifted : 0.0;
      m[p + "standing_sinkage_m"] = n > 0 ? sunk / n : 0.0;
      m[p + "bearing_Pa"] = n > 0 ? terrain::bekker::pressure(mat, kFootWidth, sunk / n) : 0.0;
      if (n > 0)
        add_check(m, p + "standing_depth_m", standing / n, bekker, 0.1 * bekker,
                  "Bekker's plate sinkage (b = foot width) for the weight on one foot in " + std::string(name));
    }
    m["footprints_count"] = found;
    const int lifted_prints = lifted_count();
    if (lifted_prints > 0)
      add_check(m, "footprints_count", found, lifted_prints, 0.0,
                "the gait script: one print at least half Bekker's depth per lifted step");
    // The controller's sweeps accept the world's allowed CCD penetration (Bullet's default
    // 0.04 m), so its capsule rests that far into any ground it stands on, Bullet's own
    // heightfields as Shore's tiles: the soil's surface as pressed.
    const double allowed = world_.world().getDispatchInfo().m_allowedCcdPenetration;
    m["allowed_ccd_penetration_m"] = allowed;
    if (walked_ > 0)
      add_check(m, "capsule_gap_mean_m", gap_sum_ / double(walked_), -allowed, 0.01,
                "btKinematicCharacterController: its capsule rests the allowed CCD penetration into the ground");
    m["note"] = "the walker always crosses sand then snow (a material map); --material does not apply";
  }

  [[nodiscard]] std::vector<int> film_substeps() const override { return evenly_spread_film(o_.substeps(), o_.smoke); }

  Image film_frame(Painter& painter) override {
    return painter.paint(contents(), {.region = around_walker(2.5),
                                      .elevation_deg = 30.0,
                                      .azimuth_deg = -120.0,
                                      .ground = View::Ground::natural,
                                      .legend = false,
                                      .width = o_.smoke ? 240 : 320});
  }

  SceneContents contents() override {
    SceneContents c{.world = &world_,
                    .soils = {{&land_, &ground_, {}}},
                    .bounds = {kX0 + 0.5, -kHalfY + 1.0, kX1 - 0.5, kHalfY - 1.0},
                    .focus = &ghost_,
                    .clock = &k_};
    c.drive = [this](double forward, double turn) {
      driven_ = forward != 0.0 || turn != 0.0;
      speed_ = driven_ ? kSpeed * std::clamp(forward, 0.0, 1.5) : kSpeed;
      if (driven_) heading_ += 0.03 * turn;
    };
    return c;
  }

  void draw(Drawing& out) const override {
    const int w = o_.smoke ? 320 : 1280;
    const std::string when = time_label(k_ * o_.substep);
    out.view("view.png", {.region = {snow_edge(0.0) - 4.5, -2.2, snow_edge(0.0) + 5.5, 2.2},
                          .target_z = kGrade * snow_edge(0.0),
                          .elevation_deg = 32.0,
                          .azimuth_deg = -105.0,
                          .ground = View::Ground::natural,
                          .width = w,
                          .title = "walker: a character controller walks up a trail, sand then snow, at " + when});
    const double edge_x = snow_edge(trail_y(kSnowX));
    out.view("closeup.png", {.region = {edge_x - 1.2, trail_y(edge_x) - 0.6, edge_x + 1.2, trail_y(edge_x) + 0.6},
                             .target_z = kGrade * edge_x,
                             .elevation_deg = 40.0,
                             .azimuth_deg = -120.0,
                             .colour_scale = 0.1,
                             .bodies = false,
                             .width = o_.smoke ? 320 : 960,
                             .title = "walker: prints where the sand meets the snow"});
    out.view("trail.png", {.camera = View::Camera::top,
                           .region = bounds_of(frame_),
                           .ground = View::Ground::sinkage,
                           .bodies = false,
                           .width = w,
                           .title = "walker: sinkage of the prints, sand (left) then snow (right)"});
    out.view("hillside.png", {.elevation_deg = 40.0,
                              .ground = View::Ground::natural,
                              .width = w,
                              .title = "walker: the hillside, its trail, sand below the snow"});
    out.filmstrip();
    out.obj("ground.obj", sample(patches(), frame_, Field::height));
  }

 private:
  static int planned_prints(const SceneOptions& o) {  // heel strikes whose stance ends within the run
    return std::max(0, static_cast<int>(std::floor((o.seconds - kStart - kStance) / kStepTime + 1e-9)) + 1);
  }
  [[nodiscard]] double strike_time(int k) const { return kStart + k * kStepTime; }
  [[nodiscard]] double walk_end_x() const { return start_x_ + kSpeed * o_.seconds + 0.5; }
  [[nodiscard]] std::vector<Patch> patches() const { return {{&land_, {}}}; }
  [[nodiscard]] int lifted_count() const {
    int n = 0;
    for (std::size_t k = 0; k < planted_.size(); ++k)
      if (k_ * o_.substep >= strike_time(static_cast<int>(k)) + kStance && standing_depth_[k] > 0.0) ++n;
    return n;
  }
  [[nodiscard]] Bounds around_walker(double half) const {
    const btVector3 c = ghost_.getWorldTransform().getOrigin();
    return {double(c.x()) - half, double(c.y()) - half, double(c.x()) + half, double(c.y()) + half};
  }

  /// Bullet's CharacterDemo: a capsule on a pair-caching ghost object, colliding with static
  /// and default objects, its up the world's z.
  void add_character() {
    world_.world().getBroadphase()->getOverlappingPairCache()->setInternalGhostPairCallback(&ghost_pairs_);
    ghost_.setCollisionShape(&capsule_);
    ghost_.setCollisionFlags(btCollisionObject::CF_CHARACTER_OBJECT);
    character_ =
        std::make_unique<btKinematicCharacterController>(&ghost_, &capsule_, btScalar(kStepHeight), btVector3(0, 0, 1));
    const double y = trail_y(start_x_);
    const double ground = land_.settings().base->height(start_x_, y);
    ghost_.setWorldTransform(btTransform(
        btQuaternion::getIdentity(), btVector3(btScalar(start_x_), btScalar(y), btScalar(ground + kStandZ + 0.05))));
    world_.world().addCollisionObject(&ghost_, btBroadphaseProxy::CharacterFilter,
                                      btBroadphaseProxy::StaticFilter | btBroadphaseProxy::DefaultFilter);
    world_.world().addAction(character_.get());
    heading_ = steer();
  }

  /// Two kinematic boxes added to the coupling. Their broadphase group is one the capsule's
  /// mask leaves out: a capsule that collided with its own feet would stand on them.
  void add_feet() {
    for (int f = 0; f < 2; ++f) {
      const btTransform pose = foot_pose(f, 0.0);
      btRigidBody* foot =
          world_.add_body(std::make_unique<btBoxShape>(btVector3(btScalar(kFootLength / 2), btScalar(kFootWidth / 2),
                                                                 btScalar(kFootHeight / 2))),
                          0.0, pose);
      foot->setCollisionFlags((foot->getCollisionFlags() & ~btCollisionObject::CF_STATIC_OBJECT) |
                              btCollisionObject::CF_KINEMATIC_OBJECT);
      foot->setActivationState(DISABLE_DEACTIVATION);
      world_.world().removeRigidBody(foot);
      world_.world().addRigidBody(foot, kFeetFilter, btBroadphaseProxy::DefaultFilter);
      // No spray: the script drives a heel through 25 cm of snow in 0.06 s, faster than a
      // foot sinks, and the soil it threw would be the script's, not the walk's.
      ground_.add_body(foot, {.spray = false});
      feet_[static_cast<std::size_t>(f)] = foot;
    }
  }

  /// The script's heading: along the trail, turning back onto its middle.
  [[nodiscard]] double steer() const {
    const btVector3 c = ghost_.getWorldTransform().getOrigin();
    const double x = c.x(), y = c.y();
    return det::atan(trail_slope(x + 0.5)) + std::clamp(0.8 * (trail_y(x + 0.5) - y), -0.4, 0.4);
  }

  /// Where a print lands if its heel strikes `ahead` seconds from now: kReach ahead of where
  /// the capsule will be, kStepWidth to the foot's side, on the ground's slope there, as
  /// deep as Bekker's plate sinkage for the whole weight on one foot in that material.
  [[nodiscard]] Print plant(int foot, double ahead) const {
    const btVector3 c = ghost_.getWorldTransform().getOrigin();
    const double fx = det::cos(heading_), fy = det::sin(heading_);
    const double side = foot == 0 ? kStepWidth : -kStepWidth, forward = kReach + speed_ * std::max(ahead, 0.0);
    Print p;
    p.x = double(c.x()) + forward * fx - side * fy;
    p.y = double(c.y()) + forward * fy + side * fx;
    p.heading = heading_;
    const terrain::HeightSource& base = *land_.settings().base;
    const double a = 0.5 * kFootLength, b = 0.5 * kFootWidth;
    p.base = base.height(p.x, p.y);
    p.pitch = det::atan((base.height(p.x + a * fx, p.y + a * fy) - base.height(p.x - a * fx, p.y - a * fy)) / (2 * a));
    p.roll = -det::atan((base.height(p.x - b * fy, p.y + b * fx) - base.height(p.x + b * fy, p.y - b * fx)) / (2 * b));
    p.material = land_.material_index(land_.column_i(p.x), land_.column_j(p.y));
    const double pressure = kMass * kGravity / (kFootLength * kFootWidth);
    p.depth =
        terrain::bekker::plate_sinkage(land_.palette()[static_cast<std::size_t>(p.material)], kFootWidth, pressure);
    p.z = p.base - p.depth;
    return p;
  }

  /// Foot f (0 left: prints 0, 2, ...; 1 right) at time t: in the stance of a print, swinging
  /// to the next, or still. A print is planted at its heel strike and kept.
  btTransform foot_pose(int f, double t) {
    int next = f;
    while (next < prints_ && t >= strike_time(next) + kStance) next += 2;
    if (next < prints_ && t >= strike_time(next)) {
      if (planted_.size() <= static_cast<std::size_t>(next)) {
        planted_.resize(static_cast<std::size_t>(next) + 1);
        standing_depth_.resize(planted_.size(), 0.0);
        standing_sinkage_.resize(planted_.size(), 0.0);
      }
      Print& p = planted_[static_cast<std::size_t>(next)];
      if (p.depth == 0.0) p = plant(f, 0.0);
      return world_pose(p, stance(p, t - strike_time(next)));
    }
    // Swinging (or still): from where the last print lifted off (or from standing beside the
    // capsule) to the landing of the next one, in an arc that clears the ground.
    const btTransform from = next >= 2 ? world_pose(planted_[static_cast<std::size_t>(next - 2)],
                                                    stance(planted_[static_cast<std::size_t>(next - 2)], kStance))
                                       : rest_pose(f);
    if (next >= prints_) return from;
    const double t0 = next >= 2 ? strike_time(next - 2) + kStance : 0.0, t1 = strike_time(next);
    if (t <= t0) return from;
    const Print target = plant(f, t1 - t);
    const btTransform to = world_pose(target, stance(target, 0.0));
    const double s = smooth((t - t0) / (t1 - t0)), arc = 4.0 * s * (1.0 - s) * 0.08;
    btVector3 at = from.getOrigin().lerp(to.getOrigin(), btScalar(s));
    const double floor = land_.settings().base->height(at.x(), at.y()) + 0.5 * kFootHeight + kClearance;
    at.setZ(btScalar(std::max(double(at.z()) + arc, floor)));
    return btTransform(from.getRotation().slerp(to.getRotation(), btScalar(s)), at);
  }

  /// A foot standing beside the capsule's start, its sole just above the ground.
  [[nodiscard]] btTransform rest_pose(int f) const {
    Print p = plant(f, 0.0);
    const double back = kReach + (f == 0 ? 0.0 : 0.3);
    p.x -= back * det::cos(p.heading);
    p.y -= back * det::sin(p.heading);
    p.z = land_.settings().base->height(p.x, p.y) + 0.01;
    p.depth = 0.0;
    return world_pose(p, {0.0, 0.5 * kFootHeight, 0.0});
  }

  /// m, the mean lowering below the untouched ground of the columns under the middle of the
  /// sole (half its length, half its width).
  [[nodiscard]] double print_depth(const Print& p, bool sinkage = false) const {
    const double fx = det::cos(p.heading), fy = det::sin(p.heading), cell = land_.settings().cell;
    double sum = 0.0;
    int n = 0;
    for (std::int64_t j = land_.column_j(p.y - kFootLength); j <= land_.column_j(p.y + kFootLength); ++j)
      for (std::int64_t i = land_.column_i(p.x - kFootLength); i <= land_.column_i(p.x + kFootLength); ++i) {
        const double dx = double(i) * cell + land_.settings().origin_x - p.x;
        const double dy = double(j) * cell + land_.settings().origin_y - p.y;
        const double u = dx * fx + dy * fy, v = -dx * fy + dy * fx;
        if (std::abs(u) > 0.25 * kFootLength || std::abs(v) > 0.25 * kFootWidth) continue;
        sum += sinkage ? land_.sinkage(i, j) : land_.base_height(i, j) - land_.height(i, j);
        ++n;
      }
    return n > 0 ? sum / n : 0.0;
  }

  SceneOptions o_;
  double start_x_;
  World world_;
  terrain::Terrain land_;
  bullet::TerrainCoupling ground_;  // after the world and the soil
  int prints_;
  btCapsuleShapeZ capsule_;
  btPairCachingGhostObject ghost_;
  btGhostPairCallback ghost_pairs_;
  std::unique_ptr<btKinematicCharacterController> character_;
  std::array<btRigidBody*, 2> feet_{};
  std::vector<Print> planted_;            // per print, once its heel struck
  std::vector<double> standing_depth_;    // per print, m, measured in the middle of its stance
  std::vector<double> standing_sinkage_;  // per print, m, the soil's plastic sinkage then
  HeightGrid frame_;
  double heading_ = 0.0, speed_ = kSpeed;
  bool driven_ = false;
  int k_ = 0;
  long fallthrough_ = 0, walked_ = 0, airborne_ = 0;
  double gap_min_ = 1e9, gap_max_ = -1e9, gap_sum_ = 0.0;
};

}  // namespace

SceneType walker_scene() {
  return {
      .name = "walker",
      .description =
          "A stock btKinematicCharacterController (Bullet's CharacterDemo set-up: a 1.7 m capsule on a "
          "btPairCachingGhostObject) walks by a script at 1.3 m/s up a winding trail on a hillside, over sand, then "
          "snow: one terrain with a material map. It stands on the coupling's tiles as on any Bullet heightfield. "
          "Its two feet are kinematic 0.26 x 0.10 m boxes added to the coupling (the README's recipe): planted "
          "under the capsule heel first, rolled flat and onto the toe, pressed as deep as Bekker's plate sinkage for "
          "75 kg on one foot, 2.6 cm in sand, 26 cm in snow. When a foot lifts, the walls of a sand print slump to a "
          "soft outline while snow's stay steep. The "
          "camera follows the walker; in the viewer the arrow keys steer it.",
      .defaults = {.seconds = 8.0, .substep = 1.0 / 120.0, .material = "sand", .cell = 0.02, .smoke_seconds = 1.5},
      .metric_help =
          {
              {"foot_pressure_Pa", "the character's weight over one foot's area, Pa"},
              {"planned_prints", "heel strikes the script makes within the run"},
              {"fallthrough_count",
               "substeps the capsule was below bedrock or 1 cm deeper into the soil than the allowed CCD penetration, "
               "and rescues (must be 0)"},
              {"volume_drift_rel", "|ground + compacted - edited| / moved volume of the soil (must be < 1e-6)"},
              {"distance_m", "how far the capsule walked along x, m"},
              {"capsule_gap_mean_m", "the capsule's lowest point above the soil under it, mean over the walk, m"},
              {"capsule_gap_min_m", "the same, smallest, m"},
              {"capsule_gap_max_m", "the same, largest, m"},
              {"allowed_ccd_penetration_m",
               "the world's allowed CCD penetration, which the controller's sweeps accept, m"},
              {"airborne_share", "share of the walk's substeps the controller was not on the ground"},
              {"sand_prints", "prints planted in sand"},
              {"sand_bekker_sinkage_m", "Bekker's plate sinkage in sand for foot_pressure_Pa (b = foot width), m"},
              {"sand_standing_depth_m", "the ground's lowering under the sole's middle at mid-stance, mean, m"},
              {"sand_print_depth_m", "the same after the foot lifted (the print left), mean, m"},
              {"sand_standing_sinkage_m", "the soil's plastic sinkage under the sole's middle at mid-stance, mean, m"},
              {"sand_bearing_Pa",
               "Bekker's pressure at that sinkage: what the print now bears (foot_pressure_Pa if "
               "it carries the character), Pa"},
              {"snow_prints", "prints planted in snow"},
              {"snow_bekker_sinkage_m", "Bekker's plate sinkage in snow for foot_pressure_Pa, m"},
              {"snow_standing_depth_m", "as for sand, m"},
              {"snow_print_depth_m", "as for sand, m"},
              {"snow_standing_sinkage_m", "as for sand, m"},
              {"snow_bearing_Pa", "as for sand, Pa"},
              {"footprints_count", "lifted prints at least half Bekker's depth deep"},
              {"note", "what --material means here"},
          },
      .create = make_scene<Walker>,
  };
}

}  // namespace shore::scenes
