// Bodies in spring-mass water through Bullet, against Archimedes and hydrostatics
// (the cases and their references: scenes/include/shore/scenes/pool_cases.h).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "bad_bodies.h"
#include "shore/bullet/water_coupling.h"
#include "shore/scenes/pool_cases.h"
#include "shore/scenes/world.h"
#include "shore/terrain/terrain.h"

using namespace shore::scenes;

namespace {
double rel(double value, double reference) { return std::abs(value - reference) / std::abs(reference); }

PoolRun one_floater(const Floater& f, double seconds = 5.0) {
  PoolRun run;
  run.pool.damping_time = 1.0;
  run.floaters = {f};
  run.seconds = seconds;
  return run;
}

Floater floater(FloaterShape shape, btVector3 size, double ratio) {
  Floater f;
  f.shape = shape;
  f.size = size;
  f.density_ratio = ratio;
  f.position = btVector3(0.013f, -0.021f, btScalar(0.5 * size.z()));  // off the nodes: no lucky alignment
  if (shape != FloaterShape::box) f.position.setZ(btScalar(0.5 * size.x()));
  return f;
}
}  // namespace

class BoxDraft : public ::testing::TestWithParam<double> {};
TEST_P(BoxDraft, FloatsAtArchimedesDraft) {
  const Floater f = floater(FloaterShape::box, btVector3(0.3f, 0.3f, 0.2f), GetParam());
  const PoolResult r = run_pool(one_floater(f));
  EXPECT_LT(rel(r.final_draft[0], archimedes_draft(f)), 0.03)
      << "density " << GetParam() << ": draft " << r.final_draft[0] << " vs " << archimedes_draft(f);
  EXPECT_EQ(r.nan_count, 0);
}
INSTANTIATE_TEST_SUITE_P(Densities, BoxDraft, ::testing::Values(0.25, 0.5, 0.8));

TEST(WaterCoupling, SphereAndHorizontalCylinderFloatAtTheirAnalyticDrafts) {
  const Floater sphere = floater(FloaterShape::sphere, btVector3(0.3f, 0.3f, 0.3f), 0.5);
  EXPECT_NEAR(archimedes_draft(sphere), 0.15, 1e-6);  // half a sphere at half density (size is a float)
  const PoolResult rs = run_pool(one_floater(sphere));
  EXPECT_LT(rel(rs.final_draft[0], archimedes_draft(sphere)), 0.05) << rs.final_draft[0];
  const Floater cyl = floater(FloaterShape::cylinder, btVector3(0.2f, 0.4f, 0.2f), 0.3);
  const PoolResult rc = run_pool(one_floater(cyl));
  EXPECT_LT(rel(rc.final_draft[0], archimedes_draft(cyl)), 0.05)
      << rc.final_draft[0] << " vs " << archimedes_draft(cyl);
}

TEST(WaterCoupling, HeavyBoxSinksToTheFloor) {
  Floater f = floater(FloaterShape::box, btVector3(0.3f, 0.3f, 0.2f), 2.0);
  const PoolResult r = run_pool(one_floater(f, 4.0));
  const double bottom = r.records.back().z[0] - 0.1;
  EXPECT_NEAR(bottom, -0.5, 0.01) << "the floor is at -0.5 m";
}

TEST(WaterCoupling, DroppedBoxNeverRisesAboveItsStart) {
  Floater f = floater(FloaterShape::box, btVector3(0.3f, 0.3f, 0.2f), 0.5);
  f.position.setZ(1.1f);
  const PoolResult r = run_pool(one_floater(f, 4.0));
  EXPECT_LT(r.max_z[0], 1.1 + 1e-6) << "energy from nowhere";
  EXPECT_LT(rel(r.final_draft[0], 0.1), 0.03);
}

TEST(WaterCoupling, TiltedBoxRightsItself) {
  Floater f = floater(FloaterShape::box, btVector3(0.4f, 0.4f, 0.1f), 0.5);
  f.rotation = btQuaternion(btVector3(1, 0, 0), 0.4f);
  f.position.setZ(0.03f);
  const PoolResult r = run_pool(one_floater(f, 6.0));
  EXPECT_LT(r.records.back().tilt[0], 0.03) << "still heeled";
}

