// footprints: a walker's two feet stride six steps across three strips of ground side by
// side, sand, mud and snow (Sumner, O'Brien & Hodgins 1998, figure 5: the same motion in
// three materials). The feet are kinematic boxes moved along a scripted gait with a
// heel-to-toe roll: each foot lands heel first, toe up, rolls flat about the heel, rolls
// onto the toe, and lifts off. Only the material's five appearance parameters differ
// between the strips: sand slumps to its angle of repose and piles a low rim, mud keeps
// steep walls and a high rim, snow compacts and keeps vertical walls with no rim.
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "shore/bullet/terrain_coupling.h"
#include "shore/scenes/film.h"
#include "shore/scenes/runner.h"
#include "shore/scenes/scene.h"
#include "shore/scenes/soil_view.h"
#include "shore/scenes/world.h"
#include "shore/terrain/height_source.h"
#include "shore/terrain/material.h"
#include "shore/terrain/terrain.h"

namespace shore::scenes {
namespace {

const std::array<std::string, 3> kMaterials = {"sand", "mud", "snow"};  // strips from south to north

// ---- the gait -----------------------------------------------------------------------------
constexpr double kFootLength = 0.26;   // m
constexpr double kFootWidth = 0.10;    // m
constexpr double kFootHeight = 0.08;   // m (the box's vertical side)
constexpr double kStepLength = 0.40;   // m between successive prints (left, right, left, ...)
constexpr double kStepWidth = 0.09;    // m, each foot's offset from the walking line
constexpr double kSoleDepth = 0.03;    // m, how far the sole is pressed below the surface
constexpr double kFirstPrintX = 0.35;  // m
constexpr double kStart = 0.10;        // s, first heel strike begins
constexpr double kStepTime = 0.45;     // s between successive heel strikes
constexpr double kHeelUp = 0.30;       // rad, toe-up pitch at heel strike
constexpr double kToeDown = 0.50;      // rad, heel-up pitch at the end of the roll onto the toe

// Stance phases, s: land on the heel, roll flat about the heel, stand flat, roll onto the
// toe, lift the toe. Their sum is longer than kStepTime: both feet are down for a moment.
constexpr std::array<double, 5> kPhase = {0.06, 0.10, 0.12, 0.14, 0.08};
constexpr double kStance = kPhase[0] + kPhase[1] + kPhase[2] + kPhase[3] + kPhase[4];

double smooth(double u) {
  u = std::clamp(u, 0.0, 1.0);
  return u * u * (3.0 - 2.0 * u);
}

/// A foot in the walking plane: x forward, z up, pitch toe-up positive.
struct SagittalPose {
  double x = 0.0, z = 0.0, pitch = 0.0;  // centre of the box
};

/// The pose whose sole's heel (or toe) corner lies at (px, pz).
SagittalPose from_heel(double px, double pz, double pitch) {
  const double c = std::cos(pitch), s = std::sin(pitch), a = 0.5 * kFootLength, b = 0.5 * kFootHeight;
  return {px + a * c - b * s, pz + a * s + b * c, pitch};
}
SagittalPose from_toe(double px, double pz, double pitch) {
  const double c = std::cos(pitch), s = std::sin(pitch), a = 0.5 * kFootLength, b = 0.5 * kFootHeight;
  return {px - a * c - b * s, pz - a * s + b * c, pitch};
}

/// One walker on one strip: prints k = 0, 1, ... alternate left (even) and right (odd).
struct Walker {
  double line_y = 0.0;  // m, walking line
  int prints = 6;
  const terrain::HeightSource* ground = nullptr;

  [[nodiscard]] double print_x(int k) const { return kFirstPrintX + k * kStepLength; }
  [[nodiscard]] double foot_y(int foot) const { return line_y + (foot == 0 ? kStepWidth : -kStepWidth); }
  [[nodiscard]] double strike_time(int k) const { return kStart + k * kStepTime; }
  /// Height of the sole during print k: the untouched ground under the print, less the depth.
  [[nodiscard]] double sole_z(int k) const { return ground->height(print_x(k), foot_y(k % 2)) - kSoleDepth; }

