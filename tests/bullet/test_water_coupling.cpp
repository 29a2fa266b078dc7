// Bodies in spring-mass water through Bullet, against Archimedes and hydrostatics
// (the cases and their references: scenes/include/shore/scenes/pool_cases.h).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "shore/core/error.h"

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
  run.pool.parallel_min_nodes = 0;  // the team on every substep, however small the pool
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

// ---- drag, force, errors ---------------------------------------------------------------

namespace {
TowRun tow(FloaterShape shape, btVector3 size, double ratio) {
  TowRun run;
  run.pool.nodes = 128;  // 6.4 m along the tow
  run.pool.nodes_y = 64;
  run.pool.damping_time = 1.0;
  run.floater.shape = shape;
  run.floater.size = size;
  run.floater.density_ratio = ratio;
  run.floater.position = btVector3(-2.5f, 0.013f, 0.0f);  // height: run_tow puts it at its draft
  return run;
}
}  // namespace

// A box 0.3 m wide floating 0.1 m deep, towed at 1 m/s: the water pushes back with
// 1/2 rho C_d A v^2 on its frontal area A = 0.3 x 0.1 m (15 N at C_d = 1), plus the
// linear term rho k A v where k is set. (The old model felt V / sample size: 31 x.) In its
// own waves the bow wave raises the water in front and the drag by a few per cent.
TEST(WaterDrag, TowedBoxFeelsTheDragLawOnItsFrontalArea) {
  for (double k : {0.0, 0.2})
    for (bool waves : {false, true}) {
      TowRun run = tow(FloaterShape::box, btVector3(0.3f, 0.3f, 0.2f), 0.5);
      run.pool.fluid.linear_drag = k;
      run.disturb = waves;
      const TowResult r = run_tow(run);
      EXPECT_EQ(r.nan_count, 0);
      EXPECT_NEAR(r.area, 0.03, 0.001) << "towed at draft " << r.draft;
      EXPECT_LT(rel(r.drag, r.reference), waves ? 0.06 : 0.005)
          << "k " << k << (waves ? ", in its waves" : "") << ": drag " << r.drag << " N vs " << r.reference << " N";
    }
}

TEST(WaterDrag, TowedBallFeelsTheDragLawOnItsWetSegment) {
  for (bool waves : {false, true}) {
    TowRun run = tow(FloaterShape::sphere, btVector3(0.2f, 0.2f, 0.2f), 0.5);
    run.pool.fluid.linear_drag = 0.0;
    run.disturb = waves;
    const TowResult r = run_tow(run);
    EXPECT_NEAR(r.area, 0.5 * std::numbers::pi * 0.01, 0.001) << "half a disc of r 0.1 m at half density";
    EXPECT_LT(rel(r.drag, r.reference), waves ? 0.06 : 0.005) << r.drag << " N vs " << r.reference << " N";
  }
}

TEST(WaterDrag, DoesNotDependOnSamplesPerCell) {
  double drag[2] = {};
  for (int n = 0; n < 2; ++n) {
    TowRun run = tow(FloaterShape::box, btVector3(0.3f, 0.3f, 0.2f), 0.5);
    run.pool.fluid.samples_per_cell = n == 0 ? 2 : 8;
    drag[n] = run_tow(run).drag;
  }
  EXPECT_LT(rel(drag[1], drag[0]), 0.05) << "2 samples: " << drag[0] << " N, 8 samples: " << drag[1] << " N";
}

// A ball of density 1.5 and 0.1 m sinks through 3 m of water at the speed where the drag
// law balances its weight less its buoyancy.
TEST(WaterDrag, DenseBallSinksAtItsTerminalVelocity) {
  SinkRun run;
  run.pool.depth = 3.0;
  run.pool.nodes = 32;
  run.pool.cell = 0.1;
  run.seconds = 8.0;
  const SinkResult r = run_sink(run);
  EXPECT_EQ(r.nan_count, 0);
  ASSERT_GT(r.terminal, 0.0) << "it did not reach the depths measured";
  EXPECT_LT(rel(r.terminal, r.reference), 0.10) << r.terminal << " m/s vs " << r.reference << " m/s";
}

