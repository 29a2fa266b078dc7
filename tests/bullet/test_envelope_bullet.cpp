// Envelopes against Bullet's own ray tests (btCollisionWorld::rayTestSingle), one vertical
// ray up (lowest point) and one down (highest point) per column. Bullet's convex ray test
// hits the margin-swept solid, so the envelope uses include_margin = true (like with like).
//
// Which Bullet caster, and the tolerance (measured with Bullet 3.24):
// - double build: Bullet's default caster (btSubsimplexConvexCast) agrees to < 1e-4 m on
//   every convex shape except capsules, where it does not converge and is off by up to
//   0.8 m (an upright capsule, 3 cm off axis: 0.5546 instead of 0.2546). Capsules are
//   therefore compared with btGjkConvexCast (kF_UseGjkConvexCastRaytest), which stops
//   within ~1 mm of the surface: 2e-3 m for capsules, 1e-3 m for everything else.
// - float build: the default caster stops short by up to 3 cm, the GJK caster by up to
//   ~1.3 cm (squared-distance thresholds of 10 * FLT_EPSILON, float ray parameters): the
//   GJK caster is used with 1.5e-2 m.
// Left out of the height comparison: columns within 1 cm of the silhouette (found by
// rasterizing on grids shifted by 1 cm), and faces steeper than slope 3 (~72 degrees), since
// a ray stopping a distance d short of a face errs by d / cos(inclination) in height.
// Columns where Bullet's up and down rays disagree on whether there is a hit at all (Bullet
// contradicting itself) are counted and must stay rare.
#include <gtest/gtest.h>

#include <BulletCollision/NarrowPhaseCollision/btRaycastCallback.h>
#include <btBulletCollisionCommon.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "shore/bullet/envelope.h"

using namespace shore::bullet;
using shore::EnvelopeRaster;

namespace {

#ifdef BT_USE_DOUBLE_PRECISION
constexpr double kRayTolerance = 1e-3;      // m
constexpr double kCapsuleTolerance = 2e-3;  // m, GJK caster
constexpr unsigned kConvexFlags = 0;        // Bullet's default caster
#else
constexpr double kRayTolerance = 1.5e-2;  // m
constexpr double kCapsuleTolerance = 1.5e-2;
constexpr unsigned kConvexFlags = btTriangleRaycastCallback::kF_UseGjkConvexCastRaytest;
#endif
constexpr unsigned kCapsuleFlags = btTriangleRaycastCallback::kF_UseGjkConvexCastRaytest;
constexpr double kSilhouetteBand = 0.01;  // m
constexpr double kMaxSlope = 3.0;

btTransform random_pose(std::mt19937& rng) {
  std::normal_distribution<double> n(0, 1);
  std::uniform_real_distribution<double> u(-1, 1);
  double q[4], s = 0;
  for (double& c : q) {
    c = n(rng);
    s += c * c;
  }
  s = std::sqrt(s);
  btTransform t;
  t.setIdentity();
  t.setRotation(btQuaternion(btScalar(q[0] / s), btScalar(q[1] / s), btScalar(q[2] / s), btScalar(q[3] / s)));
  const double dz = u(rng), dy = u(rng), dx = u(rng);  // one draw per statement: the same with every compiler
  t.setOrigin(btVector3(btScalar(0.2 * dx), btScalar(0.2 * dy), btScalar(0.5 + 0.2 * dz)));
  return t;
}

struct RayHit {
  bool hit = false;
  double z = 0;
};

RayHit vertical_ray(const btCollisionShape& shape, const btTransform& pose, double x, double y, double from_z,
                    double to_z, unsigned flags) {
  btCollisionObject object;
  object.setCollisionShape(const_cast<btCollisionShape*>(&shape));
  object.setWorldTransform(pose);
  btTransform from, to;
  from.setIdentity();
  to.setIdentity();
  const btVector3 a{btScalar(x), btScalar(y), btScalar(from_z)};
  const btVector3 b{btScalar(x), btScalar(y), btScalar(to_z)};
  from.setOrigin(a);
  to.setOrigin(b);
  btCollisionWorld::ClosestRayResultCallback cb(a, b);
  cb.m_flags = flags;
  btCollisionWorld::rayTestSingle(from, to, &object, &shape, pose, cb);
  RayHit h;
  h.hit = cb.hasHit();
  if (h.hit) h.z = double(cb.m_hitPointWorld.z());
  return h;
}

struct RayStats {
  int compared = 0, excluded = 0, failures = 0, bullet_inconsistent = 0;
  double worst = 0;
  std::string first_failure;
};

/// Largest one-sided slope of an envelope at column (i, j) (infinite if a neighbour is missing).
double steepest(const std::vector<double>& h, const EnvelopeRaster& r, std::int64_t i, std::int64_t j, double cell) {
  const double c = h[r.index(i, j)];
  double s = 0;
  for (auto [di, dj] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}}) {
    if (!r.contains(i + di, j + dj)) return std::numeric_limits<double>::infinity();
    const double n = h[r.index(i + di, j + dj)];
    if (!std::isfinite(n)) return std::numeric_limits<double>::infinity();
    s = std::max(s, std::abs(n - c) / cell);
  }
  return s;
}

