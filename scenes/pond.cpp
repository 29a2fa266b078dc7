// pond: a square pool of spring-mass water with an island. A sphere, a light box and a
// stone are dropped in and make rings that reflect off the walls and wrap around the
// island; three flat boxes of different densities float; then a violent Gaussian bump
// (20 water spacings high) is thrown into one corner. The water's stability guard must
// keep everything finite, and the floaters must settle back to Archimedes' drafts.
#include <algorithm>
#include <cmath>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <btBulletDynamicsCommon.h>

#include "shore/bullet/water_coupling.h"
#include "shore/scenes/film.h"
#include "shore/scenes/pool_cases.h"
#include "shore/scenes/runner.h"
#include "shore/scenes/scene.h"
#include "shore/scenes/water_view.h"
#include "shore/scenes/world.h"
#include "shore/water/mesh_field.h"

namespace shore::scenes {
namespace {

constexpr double kExtent = 4.0;              // m, side of the pool
constexpr double kDepth = 0.5;               // m, water depth (wave speed sqrt(g depth) = 2.2 m/s)
constexpr double kDampingTime = 1.5;         // s, amplitude e-folding time of the waves
constexpr double kWaterDensity = 1000.0;     // kg/m^3
constexpr double kIslandX = 0.45;            // m, island centre
constexpr double kIslandY = 0.35;            // m
constexpr double kIslandRadius = 0.4;        // m
constexpr double kIslandTop = 0.15;          // m above the rest level
constexpr double kBumpX = -1.45;             // m, centre of the violent disturbance (south-west corner)
constexpr double kBumpY = -1.45;             // m
constexpr double kBumpSpacings = 20.0;       // bump height in water spacings
constexpr double kBumpRadiusSpacings = 3.0;  // bump std. dev. in water spacings
constexpr double kBumpAt = 0.35;             // fraction of the run at which the bump is thrown
// Filmstrip frames as fractions of the run: rings of the drops, just after the bump, its
// reflections, the end (smoke runs keep three).
constexpr double kFrameAt[] = {0.07, 0.14, 0.38, 0.45, 0.6, 1.0};
constexpr double kSmokeFrameAt[] = {0.3, 0.6, 1.0};

struct Piece {
  std::string name;
  Floater f;
  bool floats = true;   ///< density below water's: compared with Archimedes at the end
  bool placed = false;  ///< starts at rest at its draft (checked in every run, smoke runs too)
  btRigidBody* body = nullptr;
  double draft_sum = 0.0;  ///< m, sum over the measuring window of (level - lowest point)
};

Floater box(double sx, double sy, double sz, double ratio, double x, double y, double z, double tilt = 0.0) {
  Floater f;
  f.shape = FloaterShape::box;
  f.size = btVector3(btScalar(sx), btScalar(sy), btScalar(sz));
  f.density_ratio = ratio;
  f.position = btVector3(btScalar(x), btScalar(y), btScalar(z));
  f.rotation = btQuaternion(btVector3(1, btScalar(0.5), 0).normalized(), btScalar(tilt));
  return f;
}

/// A flat box (stable upright at any density: width / height 2.5 > sqrt(6 r (1 - r)))
/// placed at rest at its Archimedes draft.
Floater floating_box(double ratio, double x, double y) {
  const double h = 0.12;
  return box(0.3, 0.3, h, ratio, x, y, -ratio * h + 0.5 * h);
}

std::vector<Piece> pieces() {
  std::vector<Piece> p;
  p.push_back({"light box (0.25)", floating_box(0.25, -0.9, 0.95), true, true});
  p.push_back({"box (0.5)", floating_box(0.5, 1.15, -0.75), true, true});
  p.push_back({"heavy box (0.75)", floating_box(0.75, 1.25, 1.3), true, true});
  p.push_back({"dropped box (0.4)", box(0.3, 0.2, 0.12, 0.4, 0.1, -1.0, 0.55, 0.25)});
  Floater sphere;
  sphere.shape = FloaterShape::sphere;
  sphere.size = btVector3(0.25f, 0.25f, 0.25f);
  sphere.density_ratio = 0.6;
  sphere.position = btVector3(btScalar(-0.6), btScalar(-0.15), btScalar(0.7));
  p.push_back({"dropped sphere (0.6)", sphere});
  p.push_back({"stone (2.5)", box(0.16, 0.16, 0.16, 2.5, -1.2, 0.0, 0.45, 0.6), false});
  return p;
}

bool on_island(double x, double y) { return std::hypot(x - kIslandX, y - kIslandY) <= kIslandRadius; }

water::SurfaceSettings pool_settings(double cell, int nodes, int threads) {
  water::PhysicalParameters phys;
  phys.cell = cell;
  phys.depth = kDepth;
  phys.density = kWaterDensity;
  phys.damping_time = kDampingTime;
  water::SurfaceSettings s = water::SurfaceSettings::physical(phys, nodes, nodes);
  s.origin_x = s.origin_y = -0.5 * (nodes - 1) * cell;
  s.rest_height = 0.0;
  // The seed paper's 3-D lattice: the violent bump stretches its springs far into the
  // nonlinear range, which is what the stability guard's deformation-aware bound watches.
  s.mode = water::SurfaceMode::full_3d;
  s.boundary = water::Boundary::vertical_only;  // pool walls: waves reflect without inversion
  s.threads = threads;                          // 0: the surface's own choice (one thread per 16384 nodes at most)
  return s;
}

/// Fixes every node inside the island's disc; returns how many.
int make_island(water::Surface& s) {
  int n = 0;
  for (int j = 0; j < s.ny(); ++j)
    for (int i = 0; i < s.nx(); ++i)
      if (on_island(s.node_x(i), s.node_y(j))) {
        s.set_fixed(i, j, true);
        ++n;
      }
  return n;
}

/// Height of the floater's bottom: the centre of its bottom face (box) or its lowest
/// point (sphere). Unlike the lowest corner, the face centre is not biased by a small heel.
double bottom_of(const Piece& p) {
  const btTransform& t = p.body->getWorldTransform();
  if (p.f.shape == FloaterShape::sphere) return t.getOrigin().z() - 0.5 * p.f.size.x();
  return (t.getOrigin() - t.getBasis().getColumn(2) * (btScalar(0.5) * p.f.size.z())).z();
}

/// The water level a floater sits in: the mean on a circle just outside its footprint
/// (the mean of the whole pool rises at once when the bump is thrown, long before its
/// waves arrive).
double level_of(const water::Surface& s, const Piece& p) {
  const btVector3 c = p.body->getWorldTransform().getOrigin();
  const double half_diagonal = 0.5 * std::hypot(double(p.f.size.x()), double(p.f.size.y()));
  return s.level_around(c.x(), c.y(), half_diagonal + 0.15);
}

int pool_nodes(const SceneOptions& o) {
  const double cell = o.smoke ? std::max(o.cell, 0.1) : o.cell;
  return std::clamp(static_cast<int>(std::lround(kExtent / cell)) + 1, 9, 1025);
}

class Pond final : public Scene {
 public:
  explicit Pond(const SceneOptions& o)
      : o_(o),
        nodes_(pool_nodes(o)),
        h_(kExtent / (nodes_ - 1)),
        pond_(pool_settings(h_, nodes_, 0)),
        island_nodes_(make_island(pond_)),
        floor_(world_.add_body(std::make_unique<btBoxShape>(btVector3(btScalar(0.5 * kExtent + 0.5),
                                                                      btScalar(0.5 * kExtent + 0.5), btScalar(0.5))),
                               0.0, btVector3(0, 0, btScalar(-kDepth - 0.5)))),
        island_(world_.add_body(
            std::make_unique<btCylinderShapeZ>(
                btVector3(btScalar(kIslandRadius), btScalar(kIslandRadius), btScalar(0.5 * (kDepth + kIslandTop)))),
            0.0, btVector3(btScalar(kIslandX), btScalar(kIslandY), btScalar(0.5 * (kIslandTop - kDepth))))),
        coupling_(world_.world(), pond_),
        parts_(pieces()),
        bump_step_(std::max(1, static_cast<int>(std::lround(kBumpAt * o.substeps())))),
        window_start_(o.substeps() -
                      std::max(1, static_cast<int>(std::lround(std::min(1.0, 0.5 * o.seconds) / o.substep)))),
        film_at_(at_fractions(
            o.substeps(), o.smoke ? std::span<const double>(kSmokeFrameAt) : std::span<const double>(kFrameAt), 1)) {
    for (Piece& p : parts_) {
      p.body = add_floater(world_, p.f);
      coupling_.add_body(p.body);
      bodies_.push_back(p.body);
    }
  }

