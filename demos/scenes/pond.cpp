// pond: a square pool of spring-mass water with an island. A sphere, a light box and a
// stone are dropped in and make rings that reflect off the walls and wrap around the
// island; three flat boxes of different densities float; then a violent Gaussian bump
// (20 water spacings high) is thrown into one corner. The water's stability guard must
// keep everything finite, and the floaters must settle back to Archimedes' drafts.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include <btBulletDynamicsCommon.h>

#include "shore/bullet/water_coupling.h"
#include "shore/cases/bullet_world.h"
#include "shore/cases/water_cases.h"
#include "shore/core/hash.h"
#include "shore/demo/mesh.h"
#include "shore/demo/render.h"
#include "shore/demo/scene.h"
#include "water_scene_util.h"

namespace shore::demo {
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

using cases::Floater;
using cases::FloaterShape;

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

double volume_of(const Floater& f) {
  if (f.shape == FloaterShape::sphere) return std::numbers::pi * std::pow(double(f.size.x()), 3) / 6.0;
  return double(f.size.x()) * f.size.y() * f.size.z();
}

std::unique_ptr<btCollisionShape> shape_of(const Floater& f) {
  if (f.shape == FloaterShape::sphere) return std::make_unique<btSphereShape>(f.size.x() * btScalar(0.5));
  return std::make_unique<btBoxShape>(f.size * btScalar(0.5));
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
  return water_scene::level_around(s, c.x(), c.y(), half_diagonal + 0.15);
}

SceneResult run(const SceneOptions& o, Progress& progress) {
  const double cell = o.smoke ? std::max(o.cell, 0.1) : o.cell;
  const int nodes = std::clamp(static_cast<int>(std::lround(kExtent / cell)) + 1, 9, 1025);
  const double h = kExtent / (nodes - 1);
  water::Surface pond(pool_settings(h, nodes, 0));
  const int island_nodes = make_island(pond);

  cases::BulletWorld world(9.81);
  const double half = 0.5 * kExtent + 0.5;
  world.add_body(std::make_unique<btBoxShape>(btVector3(btScalar(half), btScalar(half), btScalar(0.5))), 0.0,
                 btVector3(0, 0, btScalar(-kDepth - 0.5)));  // the pool's floor
  btRigidBody* island =
      world.add_body(std::make_unique<btCylinderShapeZ>(btVector3(btScalar(kIslandRadius), btScalar(kIslandRadius),
                                                                  btScalar(0.5 * (kDepth + kIslandTop)))),
                     0.0, btVector3(btScalar(kIslandX), btScalar(kIslandY), btScalar(0.5 * (kIslandTop - kDepth))));
  bullet::WaterCoupling coupling(world.world(), pond);

  std::vector<Piece> parts = pieces();
  std::vector<const btRigidBody*> drawn{island};
  for (Piece& p : parts) {
    p.body =
        world.add_body(shape_of(p.f), p.f.density_ratio * kWaterDensity * volume_of(p.f), p.f.position, p.f.rotation);
    p.body->setActivationState(DISABLE_DEACTIVATION);  // the hash must not depend on sleeping heuristics
    coupling.add_body(p.body);
    drawn.push_back(p.body);
  }

  const int n = o.substeps();
  const int bump_step = std::max(1, static_cast<int>(std::lround(kBumpAt * n)));
  const double bump_height = kBumpSpacings * h;
  const double window = std::min(1.0, 0.5 * o.seconds);  // s, drafts are averaged over the last `window`
  const int window_start = n - std::max(1, static_cast<int>(std::lround(window / o.substep)));
  std::vector<int> frame_steps;
  for (double f : o.smoke ? std::span<const double>(kSmokeFrameAt) : std::span<const double>(kFrameAt))
    frame_steps.push_back(std::clamp(static_cast<int>(std::lround(f * n)), 1, n));
  std::vector<Image> film;
  std::vector<std::string> labels;
  const water_scene::WaterOverlay overlay{on_island, {drawn.begin() + 1, drawn.end()}};  // island: land
  // The oblique view is taken while the bump's waves wrap around the island (frame 4).
  const int view_step = frame_steps[std::min<std::size_t>(3, frame_steps.size() - 1)];
  Image view_picture;
  auto oblique = [&](int k) {
    const HeightGrid g = water_scene::surface_grid(pond);
    const HeightGrid rest(g.nx, g.ny, g.cell, g.x0, g.y0, pond.settings().rest_height);
    const water_scene::BodyEnvelopes bodies = water_scene::body_envelopes(drawn, g);
    ReliefStyle style;
    style.baseline = &rest;  // blue: troughs, red: crests
    style.bodies = &bodies.top;
    style.body_bottoms = &bodies.bottom;
    style.title = "pond at " + water_scene::time_label(k * o.substep);
    return render_oblique(g, style, 35.0);
  };
  auto capture = [&](int k) {
    if (!o.write_files) return;
    film.push_back(water_scene::render_water_scene(pond, overlay, 0.0, "", o.smoke ? 160 : 480));
    labels.push_back(water_scene::time_label(k * o.substep));
    if (k == view_step) view_picture = oblique(k);
  };

  double wall = 0.0, max_wave = 0.0;
  int water_substeps_max = 0;
  long draft_samples = 0;
  for (int k = 1; k <= n; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    if (k == bump_step)
      pond.disturb(water::Disturbance::point_height(kBumpX, kBumpY, kBumpRadiusSpacings * h, bump_height));
    world.step(o.substep);
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    water_substeps_max = std::max(water_substeps_max, coupling.stats().water_substeps);
    max_wave = std::max(max_wave, water_scene::max_deviation(pond));
    if (k > window_start) {
      for (Piece& p : parts) p.draft_sum += level_of(pond, p) - bottom_of(p);
      ++draft_samples;
    }
    if (std::find(frame_steps.begin(), frame_steps.end(), k) != frame_steps.end()) capture(k);
    progress.update(static_cast<double>(k) / n);
  }

  long nan_count = water_scene::non_finite_heights(pond);
  StateHash hash;
  hash.add(pond.state_hash());
  for (const Piece& p : parts) {
    water_scene::hash_body(hash, *p.body);
    nan_count += water_scene::non_finite_state(*p.body);
  }

  SceneResult r;
  r.state_hash = hash.value();
  r.metrics = common_metrics("pond", o, n, wall, r.state_hash, nan_count);
  r.metrics["water"] = std::to_string(nodes) + " x " + std::to_string(nodes) + " nodes, 3-D lattice, spacing " +
                       std::to_string(h) + " m, depth " + std::to_string(kDepth) + " m";
  r.metrics["island_nodes"] = island_nodes;
  r.metrics["disturbance_height_m"] = bump_height;
  r.metrics["disturbance_time_s"] = bump_step * o.substep;
  double worst_box = 0.0;
  nlohmann::json drafts = nlohmann::json::object();
  for (const Piece& p : parts) {
    if (!p.floats) continue;
    const double draft = p.draft_sum / double(std::max(draft_samples, 1L));
    const double reference = cases::archimedes_draft(p.f);
    const double err = std::abs(draft - reference) / reference;
    drafts[p.name] = {{"draft_m", draft}, {"archimedes_m", reference}, {"error_rel", err}};
    if (p.f.shape == FloaterShape::box) worst_box = std::max(worst_box, err);
    if (p.placed || o.seconds >= 4.0)
      add_check(r.metrics, "draft " + p.name, draft, reference, 0.05 * reference,
                "Archimedes: displaced water weighs the body (box: draft r h; sphere: cap of r times its volume)");
  }
  r.metrics["draft_error_rel"] = worst_box;
  r.metrics["drafts"] = drafts;
  const double stone_z = parts.back().body->getWorldTransform().getOrigin().z();
  r.metrics["stone_height_m"] = stone_z;
  if (o.seconds >= 2.0)
    add_check(r.metrics, "stone_height_m", stone_z, -kDepth + 0.08, 0.01,
              "Archimedes: a stone (density 2.5) sinks and rests on the floor, centre half its size above it");
  r.metrics["water_substeps_max"] = water_substeps_max;
  r.metrics["max_wave_m"] = max_wave;
  r.metrics["final_wave_m"] = water_scene::max_deviation(pond);

  if (o.write_files) {
    r.files.push_back(
        write_png(o.file("water.png"), water_scene::render_water_scene(pond, overlay, 0.0, "pond: water at the end")));
    r.files.push_back(write_png(o.file("filmstrip.png"), filmstrip(film, labels, 3)));
    r.files.push_back(write_png(o.file("view.png"), view_picture));
    r.files.push_back(write_obj(o.file("water.obj"), water_scene::surface_grid(pond)));
  }
  return r;
}

const SceneRegistrar kRegistered{Scene{
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
    .run = run,
}};

}  // namespace
}  // namespace shore::demo