RayStats compare_with_rays(const btCollisionShape& shape, const btTransform& pose, double cell, unsigned flags,
                           double tolerance) {
  EnvelopeGrid grid;
  grid.origin_x = 0.003;
  grid.origin_y = -0.002;
  grid.cell = cell;
  EnvelopeOptions opt;
  opt.upper = true;
  EnvelopeRasterizer rz(grid, opt);
  const shore::GridRect w = rz.window_of(shape, pose).grown(1);
  EnvelopeRaster out;
  RayStats st;
  rz.rasterize(shape, pose, w, out);
  // Coverage on grids shifted by the band: a column covered on some and not on others
  // passes within the band of the silhouette.
  std::vector<EnvelopeRaster> shifted;
  for (int s = 0; s < 4; ++s) {
    EnvelopeGrid g = grid;
    (s < 2 ? g.origin_x : g.origin_y) += (s % 2 ? -kSilhouetteBand : kSilhouetteBand);
    EnvelopeRasterizer rs(g, opt);
    shifted.emplace_back();
    rs.rasterize(shape, pose, w, shifted.back());
  }
  btVector3 mn, mx;
  shape.getAabb(pose, mn, mx);
  const double below = double(mn.z()) - 0.5, above = double(mx.z()) + 0.5;
  for (int j = 0; j < w.ny; ++j)
    for (int i = 0; i < w.nx; ++i) {
      const std::int64_t gi = w.i0 + i, gj = w.j0 + j;
      const std::size_t k = out.index(gi, gj);
      bool near = false;
      for (const auto& s : shifted) near = near || (s.covers(k) != out.covers(k));
      const double x = grid.origin_x + double(gi) * cell, y = grid.origin_y + double(gj) * cell;
      const RayHit up = vertical_ray(shape, pose, x, y, below, above, flags);
      const RayHit down = vertical_ray(shape, pose, x, y, above, below, flags);
      if (near) {
        ++st.excluded;
        continue;
      }
      if (up.hit != down.hit) {
        ++st.bullet_inconsistent;
        continue;
      }
      if (up.hit != out.covers(k)) {
        if (st.failures++ == 0)
          st.first_failure = "coverage at x " + std::to_string(x) + " y " + std::to_string(y) + ": Bullet " +
                             std::to_string(up.hit) + ", envelope " + std::to_string(out.covers(k));
        continue;
      }
      if (!up.hit) continue;
      // A ray that stops a distance d short of a face inclined by theta errs by d / cos(theta)
      // in height: compare heights only where the face is at most ~72 degrees from level.
      const bool lower_ok = steepest(out.lower, out, gi, gj, cell) <= kMaxSlope;
      const bool upper_ok = steepest(out.upper, out, gi, gj, cell) <= kMaxSlope;
      if (!lower_ok && !upper_ok) {
        ++st.excluded;
        continue;
      }
      ++st.compared;
      double err = 0;
      if (lower_ok) err = std::max(err, std::abs(up.z - out.lower[k]));
      if (upper_ok) err = std::max(err, std::abs(down.z - out.upper[k]));
      st.worst = std::max(st.worst, err);
      if (!(err <= tolerance) && st.failures++ == 0)
        st.first_failure = "heights at x " + std::to_string(x) + " y " + std::to_string(y) + ": Bullet " +
                           std::to_string(up.z) + " .. " + std::to_string(down.z) + ", envelope " +
                           std::to_string(out.lower[k]) + " .. " + std::to_string(out.upper[k]);
    }
  return st;
}