// Boxes and a convex hull (an octagonal prism) released at rest at Archimedes' draft stay
// there, to a tenth of a percent; the water's force on them balances their weight.
TEST(WaterForce, RestingFloatersHoldArchimedesDraftAndBalanceTheirWeight) {
  PoolRun run;
  run.pool.damping_time = 1.0;
  run.seconds = 3.0;
  for (auto [shape, ratio] : {std::pair{FloaterShape::box, 0.5}, {FloaterShape::hull, 0.4}, {FloaterShape::box, 0.8}}) {
    Floater f;
    f.shape = shape;
    f.size = btVector3(0.3f, 0.3f, 0.2f);
    f.density_ratio = ratio;
    f.position = btVector3(btScalar(-1.0 + 0.9 * double(run.floaters.size())), 0.013f, btScalar((0.5 - ratio) * 0.2));
    run.floaters.push_back(f);
  }
  const PoolResult r = run_pool(run);
  for (std::size_t n = 0; n < run.floaters.size(); ++n)
    EXPECT_LT(rel(r.final_draft[n], archimedes_draft(run.floaters[n])), 1e-3)
        << "floater " << n << ": " << r.final_draft[n] << " vs " << archimedes_draft(run.floaters[n]);
}

TEST(WaterForce, IsReportedPerBodyAndBalancesTheWeightAtRest) {
  shore::water::PhysicalParameters phys;
  shore::water::SurfaceSettings ws = shore::water::SurfaceSettings::physical(phys, 32, 32);
  ws.origin_x = ws.origin_y = -0.775;
  ws.mode = shore::water::SurfaceMode::vertical_only;
  shore::water::Surface surface(ws);
  World world;
  shore::bullet::WaterCoupling coupling(world.world(), surface);
  Floater f;
  f.size = btVector3(0.3f, 0.3f, 0.2f);
  f.density_ratio = 0.5;
  f.position = btVector3(0.01f, 0.02f, 0.0f);  // at its draft
  btRigidBody* b = add_floater(world, f);
  coupling.add_body(b);
  EXPECT_EQ(coupling.water_force(b).submerged_volume, 0.0) << "nothing before the first substep";
  for (int k = 0; k < 480; ++k) world.step(1.0 / 240);
  const shore::bullet::BodyWater w = coupling.water_force(b);
  const double weight = 9.81 / b->getInvMass();
  EXPECT_NEAR(w.force.z(), weight, 0.01 * weight);
  EXPECT_NEAR(w.buoyancy.z(), 1000 * 9.81 * w.submerged_volume, 1e-3);
  EXPECT_NEAR(w.submerged_volume, 0.5 * 0.3 * 0.3 * 0.2, 1e-2 * 0.009);
  EXPECT_NEAR(w.centre_of_buoyancy.z(), -0.05, 5e-4) << "half way down the wet half";
  EXPECT_LT(w.torque.length(), 0.01 * weight * 0.15) << "upright: no heeling moment";
  EXPECT_DOUBLE_EQ(coupling.submerged_volume(b), w.submerged_volume);
  EXPECT_EQ(coupling.water_force(nullptr).submerged_volume, 0.0);
}

TEST(WaterCoupling, AddBodyRefusesANanPoseAndAZeroSizeShape) {
  shore::water::PhysicalParameters phys;
  shore::water::Surface surface(shore::water::SurfaceSettings::physical(phys, 16, 16));
  World world;
  shore::bullet::WaterCoupling coupling(world.world(), surface);
  btRigidBody* nan_body =
      world.add_body(std::make_unique<btBoxShape>(btVector3(0.1f, 0.1f, 0.1f)), 1.0, btVector3(0, 0, 0));
  btTransform t = nan_body->getWorldTransform();
  t.setOrigin(btVector3(std::numeric_limits<btScalar>::quiet_NaN(), 0, 0));
  nan_body->setWorldTransform(t);
  try {
    coupling.add_body(nan_body);
    ADD_FAILURE() << "a NaN pose was accepted";
  } catch (const shore::InvalidSetting& e) {
    EXPECT_NE(std::string(e.what()).find("pose"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("nan"), std::string::npos) << e.what();
  }
  btRigidBody* flat =
      world.add_body(std::make_unique<btBoxShape>(btVector3(0.1f, 0.0f, 0.1f)), 1.0, btVector3(0, 0, 0));
  try {
    coupling.add_body(flat);
    ADD_FAILURE() << "a box of zero thickness was accepted";
  } catch (const shore::InvalidSetting& e) {
    EXPECT_NE(std::string(e.what()).find("half extent y"), std::string::npos) << e.what();
  }
  btRigidBody* dot = world.add_body(std::make_unique<btSphereShape>(btScalar(0)), 1.0, btVector3(0, 0, 0));
  EXPECT_THROW(coupling.add_body(dot), shore::InvalidSetting);
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