  /// Pose during the stance of print k, u in [0, kStance] seconds after the heel strike began.
  [[nodiscard]] SagittalPose stance(int k, double u) const {
    const double heel = print_x(k) - 0.5 * kFootLength, toe = print_x(k) + 0.5 * kFootLength, z = sole_z(k);
    if (u < kPhase[0]) {  // landing: the heel comes down and forward, toe up
      const double s = smooth(u / kPhase[0]);
      return from_heel(heel - 0.06 * (1 - s), z + 0.06 * (1 - s), kHeelUp);
    }
    u -= kPhase[0];
    if (u < kPhase[1]) return from_heel(heel, z, kHeelUp * (1 - smooth(u / kPhase[1])));  // roll flat on the heel
    u -= kPhase[1];
    if (u < kPhase[2]) return from_heel(heel, z, 0.0);  // flat
    u -= kPhase[2];
    if (u < kPhase[3]) return from_toe(toe, z, -kToeDown * smooth(u / kPhase[3]));  // roll onto the toe
    u -= kPhase[3];
    const double s = smooth(u / kPhase[4]);  // lift the toe off, forward and up
    return from_toe(toe + 0.05 * s, z + 0.06 * s, -kToeDown - 0.2 * s);
  }

  /// Pose of a foot at time t: in stance, swinging between prints, or waiting.
  [[nodiscard]] SagittalPose foot(int f, double t) const {
    for (int k = f; k < prints; k += 2)
      if (t >= strike_time(k) && t < strike_time(k) + kStance) return stance(k, t - strike_time(k));
    int next = f;
    while (next < prints && t >= strike_time(next)) next += 2;
    // Swing from the lift-off of the print before (virtual before the first) to the next
    // landing; after its last print the foot swings on and stops, level, above where the
    // next print would be.
    const SagittalPose from = lift_off_before(next);
    const SagittalPose to = next < prints ? stance(next, 0.0) : SagittalPose{print_x(next), sole_z(next) + 0.15, 0.0};
    const double t0 = strike_time(next) - 2 * kStepTime + kStance, t1 = strike_time(next);
    if (t >= t1) return to;
    const double s = smooth((t - t0) / (t1 - t0));
    const double arc = 0.06 * std::sin(std::numbers::pi * std::clamp((t - t0) / (t1 - t0), 0.0, 1.0));
    return {from.x + s * (to.x - from.x), from.z + s * (to.z - from.z) + arc, from.pitch + s * (to.pitch - from.pitch)};
  }

  [[nodiscard]] SagittalPose lift_off_before(int k) const {
    if (k >= 2) return stance(k - 2, kStance);
    // Before the first print the foot waits where the print two steps back would lift off.
    const double toe = print_x(k) - 2 * kStepLength + 0.5 * kFootLength, z = sole_z(k);
    return from_toe(toe + 0.05, z + 0.06, -kToeDown - 0.2);
  }