void expect_agree(const btCollisionShape& shape, std::mt19937& rng, int poses, double cell, const char* what,
                  unsigned flags = kConvexFlags, double tolerance = kRayTolerance) {
  for (int p = 0; p < poses; ++p) {
    const RayStats st = compare_with_rays(shape, random_pose(rng), cell, flags, tolerance);
    EXPECT_EQ(st.failures, 0) << what << ": worst height error " << st.worst << " m; first: " << st.first_failure;
    EXPECT_GT(st.compared, 50) << what;
    EXPECT_LE(st.bullet_inconsistent, 5) << what;
    std::printf("%s: %d columns compared, %d left out, %d where Bullet contradicts itself, worst %.3g m\n", what,
                st.compared, st.excluded, st.bullet_inconsistent, st.worst);
  }
}

TEST(EnvelopeVsBulletRays, AnalyticShapes) {
  std::mt19937 rng(31);
  btSphereShape sphere(btScalar(0.2));
  expect_agree(sphere, rng, 2, 0.02, "sphere");
  btBoxShape box(btVector3(btScalar(0.25), btScalar(0.1), btScalar(0.15)));
  expect_agree(box, rng, 2, 0.02, "box");
  btCapsuleShapeZ capsule(btScalar(0.1), btScalar(0.3));
  expect_agree(capsule, rng, 2, 0.02, "capsule", kCapsuleFlags, kCapsuleTolerance);
  btCylinderShapeX cylinder(btVector3(btScalar(0.15), btScalar(0.25), btScalar(0.25)));  // margin 0.04: rounded rims
  expect_agree(cylinder, rng, 2, 0.02, "cylinder");
  btConeShapeZ cone(btScalar(0.2), btScalar(0.4));  // margin 0.04 outside
  expect_agree(cone, rng, 2, 0.02, "cone");
}

TEST(EnvelopeVsBulletRays, HullMeshAndCompound) {
  std::mt19937 rng(32);
  std::uniform_real_distribution<double> u(-1, 1);
  btConvexHullShape hull;
  for (int k = 0; k < 16; ++k) {
    const double z = u(rng), y = u(rng), x = u(rng);  // one draw per statement
    hull.addPoint(btVector3(btScalar(0.3 * x), btScalar(0.2 * y), btScalar(0.15 * z)));
  }
  expect_agree(hull, rng, 2, 0.02, "hull");

  btTriangleMesh mesh;
  const int n = 5;
  auto vertex = [&](int i, int j) {
    return btVector3(btScalar(0.1 * i - 0.25), btScalar(0.1 * j - 0.25), btScalar(0.05 * std::sin(1.3 * i + 0.7 * j)));
  };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      mesh.addTriangle(vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1));
      mesh.addTriangle(vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1));
    }
  btBvhTriangleMeshShape bvh(&mesh, true);
  expect_agree(bvh, rng, 2, 0.02, "mesh");

  btSphereShape sphere(btScalar(0.12));
  btBoxShape box(btVector3(btScalar(0.2), btScalar(0.08), btScalar(0.05)));
  btCompoundShape compound;
  btTransform a, b;
  a.setIdentity();
  a.setOrigin(btVector3(btScalar(0.15), 0, btScalar(0.05)));
  b.setIdentity();
  b.setRotation(btQuaternion(btVector3(1, 0, 1), btScalar(0.4)));
  compound.addChildShape(a, &sphere);
  compound.addChildShape(b, &box);
  expect_agree(compound, rng, 2, 0.02, "compound");
}

}  // namespace