  void step() override {
    if (++k_ == bump_step_)
      pond_.disturb(water::Disturbance::point_height(kBumpX, kBumpY, kBumpRadiusSpacings * h_, kBumpSpacings * h_));
    world_.step(o_.substep);
  }

  void observe() override {
    water_substeps_max_ = std::max(water_substeps_max_, coupling_.stats().water_substeps);
    max_wave_ = std::max(max_wave_, max_deviation(pond_));
    if (k_ > window_start_) {  // drafts are averaged over the last second (or half the run)
      for (Piece& p : parts_) p.draft_sum += level_of(pond_, p) - bottom_of(p);
      ++draft_samples_;
    }
  }

  [[nodiscard]] SceneState state() const override {
    return {.waters = {&pond_}, .bodies = bodies_, .layout = HashLayout::velocities_by_axis};
  }

  void measure(nlohmann::json& m) const override {
    m["water"] = std::to_string(nodes_) + " x " + std::to_string(nodes_) + " nodes, 3-D lattice, spacing " +
                 std::to_string(h_) + " m, depth " + std::to_string(kDepth) + " m";
    m["island_nodes"] = island_nodes_;
    m["disturbance_height_m"] = kBumpSpacings * h_;
    m["disturbance_time_s"] = bump_step_ * o_.substep;
    double worst_box = 0.0;
    nlohmann::json drafts = nlohmann::json::object();
    for (const Piece& p : parts_) {
      if (!p.floats) continue;
      const double draft = p.draft_sum / double(std::max(draft_samples_, 1L));
      const double reference = archimedes_draft(p.f);
      const double err = std::abs(draft - reference) / reference;
      drafts[p.name] = {{"draft_m", draft}, {"archimedes_m", reference}, {"error_rel", err}};
      if (p.f.shape == FloaterShape::box) worst_box = std::max(worst_box, err);
      if (p.placed || o_.seconds >= 4.0)
        add_check(m, "draft " + p.name, draft, reference, 0.05 * reference,
                  "Archimedes: displaced water weighs the body (box: draft r h; sphere: cap of r times its volume)");
    }
    m["draft_error_rel"] = worst_box;
    m["drafts"] = drafts;
    const double stone_z = parts_.back().body->getWorldTransform().getOrigin().z();
    m["stone_height_m"] = stone_z;
    if (o_.seconds >= 2.0)
      add_check(m, "stone_height_m", stone_z, -kDepth + 0.08, 0.01,
                "Archimedes: a stone (density 2.5) sinks and rests on the floor, centre half its size above it");
    m["water_substeps_max"] = water_substeps_max_;
    m["max_wave_m"] = max_wave_;
    m["final_wave_m"] = max_deviation(pond_);
  }