  [[nodiscard]] btTransform transform(int f, double t) const {
    const SagittalPose p = foot(f, t);
    // A rotation about +y by -pitch lifts the toe (the box's +x end) for positive pitch.
    btTransform tr(btQuaternion(btVector3(0, 1, 0), btScalar(-p.pitch)),
                   btVector3(btScalar(p.x), btScalar(foot_y(f)), btScalar(p.z)));
    return tr;
  }
  [[nodiscard]] double end_time() const { return strike_time(prints - 1) + kStance; }
};

// ---- footprint counting ---------------------------------------------------------------------

/// Connected (8-neighbour) groups of columns lowered more than `depth` below the baseline,
/// counting only groups of at least min_columns columns, within rows [j0, j1).
int count_prints(const HeightGrid& heights, const HeightGrid& baseline, int j0, int j1, double depth, int min_columns) {
  std::vector<char> seen(heights.z.size(), 0);
  std::vector<std::pair<int, int>> stack;
  auto low = [&](int i, int j) { return heights.at(i, j) < baseline.at(i, j) - depth; };
  int count = 0;
  for (int j = j0; j < j1; ++j)
    for (int i = 0; i < heights.nx; ++i) {
      if (seen[heights.index(i, j)] || !low(i, j)) continue;
      int size = 0;
      stack.push_back({i, j});
      seen[heights.index(i, j)] = 1;
      while (!stack.empty()) {
        const auto [a, b] = stack.back();
        stack.pop_back();
        ++size;
        for (int dj = -1; dj <= 1; ++dj)
          for (int di = -1; di <= 1; ++di) {
            const int x = a + di, y = b + dj;
            if (x < 0 || y < j0 || x >= heights.nx || y >= j1 || seen[heights.index(x, y)] || !low(x, y)) continue;
            seen[heights.index(x, y)] = 1;
            stack.push_back({x, y});
          }
      }
      if (size >= min_columns) ++count;
    }
  return count;
}

// ---- the scene ------------------------------------------------------------------------------

struct Strip {
  std::string material;
  double y0 = 0.0, y1 = 0.0;  // m
  std::unique_ptr<terrain::Terrain> soil;
  std::unique_ptr<bullet::TerrainCoupling> coupling;
  Walker walker;
  std::array<btRigidBody*, 2> feet{};
  [[nodiscard]] bullet::Region region() const {
    return {-bullet::Region::kUnbounded, y0, bullet::Region::kUnbounded, y1};
  }
};

class Footprints final : public Scene {
 public:
  explicit Footprints(const SceneOptions& o)
      : o_(o),
        cell_(o.smoke ? std::max(o.cell, 0.02) : o.cell),
        prints_(o.smoke ? 1 : 6),
        ground_(std::make_shared<terrain::LatticeNoise>(
            terrain::LatticeNoiseSettings{.seed = 5, .spacing = 0.3, .amplitude = 0.004, .octaves = 2})),
        strips_(kMaterials.size()) {
    const int tile_columns = std::clamp(static_cast<int>(std::lround(0.64 / cell_)), 4, 1024);
    const double strip_width = tile_columns * cell_;  // strips meet on tile edges
    for (std::size_t s = 0; s < strips_.size(); ++s) {
      Strip& st = strips_[s];
      st.material = kMaterials[s];
      st.y0 = double(s) * strip_width;
      st.y1 = st.y0 + strip_width;
      terrain::TerrainSettings ts = soil_settings(o);
      ts.cell = cell_;
      ts.tile_columns = tile_columns;
      ts.material = terrain::Material::preset(st.material);
      ts.base = ground_;
      st.soil = std::make_unique<terrain::Terrain>(ts);
      bullet::TerrainCouplingSettings cs;
      cs.region = st.region();
      st.coupling = std::make_unique<bullet::TerrainCoupling>(world_.world(), *st.soil, cs);
      st.walker = Walker{0.5 * (st.y0 + st.y1), prints_, ground_.get()};
      for (int f = 0; f < 2; ++f) {
        const btTransform pose = st.walker.transform(f, 0.0);
        btRigidBody* foot =
            world_.add_body(std::make_unique<btBoxShape>(btVector3(btScalar(kFootLength / 2), btScalar(kFootWidth / 2),
                                                                   btScalar(kFootHeight / 2))),
                            0.0, pose.getOrigin(), pose.getRotation());
        // Kinematic: moved by its motion state every substep, it imprints the soil geometrically.
        foot->setCollisionFlags((foot->getCollisionFlags() & ~btCollisionObject::CF_STATIC_OBJECT) |
                                btCollisionObject::CF_KINEMATIC_OBJECT);
        foot->setActivationState(DISABLE_DEACTIVATION);
        st.coupling->add_body(foot);
        st.feet[static_cast<std::size_t>(f)] = foot;
      }
    }
    for (const Strip& st : strips_) {
      for (btRigidBody* f : st.feet) bodies_.push_back(f);
      patches_.push_back({st.soil.get(), st.region()});
    }
    frame_ = grid_over(0.0, 0.0, strips_[0].walker.print_x(prints_ - 1) + 0.35, strips_.back().y1 - cell_, cell_);
    baseline_ = sample(patches_, frame_, Field::base);
    // The close-up and filmstrip follow one heel-to-toe roll (print 2, or 0 in smoke runs)
    // in the --material strip.
    const auto chosen =
        static_cast<std::size_t>(std::find(kMaterials.begin(), kMaterials.end(), o.material) - kMaterials.begin());
    focus_ = &strips_[std::min(chosen, strips_.size() - 1)];
    focus_print_ = std::min(2, prints_ - 1);
    const double fx = focus_->walker.print_x(focus_print_), fy = focus_->walker.foot_y(focus_print_ % 2);
    close_frame_ = grid_over(fx - 0.35, fy - 0.16, fx + 0.35, fy + 0.16, cell_);
    close_base_ = sample(patches_, close_frame_, Field::base);
  }

