// rigid_drop: a tilted, spinning box dropped onto a rigid heightfield tile (plain Bullet,
// no soil). It exercises the whole demo pipeline and shows what rigid ground does: the
// box bounces, settles and leaves no trace.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "shore/demo/mesh.h"
#include "shore/demo/render.h"
#include "shore/demo/rigid_world.h"
#include "shore/demo/scene.h"
#include "shore/terrain/material.h"

namespace shore::demo {
namespace {

constexpr double kExtent = 1.28;                                       // m, side of the square tile
constexpr double kPlateau = 0.30;                                      // m, radius of the flat centre the box lands on
constexpr double kDropHeight = 0.45;                                   // m, box centre above the plateau at the start
constexpr double kMass = 10.0;                                         // kg
constexpr int kFrames = 6;                                             // filmstrip frames (3 in smoke runs)
const btVector3 kHalf(btScalar(0.15), btScalar(0.15), btScalar(0.1));  // m, box half extents

double smoothstep(double t) {
  t = std::clamp(t, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

/// A flat plateau at z = 0 inside a shallow rippled bowl.
double ground(double x, double y) {
  const double r = std::hypot(x, y);
  const double blend = smoothstep((r - kPlateau) / 0.2);
  const double ripple = 0.02 * std::sin(11.0 * x + 1.0) * std::cos(9.0 * y);
  return blend * (0.1 * (r - kPlateau) + ripple);
}

/// Smallest height of a box corner above the ground under it (negative: penetration).
double corner_clearance(const RigidWorld& w, const btRigidBody& box) {
  double gap = 1e9;
  const btTransform& t = box.getWorldTransform();
  for (int c = 0; c < 8; ++c) {
    const btVector3 local((c & 1) ? kHalf.x() : -kHalf.x(), (c & 2) ? kHalf.y() : -kHalf.y(),
                          (c & 4) ? kHalf.z() : -kHalf.z());
    const btVector3 p = t * local;
    gap = std::min(gap, static_cast<double>(p.z()) - w.ground_height(p.x(), p.y()));
  }
  return gap;
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

Image frame_picture(const RigidWorld& w, int min_pixels, const std::string& title) {
  const HeightGrid g = w.ground_grid();
  const RigidWorld::Envelopes bodies = w.body_envelopes();
  ReliefStyle style;
  style.bodies = &bodies.top;
  style.body_bottoms = &bodies.bottom;
  style.min_pixels = min_pixels;
  style.title = title;
  style.legend = false;
  return render_oblique(g, style, 30.0);
}

std::string time_label(double t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "t = %.2f s", t);
  return buf;
}

SceneResult run(const SceneOptions& o, Progress& progress) {
  RigidWorld w(tile_settings(o), ground);
  btTransform pose;
  pose.setIdentity();
  pose.setOrigin(btVector3(btScalar(0.03), btScalar(-0.02), btScalar(kDropHeight)));
  pose.setRotation(btQuaternion(btVector3(1, btScalar(0.6), 0).normalized(), btScalar(0.35)));
  btRigidBody& box = w.add_box(kHalf, kMass, pose);
  box.setAngularVelocity(btVector3(0, 0, btScalar(2.0)));
  box.setActivationState(DISABLE_DEACTIVATION);  // the hash must not depend on sleeping heuristics

  const double initial_clearance = corner_clearance(w, box);
  const int n = o.substeps();
  const int frames = o.smoke ? 3 : kFrames;
  std::vector<Image> film;
  std::vector<std::string> labels;
  auto capture = [&](int k) {
    if (!o.write_files) return;
    film.push_back(frame_picture(w, 240, ""));
    labels.push_back(time_label(k * o.substep));
  };
  int next_frame = 1;
  capture(0);

  double wall = 0.0, max_penetration = 0.0, landing_time = -1.0;
  long fallthrough = 0;
  for (int k = 1; k <= n; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    w.step(o.substep);
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double gap = corner_clearance(w, box);
    max_penetration = std::max(max_penetration, -gap);
    if (landing_time < 0.0 && gap < 1e-3) landing_time = k * o.substep;
    const btVector3 c = box.getWorldTransform().getOrigin();
    if (c.z() < w.ground_height(c.x(), c.y())) ++fallthrough;
    if (next_frame < frames && k == static_cast<int>(std::lround(static_cast<double>(n) * next_frame / (frames - 1)))) {
      capture(k);
      ++next_frame;
    }
    progress.update(static_cast<double>(k) / n);
  }

  SceneResult r;
  r.state_hash = w.state_hash();
  r.metrics = common_metrics("rigid_drop", o, n, wall, r.state_hash, w.nan_count());
  const double rest_gap = corner_clearance(w, box);
  const double speed = box.getLinearVelocity().length();
  const btVector3 up = box.getWorldTransform().getBasis().getColumn(2);
  r.metrics["ground"] = "rigid heightfield tile, " + std::to_string(w.tile().columns()) + " x " +
                        std::to_string(w.tile().columns()) + " vertices";
  r.metrics["box_mass_kg"] = kMass;
  r.metrics["landing_time_s"] = landing_time;
  r.metrics["max_penetration_m"] = max_penetration;
  r.metrics["rest_gap_m"] = rest_gap;
  r.metrics["rest_speed_mps"] = speed;
  r.metrics["rest_tilt_rad"] = std::acos(std::clamp(static_cast<double>(std::abs(up.z())), 0.0, 1.0));
  r.metrics["fallthrough_count"] = fallthrough;
  // Free fall from rest (spin about the vertical keeps corner heights): the lowest corner
  // reaches 1 mm above the plateau after sqrt(2 (d0 - 1 mm) / g), to within a substep.
  add_check(r.metrics, "landing_time_s", landing_time, std::sqrt(2.0 * (initial_clearance - 1e-3) / 9.81),
            1.5 * o.substep, "free fall from rest: t = sqrt(2 d / g)");
  add_check(r.metrics, "rest_gap_m", rest_gap, 0.0, 0.005, "rigid contact: a box at rest touches the ground");

  if (o.write_files) {
    const HeightGrid g = w.ground_grid();
    const RigidWorld::Envelopes bodies = w.body_envelopes();
    ReliefStyle top;
    top.bodies = &bodies.top;
    top.body_bottoms = &bodies.bottom;
    top.title = "rigid_drop: ground height, box outline";
    r.files.push_back(write_png(o.file("top.png"), render_relief(g, top)));
    ReliefStyle view = top;
    view.title = "rigid_drop at " + time_label(n * o.substep);
    r.files.push_back(write_png(o.file("view.png"), render_oblique(g, view, 30.0)));
    r.files.push_back(write_png(o.file("filmstrip.png"), filmstrip(film, labels, 3)));
    r.files.push_back(write_obj(o.file("ground.obj"), g));
  }
  return r;
}

const SceneRegistrar kRegistered{Scene{
    .name = "rigid_drop",
    .description = "A 0.3 x 0.3 x 0.2 m, 10 kg box, tilted and spinning, is dropped from 0.45 m onto a rigid Bullet "
                   "heightfield tile (a flat plateau inside a rippled bowl). Plain Bullet, no soil: the box bounces, "
                   "settles on the plateau and leaves no trace. It exercises the whole demo pipeline (pictures, mesh, "
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
    .run = run,
}};

}  // namespace
}  // namespace shore::demo
