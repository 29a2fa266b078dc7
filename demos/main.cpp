// shore-demo: headless scenes. (Foundation version: one scene; the scene library grows
// with the physics.)
#include <CLI/CLI.hpp>
#include <btBulletDynamicsCommon.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "shore/bullet/heightfield_tile.h"
#include "shore/terrain/bekker.h"

namespace fs = std::filesystem;

namespace {
// A box dropped on a rigid heightfield tile: where it comes to rest.
nlohmann::json run_tile_drop(double seconds, double substep) {
  shore::bullet::HeightfieldTileSettings s;
  s.columns = 65;
  s.cell = 0.02;
  s.origin_x = -0.64;
  s.origin_y = -0.64;
  shore::bullet::HeightfieldTile tile(s);
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
  world.setGravity(btVector3(0, 0, btScalar(-9.81)));
  world.addCollisionObject(tile.object());
  btBoxShape box(btVector3(btScalar(0.15), btScalar(0.15), btScalar(0.1)));
  btVector3 inertia;
  box.calculateLocalInertia(btScalar(10), inertia);
  btTransform start;
  start.setIdentity();
  start.setOrigin(btVector3(0, 0, btScalar(1.0)));
  btDefaultMotionState motion(start);
  btRigidBody body(btRigidBody::btRigidBodyConstructionInfo(btScalar(10), &motion, &box, inertia));
  world.addRigidBody(&body);
  const int steps = static_cast<int>(seconds / substep + 0.5);
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < steps; ++k) world.stepSimulation(btScalar(substep), 1, btScalar(substep));
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double rest = body.getWorldTransform().getOrigin().z() - 0.1;
  world.removeRigidBody(&body);
  world.removeCollisionObject(tile.object());
  return {{"scene", "tile_drop"},
          {"substeps", steps},
          {"sim_seconds", seconds},
          {"wall_seconds", wall},
          {"box_bottom_rest_height_m", rest}};
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"shore-demo: headless Shore scenes"};
  std::string out = "out";
  double seconds = 2.0;
  double substep = 1.0 / 240;
  app.add_option("--out", out, "output directory")->capture_default_str();
  app.add_option("--seconds", seconds, "simulated seconds")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--substep", substep, "substep, s")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_subcommand("all", "run every scene");
  app.add_subcommand("tile_drop", "a box dropped on a rigid heightfield tile");
  app.require_subcommand(1);
  CLI11_PARSE(app, argc, argv);
  const nlohmann::json m = run_tile_drop(seconds, substep);
  const fs::path dir = fs::path(out) / "tile_drop";
  fs::create_directories(dir);
  std::ofstream(dir / "metrics.json") << m.dump(2) << '\n';
  std::printf("%s\nwrote %s\n", m.dump(2).c_str(), (dir / "metrics.json").c_str());
  return 0;
}