// Bobbing: stiffness rho g A, mass rho_b A H: period 2 pi sqrt(d / g) for the hydrostatic
// spring alone; added mass and drag can only lengthen it.
TEST(WaterCoupling, HeavePeriodIsHydrostaticOrLonger) {
  Floater f = floater(FloaterShape::box, btVector3(0.3f, 0.3f, 0.2f), 0.5);
  f.position.setZ(0.03f);  // 3 cm above equilibrium (the centre floats at draft - H/2 = 0)
  PoolRun run = one_floater(f, 3.0);
  run.record_every = 1;
  run.pool.damping_time = 5.0;
  const PoolResult r = run_pool(run);
  // Period from the first three upward zero crossings of z - z_eq (z_eq = 0).
  std::vector<double> crossings;
  for (std::size_t k = 1; k < r.records.size(); ++k) {
    const double a = r.records[k - 1].z[0], b = r.records[k].z[0];
    if (a < 0 && b >= 0)
      crossings.push_back(r.records[k - 1].t + (r.records[k].t - r.records[k - 1].t) * (-a) / (b - a));
  }
  ASSERT_GE(crossings.size(), 2u) << "no oscillation";
  const double period = crossings[1] - crossings[0];
  const double hydrostatic = 2 * std::numbers::pi * std::sqrt(0.1 / 9.81);
  EXPECT_GT(period, 0.97 * hydrostatic) << period;
  EXPECT_LT(period, 1.6 * hydrostatic) << period;
}

namespace {
/// The largest wave energy the impact put into the water.
double peak_wave_energy(const PoolResult& r) {
  double e = 0.0;
  for (const PoolRecord& rec : r.records) e = std::max(e, rec.water_energy);
  return e;
}
PoolResult drop_sphere(double height) {
  PoolRun run;
  run.pool.nodes = 65;  // a node at the centre
  Floater f;
  f.shape = FloaterShape::sphere;
  f.size = btVector3(0.2f, 0.2f, 0.2f);
  f.density_ratio = 0.5;
  f.position = btVector3(0, 0, btScalar(0.1 + height));
  run.floaters = {f};
  run.seconds = std::sqrt(2 * height / 9.81) + 0.5;  // half a second after the impact
  return run_pool(run);
}
}  // namespace

TEST(WaterCoupling, DroppedSphereMakesSymmetricRingsLargerFromHigher) {
  const PoolResult low = drop_sphere(1.0), high = drop_sphere(4.0);
  const auto& s = *low.surface;
  const int c = s.nx() / 2;
  double peak = 0.0, asym = 0.0;
  for (int k = 1; k < c; ++k)
    for (int m = 0; m <= k; ++m) {  // the 8 images of (k, m) under the square's symmetries
      const double ref = s.height(c + k, c + m);
      for (auto [di, dj] : {std::pair{k, m}, {-k, m}, {k, -m}, {-k, -m}, {m, k}, {-m, k}, {m, -k}, {-m, -k}})
        asym = std::max(asym, std::abs(s.height(c + di, c + dj) - ref));
      peak = std::max(peak, std::abs(ref));
    }
  EXPECT_GT(peak, 1e-3) << "no rings";
  EXPECT_LT(asym, 1e-3 * peak) << "asymmetry " << asym << " of " << peak;
  EXPECT_GT(peak_wave_energy(high), 1.1 * peak_wave_energy(low))
      << "a faster entry makes larger rings";  // measured 1.34x
}

TEST(WaterCoupling, FiftyFloatersStayFiniteAndInTheWater) {
  PoolRun run;
  run.pool.nodes = 48;
  run.pool.cell = 0.1;
  run.pool.substep = 1.0 / 120;
  for (int k = 0; k < 50; ++k) {
    Floater f;
    f.density_ratio = 0.3 + 0.01 * k;
    f.position = btVector3(btScalar(-1.75 + 0.5 * (k % 8)), btScalar(-1.75 + 0.5 * (k / 8)), btScalar(0.3 + 0.02 * k));
    f.size = btVector3(0.25f, 0.25f, 0.15f);
    f.rotation = btQuaternion(btScalar(0.1 * k), btScalar(0.05 * k), 0);
    run.floaters.push_back(f);
  }
  run.seconds = 10000 * run.pool.substep;
  run.record_every = 100;
  const PoolResult r = run_pool(run);
  EXPECT_EQ(r.nan_count, 0);
  for (std::size_t n = 0; n < r.max_z.size(); ++n) EXPECT_LT(r.max_z[n], 0.3 + 0.02 * double(n) + 1e-3) << n;
  for (double z : r.records.back().z) EXPECT_GT(z, -0.5);
}