  [[nodiscard]] std::vector<int> film_substeps() const override { return film_at_; }

  Image film_frame(Painter& painter) override {
    // The oblique views are taken while the bump's waves wrap around the island (frame 4).
    if (k_ == film_at_[std::min<std::size_t>(3, film_at_.size() - 1)]) {
      view_ = painter.paint(contents(), {.elevation_deg = 35.0,
                                         .water = View::Water::height,
                                         .width = 960,
                                         .title = "pond at " + time_label(k_ * o_.substep)});
      // The water as the renderer draws it: its 3-D nodes simplified to 1 pixel of this
      // picture, the triangles outlined.
      lod_ = painter.paint(contents(), {.elevation_deg = 40.0,
                                        .water = View::Water::natural,
                                        .legend = false,
                                        .mesh_edges = true,
                                        .width = 960,
                                        .title = "water at " + time_label(k_ * o_.substep) + ", mesh at 1 px"});
    }
    return painter.paint(
        contents(),
        {.camera = View::Camera::top, .water = View::Water::height, .legend = false, .width = o_.smoke ? 200 : 400});
  }

  SceneContents contents() override {
    const double half = 0.5 * kExtent;
    return {.world = &world_, .waters = {{&pond_, &coupling_}}, .bounds = {-half, -half, half, half}, .clock = &k_};
  }

