// baseline: what plain Bullet costs on a rigid heightfield, the yardstick the deformable
// plugin is compared with. A rigid wheel (D 0.8 m, b 0.3 m, 4 kN: DESIGN.md's wheel case)
// and a box are towed at 1 m/s over a flat 1 cm tile; the demo scene rigid_drop runs too.
// "Error" is the height error of rigid contact: on flat rigid ground the axle should stay
// at exactly R and the box's underside at exactly 0.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "measure.h"
#include "shore/demo/rigid_world.h"
#include "shore/demo/scene.h"
#include "sweep.h"

namespace shore::bench {
namespace {

constexpr double kCell = 0.01;     // m, tile spacing (DESIGN.md's default grid)
constexpr int kColumns = 257;      // 2.56 m tile
constexpr double kTowSpeed = 1.0;  // m/s
constexpr double kTurnX = 0.9;     // m, the tow reverses beyond +-kTurnX (stays on the tile)
constexpr double kWheelRadius = 0.4, kWheelHalfWidth = 0.15, kWheelLoad = 4000.0;  // m, m, N
constexpr double kGravity = 9.81;
const btVector3 kBoxHalf(btScalar(0.15), btScalar(0.15), btScalar(0.1));

enum class Body { wheel, box };

/// A body towed back and forth over flat rigid ground.
class TowedBody {
 public:
  TowedBody(Body kind, double substep)
      : kind_(kind), h_(substep), world_(settings(), [](double, double) { return 0.0; }) {
    btTransform pose;
    pose.setIdentity();
    if (kind == Body::wheel) {
      pose.setOrigin(btVector3(btScalar(-0.5), 0, btScalar(kWheelRadius)));
      body_ = &world_.add_cylinder(kWheelRadius, kWheelHalfWidth, kWheelLoad / kGravity, pose);
      body_->setAngularVelocity(btVector3(0, btScalar(kTowSpeed / kWheelRadius), 0));
      rest_ = kWheelRadius;
    } else {
      pose.setOrigin(btVector3(btScalar(-0.5), 0, kBoxHalf.z()));
      body_ = &world_.add_box(kBoxHalf, 10.0, pose);
      rest_ = kBoxHalf.z();
    }
    body_->setActivationState(DISABLE_DEACTIVATION);
    for (int k = 0; k < static_cast<int>(0.1 / h_); ++k) step();  // settle
    error_sum_ = 0.0;
    error_count_ = 0;
  }

  void step() {
    const double x = body_->getWorldTransform().getOrigin().x();
    if (x > kTurnX) direction_ = -1.0;
    if (x < -kTurnX) direction_ = 1.0;
    btVector3 v = body_->getLinearVelocity();
    v.setX(btScalar(direction_ * kTowSpeed));
    body_->setLinearVelocity(v);
    world_.step(h_);
    error_sum_ += std::abs(static_cast<double>(body_->getWorldTransform().getOrigin().z()) - rest_);
    ++error_count_;
  }
  /// Mean |height error| of the body's centre since construction (after settling), m.
  [[nodiscard]] double mean_error() const { return error_count_ ? error_sum_ / error_count_ : 0.0; }

 private:
  static bullet::HeightfieldTileSettings settings() {
    bullet::HeightfieldTileSettings s;
    s.columns = kColumns;
    s.cell = kCell;
    s.origin_x = s.origin_y = -0.5 * (kColumns - 1) * kCell;
    s.friction = 0.8;
    return s;
  }
  Body kind_;
  double h_;
  demo::RigidWorld world_;
  btRigidBody* body_ = nullptr;
  double rest_ = 0.0;
  double direction_ = 1.0;
  double error_sum_ = 0.0;
  long error_count_ = 0;
};

std::string substep_label(double h) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "1/%.0f s", 1.0 / h);
  return buf;
}