  void step() override {
    ++k_;
    const double t = k_ * o_.substep;
    for (Strip& st : strips_)
      for (int f = 0; f < 2; ++f)
        st.feet[static_cast<std::size_t>(f)]->getMotionState()->setWorldTransform(st.walker.transform(f, t));
    world_.step(o_.substep);
  }

  [[nodiscard]] SceneState state() const override {
    SceneState s{.bodies = bodies_, .soil_heights = {sample(patches_, frame_, Field::height)}};
    for (const Strip& st : strips_) s.soils.push_back(st.soil.get());
    return s;
  }

  void measure(nlohmann::json& m) const override {
    const HeightGrid heights = sample(patches_, frame_, Field::height);
    const HeightGrid sinkage = sample(patches_, frame_, Field::sinkage);
    double drift = 0.0;
    int total_prints = 0;
    const int min_columns = static_cast<int>(0.3 * kFootLength * kFootWidth / (cell_ * cell_));
    nlohmann::json per = nlohmann::json::object();
    double snow_floor_error = -1.0;
    for (const Strip& st : strips_) {
      drift = std::max(drift, volume_drift_rel(*st.soil));
      const int j0 = std::clamp(static_cast<int>(std::lround((st.y0 - frame_.y0) / cell_)), 0, frame_.ny);
      const int j1 = std::clamp(static_cast<int>(std::lround((st.y1 - frame_.y0) / cell_)), 0, frame_.ny);
      const int count = count_prints(heights, baseline_, j0, j1, 0.3 * kSoleDepth, min_columns);
      total_prints += count;
      double deepest = 0.0, rim = 0.0, max_sink = 0.0;
      for (int j = j0; j < j1; ++j)
        for (int i = 0; i < frame_.nx; ++i) {
          deepest = std::max(deepest, baseline_.at(i, j) - heights.at(i, j));
          rim = std::max(rim, heights.at(i, j) - baseline_.at(i, j));
          max_sink = std::max(max_sink, sinkage.at(i, j));
        }
      // Print floors: the lowest column under each print against the sole's height there.
      double floor_error = 0.0;
      for (int k = 0; k < prints_; ++k) {
        const double px = st.walker.print_x(k), py = st.walker.foot_y(k % 2);
        double lowest = 1e9;
        for (std::int64_t j = st.soil->column_j(py - kFootWidth); j <= st.soil->column_j(py + kFootWidth); ++j)
          for (std::int64_t i = st.soil->column_i(px - kFootLength); i <= st.soil->column_i(px + kFootLength); ++i)
            lowest = std::min(lowest, st.soil->height(i, j));
        floor_error = std::max(floor_error, std::abs(lowest - st.walker.sole_z(k)));
      }
      if (st.material == "snow") snow_floor_error = floor_error;
      per[st.material] = {{"footprints_count", count},
                          {"deepest_m", deepest},
                          {"rim_height_m", rim},
                          {"max_sinkage_m", max_sink},
                          {"print_floor_error_m", floor_error},
                          {"volume_drift_rel", volume_drift_rel(*st.soil)}};
    }
    const bool walk_complete = k_ * o_.substep >= strips_[0].walker.end_time();
    m["volume_drift_rel"] = drift;
    m["max_sinkage_m"] = max_of(sinkage);
    m["footprints_count"] = total_prints;
    m["planned_prints"] = prints_ * static_cast<int>(strips_.size());
    m["sole_depth_m"] = kSoleDepth;
    m["per_material"] = per;
    m["walk_complete"] = walk_complete;
    // Each strip must show one print per scripted step (only counted once the walk is over).
    if (walk_complete)
      add_check(m, "footprints_count", total_prints, prints_ * static_cast<double>(strips_.size()), 0.0,
                "the gait script: one heel strike per step and strip");
    // Snow has no rim share (alpha 0) and vertical angles: a kinematic sole pressed to height
    // z leaves a floor exactly at z (to the contact tolerance, 0.1 mm).
    add_check(m, "snow_print_floor_error_m", snow_floor_error, 0.0, 2e-4,
              "geometry: a kinematic sole's imprint in a material with neither rim nor slump");
  }