  void draw(Drawing& out) const override {
    out.view("water.png", {.camera = View::Camera::top,
                           .water = View::Water::height,
                           .width = 960,
                           .title = "pond: water at the end, coloured by height"});
    out.filmstrip();
    out.png("view.png", view_);
    out.obj("water.obj", surface_grid(pond_));
    out.png("lod.png", lod_);
  }

 private:
  SceneOptions o_;
  int nodes_;
  double h_;  // m, water node spacing
  water::Surface pond_;
  int island_nodes_;
  World world_;
  btRigidBody* floor_;
  btRigidBody* island_;
  bullet::WaterCoupling coupling_;
  std::vector<Piece> parts_;
  std::vector<const btRigidBody*> bodies_;  // the pieces, in order
  int bump_step_, window_start_;
  std::vector<int> film_at_;
  Image view_;
  Image lod_;  // the water mesh at the oblique view's moment
  int k_ = 0;
  int water_substeps_max_ = 0;
  double max_wave_ = 0.0;
  long draft_samples_ = 0;
};

}  // namespace

SceneType pond_scene() {
  return {
      .name = "pond",
      .description =
          "A 4 x 4 m pool of spring-mass water (0.5 m deep; the seed paper's 3-D lattice; walls reflect) with a fixed "
          "island. "
          "A sphere, a light box and a stone are dropped in and make rings that reflect off the walls and wrap around "
          "the island; three flat boxes of densities 0.25, 0.5 and 0.75 float. At 35 % of the run a Gaussian bump 20 "
          "water spacings high is thrown into the south-west corner: the stability guard must keep everything finite, "
          "and the floaters must settle back to Archimedes' drafts. Look at the filmstrip for rings and reflections.",
      .defaults = {.seconds = 8.0, .substep = 1.0 / 240.0, .material = "sand", .cell = 0.05, .smoke_seconds = 0.5},
      .metric_help =
          {
              {"water", "the water grid"},
              {"island_nodes", "fixed water nodes forming the island"},
              {"disturbance_height_m", "height of the violent Gaussian bump, m (20 water spacings)"},
              {"disturbance_time_s", "when the bump is thrown, s"},
              {"draft_error_rel",
               "worst relative error of the floating boxes' mean draft (last second, bottom-face centre below the mean "
               "water "
               "level on a circle 0.15 m outside its footprint) "
               "against Archimedes"},
              {"drafts", "per floater: mean draft over the last second, Archimedes' draft, relative error"},
              {"stone_height_m", "final height of the stone's centre, m (the floor is at -0.5 m)"},
              {"water_substeps_max", "most internal substeps the water's stability guard took in one Bullet substep"},
              {"max_wave_m", "largest |water height - rest level| seen during the run, m (includes the bump)"},
              {"final_wave_m", "largest |water height - rest level| at the end, m"},
          },
      .create = make_scene<Pond>,
  };
}

}  // namespace shore::scenes