void run(const SweepContext& ctx, SweepResult& out) {
  const std::vector<double> substeps = ctx.quick
                                           ? std::vector<double>{1.0 / 120, 1.0 / 240, 1.0 / 480}
                                           : std::vector<double>{1.0 / 60, 1.0 / 120, 1.0 / 240, 1.0 / 480, 1.0 / 960};
  const double min_seconds = ctx.quick ? 0.3 : 1.0;
  Table& t = out.table("baseline_rigid_heightfield",
                       {"method", "substep_s", "ms_per_substep", "s_wall_per_s_sim", "height_error_m"});
  double wheel_240 = 0, box_240 = 0;
  for (Body kind : {Body::wheel, Body::box}) {
    const std::string method = kind == Body::wheel ? "rigid_heightfield_wheel" : "rigid_heightfield_box";
    for (double h : substeps) {
      ctx.progress(method + ", substep " + substep_label(h));
      TowedBody body(kind, h);
      const int batch = std::max(1, static_cast<int>(std::lround(0.05 / h)));  // 50 ms simulated per call
      const Measurement m = measure(
          [&] {
            for (int k = 0; k < batch; ++k) body.step();
          },
          min_seconds, 5);
      const double ms = m.median_s / batch * 1e3;
      t.add({method, h, ms, ms * 1e-3 / h, body.mean_error()});
      if (std::abs(h - 1.0 / 240) < 1e-12) (kind == Body::wheel ? wheel_240 : box_240) = ms;
    }
  }
  // The demo scene, reused: a box dropped onto a rippled rigid tile (simulation loop only).
  if (const demo::Scene* scene = demo::find_scene("rigid_drop")) {
    for (double h : substeps) {
      ctx.progress("rigid_drop scene, substep " + substep_label(h));
      demo::Overrides o;
      o.smoke = true;
      o.threads = 1;
      o.write_files = false;
      o.substep = h;
      const demo::SceneResult r = demo::run_scene(*scene, demo::resolve(*scene, o), demo::ProgressMode::quiet);
      const double ms = r.metrics["wall_seconds"].get<double>() / r.metrics["substeps"].get<double>() * 1e3;
      t.add({"rigid_drop_scene", h, ms, ms * 1e-3 / h, std::abs(r.metrics["rest_gap_m"].get<double>())});
    }
  }
  out.figure("baseline.rigid_heightfield_wheel_ms_per_substep", wheel_240, "ms (substep 1/240 s, 1 cm tile)");
  out.figure("baseline.rigid_heightfield_wheel_s_per_sim_s", wheel_240 * 1e-3 * 240,
             "s wall per s simulated (1/240 s)");
  out.figure("baseline.rigid_heightfield_box_ms_per_substep", box_240, "ms (substep 1/240 s, 1 cm tile)");
  out.plot({.name = "baseline_time_vs_error",
            .title = "Plain Bullet on a rigid 1 cm heightfield: cost against height error",
            .table = "baseline_rigid_heightfield",
            .x = "height_error_m",
            .y = "s_wall_per_s_sim",
            .series = "method",
            .x_label = "mean height error of rigid contact, m",
            .y_label = "wall seconds per simulated second"});
  out.plot({.name = "baseline_cost_vs_substep",
            .title = "Plain Bullet on a rigid 1 cm heightfield: cost per substep",
            .table = "baseline_rigid_heightfield",
            .x = "substep_s",
            .y = "ms_per_substep",
            .series = "method",
            .x_label = "substep, s",
            .y_label = "ms per substep"});
  out.note(
      "Rigid wheel: cylinder D 0.8 m, b 0.3 m, 4 kN (407.7 kg), towed back and forth at 1 m/s over a flat "
      "257 x 257 tile at 1 cm; box: 0.3 x 0.3 x 0.2 m, 10 kg, towed the same way; rigid_drop_scene: the demo "
      "scene's smoke run (simulation loop only, error = |rest gap|). One thread, Bullet's own collision and "
      "solver; height_error_m is the mean |centre height - rest height| while towed.");
}

const SweepRegistrar kRegistered{Sweep{
    .name = "baseline",
    .description = "plain rigid Bullet heightfield: towed wheel and box, cost per substep and height error",
    .run = run,
}};

}  // namespace
}  // namespace shore::bench