  /// The heel-to-toe roll of the focus print: frame q at the first substep after the one
  /// before it that reaches an even share q of the stance.
  [[nodiscard]] std::vector<int> film_substeps() const override {
    const int frames = o_.smoke ? 3 : 6, n = o_.substeps();
    const double t0 = focus_->walker.strike_time(focus_print_), t1 = t0 + kStance;
    std::vector<int> at;
    int k = 1;
    for (int q = 0; q < frames; ++q, ++k) {
      while (k <= n && k * o_.substep < t0 + (t1 - t0) * q / (frames - 1) - 1e-9) ++k;
      if (k > n) break;
      at.push_back(k);
    }
    return at;
  }

  Image film_frame(Painter& painter) override {
    return painter.paint(contents(), {.region = bounds_of(close_frame_),
                                      .elevation_deg = 30.0,
                                      .colour_scale = 0.04,
                                      .legend = false,
                                      .width = o_.smoke ? 240 : 320});
  }

  SceneContents contents() override {
    SceneContents c{.world = &world_, .bounds = bounds_of(frame_), .clock = &k_};
    for (Strip& s : strips_) c.soils.push_back({s.soil.get(), s.coupling.get(), s.region()});
    return c;
  }

  void draw(Drawing& out) const override {
    const HeightGrid heights = sample(patches_, frame_, Field::height);
    const int w = o_.smoke ? 320 : 1280;
    out.view("top.png",
             {.camera = View::Camera::top, .width = w, .title = "footprints: sand (bottom), mud, snow (top)"});
    out.view("view.png",
             {.elevation_deg = 40.0, .width = w, .title = "footprints in sand (front), mud and snow (back)"});
    out.view("closeup.png", {.region = bounds_of(close_frame_),
                             .elevation_deg = 35.0,
                             .colour_scale = 0.04,
                             .width = o_.smoke ? 320 : 960,
                             .title = "one footprint in " + focus_->material});
    out.filmstrip();
    out.obj("ground.obj", heights);
  }

 private:
  SceneOptions o_;
  double cell_;
  int prints_;
  std::shared_ptr<terrain::LatticeNoise> ground_;
  World world_;
  std::vector<Strip> strips_;  // after the world: their couplings go first
  std::vector<const btRigidBody*> bodies_;
  std::vector<Patch> patches_;
  HeightGrid frame_, baseline_;
  const Strip* focus_ = nullptr;
  int focus_print_ = 0;
  HeightGrid close_frame_, close_base_;
  int k_ = 0;
};

}  // namespace

SceneType footprints_scene() {
  return {
      .name = "footprints",
      .description =
          "Two kinematic feet (0.26 x 0.10 m boxes) stride six steps along each of three strips side by side: sand "
          "(front), mud and snow (back), as in Sumner et al.'s figure 5. Each foot lands heel first with the toe up, "
          "rolls flat about the heel, rolls onto the toe and lifts off; the sole is pressed 3 cm below the surface. "
          "Only "
          "the materials' appearance parameters differ: sand slumps to its angle of repose with a low rim, mud keeps "
          "steep walls and a high rim, snow compacts with vertical walls and no rim. --material picks the strip of the "
          "close-up and of the heel-to-toe filmstrip; all three strips always run.",
      .defaults = {.seconds = 3.0, .substep = 1.0 / 240.0, .material = "sand", .cell = 0.01, .smoke_seconds = 0.65},
      .metric_help =
          {
              {"volume_drift_rel", "largest volume drift of the three soils (must be < 1e-6)"},
              {"max_sinkage_m", "largest plastic sinkage in any strip, m"},
              {"footprints_count",
               "separate prints found in the soil (columns lowered > 9 mm, 8-connected), all strips"},
              {"planned_prints", "heel strikes the gait script makes, all strips"},
              {"sole_depth_m", "how far the sole is pressed below the untouched surface, m"},
              {"per_material", "per strip: prints, deepest lowering, rim height, sinkage, print floor error, drift"},
              {"walk_complete", "whether the run lasted until the last foot lifted"},
          },
      .create = make_scene<Footprints>,
  };
}

}  // namespace shore::scenes