TEST(WaterCoupling, VeryLightBodyAtSixtyHertzIsNotLaunched) {
  Floater f = floater(FloaterShape::box, btVector3(0.3f, 0.3f, 0.2f), 0.05);
  f.position.setZ(0.15f);
  PoolRun run = one_floater(f, 5.0);
  run.pool.substep = 1.0 / 60;
  const PoolResult r = run_pool(run);
  EXPECT_EQ(r.nan_count, 0);
  EXPECT_LT(r.max_z[0], 0.15 + 1e-3);
  EXPECT_LT(rel(r.final_draft[0], archimedes_draft(f)), 0.10) << r.final_draft[0];
}

TEST(WaterCoupling, SameResultWhateverTheThreadCount) {
  PoolRun run;
  run.pool.vertical_only = false;
  run.floaters = {floater(FloaterShape::box, btVector3(0.3f, 0.3f, 0.2f), 0.5),
                  floater(FloaterShape::sphere, btVector3(0.2f, 0.2f, 0.2f), 0.7)};
  run.floaters[1].position = btVector3(0.6f, 0.4f, 0.5f);
  run.seconds = 1.0;
  std::uint64_t first = 0;
  for (int threads : {1, 2, 4}) {
    run.pool.threads = threads;
    const PoolResult r = run_pool(run);
    if (threads == 1) first = r.state_hash;
    EXPECT_EQ(r.state_hash, first) << threads << " threads";
  }
}

namespace {
/// A beach: ground rising along x with slope 0.1, crossing z = 0 at x = 1 m.
class Slope : public shore::terrain::HeightSource {
 public:
  [[nodiscard]] double height(double x, double) const override { return 0.1 * (x - 1.0); }
};
}  // namespace

// Nodes over ground above the water's rest level are fixed (the shoreline), the others
// are not: exactly the nodes with x > 1 m on this slope.
TEST(WaterCoupling, ShorelineIsFixedWhereTheGroundRisesAboveTheWater) {
  shore::terrain::TerrainSettings ts;
  ts.cell = 0.05;
  ts.base = std::make_shared<Slope>();
  const shore::terrain::Terrain ground(ts);
  shore::water::PhysicalParameters phys;
  phys.cell = 0.05;
  shore::water::SurfaceSettings ws = shore::water::SurfaceSettings::physical(phys, 32, 16);
  ws.origin_x = 0.0125;  // nodes between soil columns: no node sits exactly on the waterline
  ws.mode = shore::water::SurfaceMode::vertical_only;
  ws.boundary = shore::water::Boundary::vertical_only;
  shore::water::Surface surface(ws);
  shore::scenes::World world;
  shore::bullet::WaterCoupling coupling(world.world(), surface);
  const int fixed = coupling.fix_shoreline(ground);
  int expected = 0;
  for (int j = 0; j < surface.ny(); ++j)
    for (int i = 0; i < surface.nx(); ++i) {
      // The soil column under node i is the nearest one; its ground is above water iff its x > 1.
      const double column_x = ground.column_x(ground.column_i(surface.node_x(i)));
      const bool dry = column_x > 1.0 + 1e-9;
      expected += dry;
      EXPECT_EQ(surface.is_fixed(i, j), dry) << "node " << i << "," << j;
    }
  EXPECT_EQ(fixed, expected);
  EXPECT_GT(fixed, 0);
}

// As for the soil: a shape the water cannot take is refused by add_body; a broken pose later
// is skipped and counted inside stepSimulation.
TEST(WaterCoupling, BadShapesAreRefusedAtAddBodyAndBadPosesSkippedPerSubstep) {
  shore::water::PhysicalParameters phys;
  shore::water::SurfaceSettings ws = shore::water::SurfaceSettings::physical(phys, 32, 32);
  shore::water::Surface surface(ws);
  shore::scenes::World world;
  shore::bullet::WaterCoupling coupling(world.world(), surface);
  expect_bad_bodies_refused_or_skipped(world, coupling, btVector3(0.5f, 0.5f, 0.3f));
}
