// tracks: a riderless bicycle (a light frame and two narrow wheels on hinges, no steering)
// launched at 3 m/s across soft ground, after Sumner et al.'s bicycle tracks and crash
// (figures 1 and 4). The wheels sink and cut a rut, the soil's compaction resistance
// slows the bicycle, and since nothing steers it, a small initial lean grows until it
// falls over and the frame slaps a print into the ground beside the rut.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "shore/bullet/terrain_coupling.h"
#include "shore/cases/bullet_world.h"
#include "shore/demo/mesh.h"
#include "shore/demo/render.h"
#include "shore/demo/scene.h"
#include "shore/terrain/bekker.h"
#include "shore/terrain/height_source.h"
#include "shore/terrain/material.h"
#include "shore/terrain/terrain.h"
#include "soil_scene_util.h"

namespace shore::demo {
namespace {

using namespace soil_scene;

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
  std::vector<std::unique_ptr<btHingeConstraint>> hinges;
};

/// The whole bicycle leaned by kLean about the x axis through its contact line.
Bicycle build(cases::BulletWorld& world, double ground_z) {
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
    b.hinges.push_back(std::make_unique<btHingeConstraint>(*b.frame, *wheel,
                                                           btVector3(btScalar(x), 0, btScalar(-kFrameAbove)),
                                                           btVector3(0, 0, 0), btVector3(0, 1, 0), btVector3(0, 1, 0)));
    world.world().addConstraint(b.hinges.back().get(), true);  // no collision between frame and wheels
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

SceneResult run(const SceneOptions& o, Progress& progress) {
  const double cell = o.cell;  // the 7 cm tyre needs fine cells, smoke runs too
  terrain::LatticeNoiseSettings noise;
  noise.seed = 11;
  noise.spacing = 0.4;
  noise.amplitude = 0.003;
  noise.octaves = 2;
  const auto ground = std::make_shared<terrain::LatticeNoise>(noise);
  terrain::TerrainSettings ts;
  ts.cell = cell;
  ts.material = terrain::Material::preset(o.material);
  ts.base = ground;
  ts.threads = o.threads;
  terrain::Terrain soil(ts);

  cases::BulletWorld world;
  bullet::TerrainCoupling coupling(world.world(), soil);
  Bicycle bike = build(world, ground->height(0.0, 0.0) + noise.amplitude);
  const std::vector<const btRigidBody*> bodies = {bike.frame, bike.wheels[0], bike.wheels[1]};
  const std::vector<const btCollisionObject*> objects = {bike.frame, bike.wheels[0], bike.wheels[1]};
  for (btRigidBody* b : {bike.frame, bike.wheels[0], bike.wheels[1]}) coupling.add_body(b);

  const std::vector<Patch> patches = {{&soil, {}}};
  const HeightGrid frame = grid_over(-1.0, -1.0, o.smoke ? 2.0 : 7.0, 1.0, cell);
  const HeightGrid baseline = sample(patches, frame, Field::base);
  const int n = o.substeps();
  FilmSchedule film(n, o.smoke);
  auto capture = [&](int k) {
    if (o.write_files) film.capture_soil(k, k * o.substep, patches, frame, baseline, objects, o.smoke ? 160 : 480);
  };
  capture(0);

  double wall = 0.0, v_end_rolling = kSpeed, t_fall = -1.0, x_fall = 0.0;
  std::vector<btVector3> contacts;  // rim bottoms along the path while rolling, >= one cell apart
  std::array<btVector3, 2> last_contact = {rim_bottom(*bike.wheels[0]), rim_bottom(*bike.wheels[1])};
  for (int k = 1; k <= n; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    world.step(o.substep);
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (t_fall < 0.0) {
      if (lean_of(bike) > kFallenLean) {
        t_fall = k * o.substep;
        x_fall = static_cast<double>(bike.frame->getCenterOfMassPosition().x());
      } else {
        v_end_rolling = hub_speed(bike);
        for (std::size_t w = 0; w < 2; ++w) {
          const btVector3 c = rim_bottom(*bike.wheels[w]);
          if ((c - last_contact[w]).length() >= btScalar(cell)) {
            contacts.push_back(c);
            last_contact[w] = c;
          }
        }
      }
    }
    capture(k);
    progress.update(double(k) / n);
  }

  // The rut: how far the ground under each recorded rim bottom lies below the untouched
  // surface (skipping the first 0.3 m, where the bicycle was set down).
  double rut_sum = 0.0;
  int rut_n = 0;
  for (const btVector3& c : contacts) {
    if (c.x() < 0.3 - kAxle) continue;
    const std::int64_t i = soil.column_i(c.x()), j = soil.column_j(c.y());
    rut_sum += soil.base_height(i, j) - soil.height(i, j);
    ++rut_n;
  }
  const HeightGrid heights = sample(patches, frame, Field::height);
  const HeightGrid sinkage = sample(patches, frame, Field::sinkage);
  long fallthrough = coupling.stats().rescues;
  for (const btRigidBody* b : bodies) {
    const btVector3 c = b->getCenterOfMassPosition();
    if (c.z() < soil.bedrock(soil.column_i(c.x()), soil.column_j(c.y()))) ++fallthrough;
  }
  StateHash hash;
  hash.add(soil.state_hash());
  hash_bodies(hash, bodies);

  SceneResult r;
  r.state_hash = hash.value();
  r.metrics =
      common_metrics("tracks", o, n, wall, r.state_hash, non_finite_bodies(bodies) + heights.non_finite_count());
  r.metrics["rut_depth_m"] = rut_n > 0 ? rut_sum / rut_n : 0.0;
  r.metrics["rut_samples"] = rut_n;
  r.metrics["launch_speed_mps"] = kSpeed;
  r.metrics["speed_end_of_rolling_mps"] = v_end_rolling;
  r.metrics["speed_loss_rel"] = (kSpeed - v_end_rolling) / kSpeed;
  r.metrics["rolling_seconds"] = t_fall >= 0.0 ? t_fall : n * o.substep;
  r.metrics["rolling_distance_m"] =
      t_fall >= 0.0 ? x_fall : static_cast<double>(bike.frame->getCenterOfMassPosition().x());
  r.metrics["final_lean_rad"] = lean_of(bike);
  r.metrics["fell_over"] = lean_of(bike) > kLyingLean;
  // For comparison, not as a check: Bekker's steady rolling sinkage of a rigid wheel under
  // its share of the weight (the frame's centre lies midway between the axles). The rut
  // measured here is deeper (sand about +35 %, mud about +75 % at 1 cm cells): the tyres
  // land, bounce and lean, and the rear tyre runs in the front tyre's rut.
  const double wheel_load = (0.5 * kFrameMass + kWheelMass) * 9.81;
  r.metrics["bekker_rolling_sinkage_m"] =
      terrain::bekker::wheel_sinkage_rolling(ts.material, wheel_load, 2 * kWheelRadius, kTyreWidth);
  r.metrics["deepest_m"] = max_lowering(baseline, heights);
  r.metrics["volume_drift_rel"] = volume_drift_rel(soil);
  r.metrics["max_sinkage_m"] = max_of(sinkage);
  r.metrics["fallthrough_count"] = fallthrough;

  if (o.write_files) {
    const BodyEnvelopes env = body_envelopes(objects, frame);
    ReliefStyle top;
    top.baseline = &baseline;
    top.bodies = &env.top;
    top.body_bottoms = &env.bottom;
    top.min_pixels = o.smoke ? 240 : 1000;
    top.title = "tracks in " + o.material + ": rut, then the fall";
    r.files.push_back(write_png(o.file("top.png"), render_relief(heights, top)));
    r.files.push_back(write_png(o.file("view.png"), oblique_frame(heights, baseline, &env, 2.0, o.smoke ? 240 : 1200,
                                                                  "bicycle in " + o.material + " at " +
                                                                      time_label(n * o.substep) + " (heights x2)",
                                                                  0.0, 40.0, true)));
    r.files.push_back(write_png(o.file("filmstrip.png"), filmstrip(film.images, film.labels, 3)));
    r.files.push_back(write_obj(o.file("ground.obj"), heights));
  }
  for (auto& h : bike.hinges) world.world().removeConstraint(h.get());
  return r;
}

const SceneRegistrar kRegistered{Scene{
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
    .run = run,
}};

}  // namespace
}  // namespace shore::demo
