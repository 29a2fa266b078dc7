#include "shore/scenes/envelope_cases.h"

#include <btBulletCollisionCommon.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "shore/bullet/envelope.h"

namespace shore::scenes {
namespace {

using Clock = std::chrono::steady_clock;

btTransform make_pose(double x, double y, double z, const btQuaternion& q) {
  btTransform t;
  t.setIdentity();
  t.setRotation(q);
  t.setOrigin(btVector3(btScalar(x), btScalar(y), btScalar(z)));
  return t;
}

btQuaternion tilt(double yaw, double pitch, double roll) {
  btQuaternion q;
  q.setEulerZYX(btScalar(yaw), btScalar(pitch), btScalar(roll));
  return q;
}

std::shared_ptr<btCollisionShape> ellipsoid_hull(double ax, double ay, double az, int n) {
  auto hull = std::make_shared<btConvexHullShape>();
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < n; ++k) {  // Fibonacci points: evenly spread over the ellipsoid
    const double z = 1.0 - 2.0 * (k + 0.5) / n;
    const double r = std::sqrt(1.0 - z * z);
    const double phi = golden * k;
    hull->addPoint(btVector3(btScalar(ax * r * std::cos(phi)), btScalar(ay * r * std::sin(phi)), btScalar(az * z)),
                   k == n - 1);
  }
  return hull;
}

/// The columns a method is run on: the envelope's window.
struct Columns {
  shore::bullet::EnvelopeGrid grid;
  shore::GridRect window;
  double z_from = 0, z_to = 0;
  [[nodiscard]] double x(int i) const { return grid.origin_x + double(window.i0 + i) * grid.cell; }
  [[nodiscard]] double y(int j) const { return grid.origin_y + double(window.j0 + j) * grid.cell; }
};

/// One upward ray per column; hits[k] = lowest hit or +inf.
template <class Cast>
void cast_all(const Columns& c, std::vector<double>& hits, Cast&& cast) {
  hits.assign(std::size_t(c.window.nx) * std::size_t(c.window.ny), std::numeric_limits<double>::infinity());
  for (int j = 0; j < c.window.ny; ++j)
    for (int i = 0; i < c.window.nx; ++i) {
      const btVector3 from(btScalar(c.x(i)), btScalar(c.y(j)), btScalar(c.z_from));
      const btVector3 to(btScalar(c.x(i)), btScalar(c.y(j)), btScalar(c.z_to));
      btCollisionWorld::ClosestRayResultCallback cb(from, to);
      cast(from, to, cb);
      if (cb.hasHit())
        hits[std::size_t(j) * std::size_t(c.window.nx) + std::size_t(i)] = double(cb.m_hitPointWorld.z());
    }
}

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

std::vector<EnvelopeCase> standard_envelope_cases() {
  std::vector<EnvelopeCase> cases;
  // Wheel: btCylinderShape's axis is local y (the axle); radius 0.4 m, half width 0.15 m.
  cases.push_back({"wheel", std::make_shared<btCylinderShape>(btVector3(btScalar(0.4), btScalar(0.15), btScalar(0.4))),
                   make_pose(0.51, 0.37, 0.35, tilt(0.2, 0.0, 0.05))});
  cases.push_back(
      {"sphere", std::make_shared<btSphereShape>(btScalar(0.25)), make_pose(0.13, -0.21, 0.2, tilt(0, 0, 0))});
  cases.push_back({"box", std::make_shared<btBoxShape>(btVector3(btScalar(0.3), btScalar(0.2), btScalar(0.15))),
                   make_pose(-0.4, 0.3, 0.3, tilt(0.5, 0.3, 0.2))});
  cases.push_back({"convex_hull", ellipsoid_hull(0.3, 0.2, 0.15, 96), make_pose(0.2, 0.1, 0.25, tilt(0.7, 0.2, -0.3))});
  return cases;
}

EnvelopeCaseResult run_envelope_case(const EnvelopeCase& c, double cell, int rounds) {
  shore::bullet::EnvelopeGrid grid;
  grid.cell = cell;
  shore::bullet::EnvelopeOptions options;  // lower envelope only: what one upward ray gives
  shore::bullet::EnvelopeRasterizer rasterizer(grid, options);
  shore::EnvelopeRaster raster;

  Columns cols;
  cols.grid = grid;
  cols.window = rasterizer.window_of(*c.shape, c.pose);
  btVector3 mn, mx;
  c.shape->getAabb(c.pose, mn, mx);
  cols.z_from = double(mn.z()) - 0.1;
  cols.z_to = double(mx.z()) + 0.1;

  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  btDbvtBroadphase broadphase;
  btCollisionWorld world(&dispatcher, &broadphase, &config);
  btCollisionObject object;
  object.setCollisionShape(c.shape.get());
  object.setWorldTransform(c.pose);
  world.addCollisionObject(&object);
  world.updateAabbs();

  std::vector<double> world_hits, single_hits;
  std::vector<double> t_env, t_world, t_single;
  EnvelopeCaseResult r;
  r.name = c.name;
  r.columns = cols.window.nx * cols.window.ny;
  rasterizer.rasterize(*c.shape, c.pose, raster);  // warm the hull cache
  for (int round = 0; round < std::max(1, rounds); ++round) {
    // The envelope is fast: repeat it so that each sample spans a measurable time.
    const int reps = 20;
    auto t0 = Clock::now();
    for (int k = 0; k < reps; ++k) r.covered = rasterizer.rasterize(*c.shape, c.pose, raster);
    t_env.push_back(seconds_since(t0) / reps);

    t0 = Clock::now();
    cast_all(cols, world_hits, [&](const btVector3& a, const btVector3& b, btCollisionWorld::RayResultCallback& cb) {
      world.rayTest(a, b, cb);
    });
    t_world.push_back(seconds_since(t0));

    t0 = Clock::now();
    cast_all(cols, single_hits, [&](const btVector3& a, const btVector3& b, btCollisionWorld::RayResultCallback& cb) {
      btTransform from, to;
      from.setIdentity();
      to.setIdentity();
      from.setOrigin(a);
      to.setOrigin(b);
      btCollisionWorld::rayTestSingle(from, to, &object, c.shape.get(), c.pose, cb);
    });
    t_single.push_back(seconds_since(t0));
  }
  world.removeCollisionObject(&object);

  r.envelope_us = 1e6 * median(t_env);
  r.ray_world_us = 1e6 * median(t_world);
  r.ray_single_us = 1e6 * median(t_single);
  r.speedup_world = r.ray_world_us / r.envelope_us;
  r.speedup_single = r.ray_single_us / r.envelope_us;
  double sum = 0;
  int both = 0;
  for (std::size_t k = 0; k < raster.lower.size(); ++k) {
    const bool env_hit = raster.covers(k), ray_hit = std::isfinite(world_hits[k]);
    if (env_hit != ray_hit) ++r.coverage_mismatch;
    if (env_hit && ray_hit) {
      sum += std::abs(raster.lower[k] - world_hits[k]);
      ++both;
    }
  }
  r.mean_abs_diff_mm = both ? 1e3 * sum / both : 0.0;
  return r;
}

std::vector<EnvelopeCaseResult> run_envelope_cases(double cell, int rounds) {
  std::vector<EnvelopeCaseResult> out;
  for (const EnvelopeCase& c : standard_envelope_cases()) out.push_back(run_envelope_case(c, cell, rounds));
  return out;
}

}  // namespace shore::scenes
