// Spray (shore/terrain/spray.h), on the terrain alone with bodies moved by hand: particles
// land where ballistics says, volume is exact at every step, slow bodies make nothing,
// faster ones throw more, results are bit-identical whatever the threads or the order of
// the imprints, the particle limit and the region's edges are kept and counted, the state
// saves and loads, bad parameters are refused by name.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "shore/core/error.h"
#include "shore/terrain/terrain.h"
#include "terrain_fixtures.h"

using namespace shore::terrain;
using namespace shore::terrain::testing;

namespace {

constexpr double kG = 9.81;

/// A wheel driven at a fixed slip along +x, pressed `depth` into the soil, spinning at
/// rim_speed (its bottom moving backward), kinematically: what a slipping tyre does.
struct SpinningWheel {
  double radius = 0.3, width = 0.15, depth = 0.03, rim_speed = 3.0, slip = 0.5;
  std::uint64_t key = 7;
  double x0 = 0.0;

  [[nodiscard]] double speed() const { return (1.0 - slip) * rim_speed; }
  /// Its envelope and imprint at time t (the imprint points at env).
  Imprint at(const Terrain& t, double time, shore::EnvelopeRaster& env) const {
    const double x = x0 + speed() * time, z = radius - depth;
    env = wheel_by_centre(t, x, z, radius, width);
    Imprint im{&env};
    const double omega = rim_speed / radius, turn = omega * time;
    im.velocity.x = speed();
    im.angular_velocity.y = omega;
    im.centre.x = x, im.centre.z = z;
    im.orientation.w = std::cos(turn / 2), im.orientation.y = std::sin(turn / 2);
    im.key = key;
    return im;
  }
};

TerrainSettings sand(double cell = 0.01) {
  TerrainSettings s;
  s.cell = cell;
  s.material = Material::sand();
  s.tile_columns = 32;
  return s;
}

/// |ground + compacted + airborne + lost - edited| after each step, over the volume moved
/// so far (displaced by collision plus picked up by bodies).
struct VolumeWatch {
  double moved = 0.0, worst = 0.0;
  void after(const Terrain& t, const StepReport& r) {
    moved += r.displaced_volume + r.picked_volume;
    const VolumeTotals v = t.volume();
    if (moved > 0.0) worst = std::max(worst, std::abs(v.total() - v.edited) / moved);
  }
};

/// Where a particle at (x, y, z) with velocity v reaches the plane z = ground, with
/// gravity and a linear drag k (closed form of dv/dt = g - k v), by bisection on time.
std::pair<double, double> ballistic_landing(const SprayParticle& p, double k, double ground) {
  auto distance = [&](double v, double t) { return k > 0.0 ? v * (1.0 - std::exp(-k * t)) / k : v * t; };
  auto height = [&](double t) {
    if (k == 0.0) return p.position.z + p.velocity.z * t - 0.5 * kG * t * t;
    const double vt = kG / k;
    return p.position.z + distance(p.velocity.z + vt, t) - vt * t;
  };
  double lo = 0.0, hi = 100.0;
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (height(mid) > ground ? lo : hi) = mid;
  }
  return {p.position.x + distance(p.velocity.x, lo), p.position.y + distance(p.velocity.y, lo)};
}

/// A one-column body that touches the soil once and then leaves it at `velocity`.
Terrain fling_one_particle(double drag, const double velocity[3], SprayParticle& thrown) {
  TerrainSettings s = sand();
  s.material.spray.jitter = 0.0;
  s.material.spray.drag = drag;
  s.material.spray.half_life = 1e-6;      // everything drops off in the first step off the ground
  s.material.spray.speed_scale = 0.1;     // and flies
  s.material.spray.particle_size = 0.05;  // one particle holds more than a piece: one per piece
  Terrain t(s);
  const double dt = 0.01;
  for (int step = 0; step < 2; ++step) {
    const double lift = double(step) * dt;
    const shore::EnvelopeRaster env =
        box_envelope(t.column_i(velocity[0] * lift), t.column_j(velocity[1] * lift), 1, 1, velocity[2] * lift);
    Imprint im{&env};
    im.velocity.x = velocity[0], im.velocity.y = velocity[1], im.velocity.z = velocity[2];
    im.centre.x = velocity[0] * lift, im.centre.y = velocity[1] * lift, im.centre.z = 0.05 + velocity[2] * lift;
    im.key = 1;
    t.step({&im, 1}, dt);
  }
  const std::vector<SprayParticle> p = t.spray_particles();
  EXPECT_EQ(p.size(), 1u);
  if (!p.empty()) thrown = p.front();
  return t;
}

/// The column of a rectangle whose height rose most since `before` (its heights, row-major).
struct Rise {
  std::int64_t i = 0, j = 0;
  double height = 0.0;
};

std::vector<double> heights_of(const Terrain& t, const shore::GridRect& r) {
  std::vector<double> h;
  for (std::int64_t j = r.j0; j < r.j0 + r.ny; ++j)
    for (std::int64_t i = r.i0; i < r.i0 + r.nx; ++i) h.push_back(t.height(i, j));
  return h;
}

Rise highest_rise(const Terrain& t, const shore::GridRect& r, const std::vector<double>& before) {
  Rise most;
  std::size_t k = 0;
  for (std::int64_t j = r.j0; j < r.j0 + r.ny; ++j)
    for (std::int64_t i = r.i0; i < r.i0 + r.nx; ++i, ++k)
      if (const double d = t.height(i, j) - before[k]; d > most.height) most = {i, j, d};
  return most;
}

/// Flies the thrown particle until it lands (within 2 s); the column that rose within
/// `r` must be where ballistics puts it, (x, y), within one column, and hold its volume.
Rise expect_landing(Terrain& t, const shore::GridRect& r, const SprayParticle& p, double x, double y, double drag) {
  const std::vector<double> before = heights_of(t, r);
  for (int k = 0; k < 200 && t.spray_counts().landed == 0; ++k) t.step({}, 0.01);
  EXPECT_EQ(t.spray_counts().landed, 1) << "drag " << drag;
  const Rise hit = highest_rise(t, r, before);
  const double cell = t.settings().cell;
  EXPECT_LE(std::abs(t.column_x(hit.i) - x), cell)
      << "drag " << drag << ": landed at column x " << t.column_x(hit.i) << ", ballistics " << x;
  EXPECT_LE(std::abs(t.column_y(hit.j) - y), cell) << "drag " << drag;
  EXPECT_NEAR(hit.height * cell * cell, p.volume, 1e-15 * p.volume + 1e-22) << "its whole volume, on that column";
  return hit;
}

}  // namespace

// On flat ground, and onto a raised wall across the path: a flight is not sampled against
// the ground while it is above the highest soil top near its path (spray_flight.h), and the
// wall must still catch the particle where ballistics crosses the wall's top.
TEST(Spray, AParticleLandsWhereBallisticsSaysAndAddsItsVolumeThere) {
  const double velocity[3] = {2.0, 1.0, 3.0};
  for (const double wall : {0.0, 0.1})  // m, the top of the ground it lands on
    for (const double drag : {0.0, 2.0}) {
      SprayParticle p;
      Terrain t = fling_one_particle(drag, velocity, p);
      ASSERT_GT(p.volume, 0.0);
      EXPECT_NEAR(p.velocity.x, velocity[0] * (drag > 0 ? std::exp(-drag * 0.01) : 1.0), 0.05);
      const auto [x, y] = ballistic_landing(p, drag, wall);
      const shore::GridRect r{t.column_i(x) - 8, t.column_j(y) - 8, 33, 17};
      if (wall > 0.0)
        for (std::int64_t j = r.j0; j < r.j0 + r.ny; ++j)
          for (std::int64_t i = r.i0; i < r.i0 + r.nx; ++i) t.set_height(i, j, t.base_height(i, j) + wall);
      const VolumeTotals before = t.volume();
      const Rise hit = expect_landing(t, r, p, x, y, drag);
      EXPECT_EQ(t.volume().airborne, 0.0);
      EXPECT_NEAR(t.volume().ground - before.ground, p.volume, 1e-18);
      // Landed soil is loose: it lowers the column's sinkage by its height.
      EXPECT_NEAR(t.sinkage(hit.i, hit.j), -hit.height, 1e-15);
    }
}

TEST(Spray, VolumeIsExactAtEveryStepOfASpinningWheel) {
  Terrain t(sand());
  const SpinningWheel w;
  const double dt = 1.0 / 240;
  VolumeWatch watch;
  double peak_airborne = 0.0;
  shore::EnvelopeRaster env;
  for (int k = 0; k < 480; ++k) {  // 2 s at 50 % slip
    const Imprint im = w.at(t, k * dt, env);
    watch.after(t, t.step({&im, 1}, dt));
    peak_airborne = std::max(peak_airborne, t.volume().airborne);
  }
  const SprayCounts c = t.spray_counts();
  EXPECT_GT(c.created, 100) << "a wheel spinning at 3 m/s throws sand";
  EXPECT_GT(c.landed, 50);
  EXPECT_GT(peak_airborne, 0.0);
  EXPECT_LT(watch.worst, 1e-12) << "worst |ground + compacted + airborne + lost - edited| / moved";
}

// A material map: a piece loads the adhesion of the column it touches (Sumner's area x
// adhesion). Painted with a copy of sand, the wheel picks up and throws exactly what it does
// on sand alone; painted with a gravel of no adhesion, nothing.
TEST(Spray, APieceLoadsTheAdhesionOfTheColumnItTouches) {
  const auto run = [](const Material* painted) {
    Terrain t(sand());
    if (painted != nullptr) {
      t.set_palette({Material::sand(), *painted});
      t.paint_rect({-50, -50, 400, 100}, 1);  // under the wheel's whole path
    }
    const SpinningWheel w;
    shore::EnvelopeRaster env;
    for (int k = 0; k < 240; ++k) {
      const Imprint im = w.at(t, k / 240.0, env);
      t.step({&im, 1}, 1.0 / 240);
    }
    return t.spray_counts();
  };
  const SprayCounts alone = run(nullptr);
  ASSERT_GT(alone.picked_volume, 0.0) << "the wheel picked nothing up: this tests nothing";
  Material copy = Material::sand();
  copy.name = "sand copy";
  const SprayCounts same = run(&copy);
  EXPECT_EQ(same.picked_volume, alone.picked_volume);
  EXPECT_EQ(same.created, alone.created);
  Material gravel = Material::sand();
  gravel.name = "gravel";
  gravel.spray.adhesion = 0.0;
  const SprayCounts none = run(&gravel);
  EXPECT_EQ(none.picked_volume, 0.0);
  EXPECT_EQ(none.created, 0);
}

TEST(Spray, BodiesAtRestOrCreepingMakeNothingAndHoldNoMemory) {
  // Rolling: no point of the ball moves faster than twice its speed, below sand's min_speed
  // of 0.3 m/s.
  for (const double speed : {0.0, 0.05, 0.14}) {
    Terrain on(sand());
    TerrainSettings quiet = sand();
    quiet.spray.enabled = false;
    Terrain off(quiet);
    for (int k = 0; k < 120; ++k) {
      const double x = speed * k / 240.0;
      for (Terrain* t : {&on, &off}) {
        const shore::EnvelopeRaster ball = sphere_envelope(*t, x, 0.0, 0.1 - 0.02 - 1e-4 * k, 0.1);
        Imprint im{&ball};
        im.velocity.x = speed, im.velocity.z = -0.024;
        im.centre.x = x, im.centre.z = 0.08 - 1e-4 * k;
        im.angular_velocity.y = speed / 0.1;  // rolling
        t->step({&im, 1}, 1.0 / 240);
      }
    }
    const SprayCounts c = on.spray_counts();
    EXPECT_EQ(c.created, 0) << speed;
    EXPECT_EQ(c.clinging_cells, 0) << speed;
    EXPECT_EQ(c.picked_volume, 0.0) << speed;
    EXPECT_EQ(on.volume().airborne, 0.0) << speed;
    EXPECT_EQ(on.memory_bytes(), off.memory_bytes()) << "spray allocated something at " << speed << " m/s";
  }
}

// A wheel's rim stays on the soil for many steps (here 0.9 rad of its turn at 10 rad/s,
// 21 steps of 1/240 s): stepping its clinging soil every second step over twice the time
// (Imprint::cling_every) finds every piece that passes the soil, so it picks up and throws
// about as much, the volume still exact at every step.
TEST(Spray, ARimThatStaysOnTheSoilClingsAsMuchSteppedEverySecondStep) {
  const auto run = [](int every, double& worst) {
    Terrain t(sand());
    const SpinningWheel w;
    const double dt = 1.0 / 240;
    VolumeWatch watch;
    shore::EnvelopeRaster env;
    for (int k = 0; k < 480; ++k) {  // 2 s at 50 % slip
      Imprint im = w.at(t, k * dt, env);
      im.cling_every = every;
      watch.after(t, t.step({&im, 1}, dt));
    }
    worst = watch.worst;
    return t.spray_counts();
  };
  double worst_each = 0.0, worst_second = 0.0;
  const SprayCounts each = run(1, worst_each), second = run(2, worst_second);
  ASSERT_GT(each.picked_volume, 0.0) << "the wheel picked nothing up: this tests nothing";
  EXPECT_NEAR(second.picked_volume / each.picked_volume, 1.0, 0.03);
  EXPECT_NEAR(double(second.created) / double(each.created), 1.0, 0.05);
  EXPECT_LT(worst_second, 1e-12) << "worst |ground + compacted + airborne + lost - edited| / moved";
  std::printf("picked %.6e / %.6e m^3, created %lld / %lld\n", second.picked_volume, each.picked_volume,
              static_cast<long long>(second.created), static_cast<long long>(each.created));
}

namespace {

/// A 3 x 3 column plate that presses 1 mm into the soil for 3 steps while moving along x at
/// 1 m/s (it loads its pieces), then is lifted 5 cm and keeps moving: its soil sheds with
/// the half-life in particles far smaller than a piece's load. `cadence(step)` is its
/// Imprint::cling_every at each step after the lift.
struct ShedCadence {
  static constexpr double kDt = 1.0 / 240;
  static constexpr int kPress = 3;
  static constexpr std::uint64_t kKey = 0xc1a9'0b0d'1e55'0005;  // distinct in the state file's bytes
  Terrain t;
  VolumeWatch watch;
  explicit ShedCadence(const TerrainSettings& s) : t(s) {}

  static TerrainSettings settings() {
    TerrainSettings s = sand();
    s.material.spray.particle_size = 0.0005;  // 1/1500 of a piece's load: the rounding stays small
    return s;
  }
  /// Steps it once (the k-th, from 0) at this cadence; returns whether its soil was stepped.
  bool step(int k, int cadence) {
    const bool lifted = k >= kPress;
    const shore::EnvelopeRaster env = box_envelope(10, 10, 3, 3, lifted ? 0.05 : -0.001);
    Imprint im{&env};
    im.velocity.x = 1.0;
    im.centre.x = t.column_x(11), im.centre.y = t.column_y(11), im.centre.z = lifted ? 0.1 : 0.05;
    im.key = kKey;
    im.cling_every = cadence;
    watch.after(t, t.step({&im, 1}, kDt));
    return k % cadence == 0;
  }
};

}  // namespace

// Shedding is exponential: over any time, whatever the steps it is cut into, a piece sheds
// the same share. A body whose cadence switches (1, 1, 2, 2, 1, 2, 3, ...) must so hold,
// after each of its clinging steps, what a body stepped every step holds then, up to the
// particles' rounding (each piece owes less than a particle either way).
TEST(Spray, ABodySwitchingCadenceShedsWhatItShedsEveryStep) {
  const int cadences[] = {1, 1, 2, 2, 1, 2, 2, 2, 1, 3, 3, 1, 2, 1, 3, 3, 3, 2, 2, 1};
  ShedCadence each(ShedCadence::settings()), switching(ShedCadence::settings());
  const double vp = ShedCadence::settings().material.spray.particle_volume();
  int compared = 0;
  for (int k = 0; k < 60; ++k) {
    const int cadence = k < ShedCadence::kPress ? 1 : cadences[(k - ShedCadence::kPress) % std::size(cadences)];
    each.step(k, 1);
    if (!switching.step(k, cadence) || k <= ShedCadence::kPress) continue;
    const double held = each.t.volume().clinging;
    ASSERT_GT(held, 0.0) << "the plate holds nothing at step " << k << ": this tests nothing";
    const auto pieces = static_cast<double>(each.t.spray_counts().clinging_cells);
    EXPECT_NEAR(switching.t.volume().clinging, held, 2.0 * pieces * vp)
        << "at step " << k << ", cadence " << cadence << " (" << held / vp << " particles held)";
    ++compared;
  }
  EXPECT_GT(compared, 30);
  EXPECT_LT(each.t.volume().clinging, 0.5 * each.t.spray_counts().picked_volume) << "too little shed to test";
  EXPECT_LT(each.watch.worst, 1e-12) << "worst |ground + compacted + airborne + lost - edited| / moved";
  EXPECT_LT(switching.watch.worst, 1e-12) << "worst |ground + compacted + airborne + lost - edited| / moved";
  EXPECT_EQ(switching.t.spray_counts().picked_volume, each.t.spray_counts().picked_volume);
}

TEST(Spray, AirborneVolumeGrowsWithTheWheelsSpeed) {
  double last = 0.0;
  for (const double rim : {1.0, 2.0, 4.0, 8.0}) {
    Terrain t(sand());
    SpinningWheel w;
    w.rim_speed = rim;
    const double dt = 1.0 / 240;
    double sum = 0.0;
    shore::EnvelopeRaster env;
    for (int k = 0; k < 120; ++k) {
      const Imprint im = w.at(t, k * dt, env);
      t.step({&im, 1}, dt);
      if (k >= 60) sum += t.volume().airborne;
    }
    const double mean = sum / 60;
    EXPECT_GT(mean, last) << "mean airborne volume at rim speed " << rim << " m/s";
    last = mean;
  }
}

namespace {

/// A spinning wheel and a sphere sliding fast beside it, imprints in either order.
std::uint64_t two_bodies(int threads, bool reversed) {
  TerrainSettings s = sand();
  s.threads = threads;
  s.parallel_min_columns = 0;  // split even these small regions between threads
  s.max_erosion_passes = 2;    // fewer fork-joins: this machine's cores are shared
  Terrain t(s);
  SpinningWheel w;
  const double dt = 1.0 / 240;
  shore::EnvelopeRaster wheel;
  for (int k = 0; k < 60; ++k) {
    const double x = 2.0 * k * dt;
    const shore::EnvelopeRaster ball = sphere_envelope(t, x, 0.4, 0.1 - 0.015, 0.1);
    Imprint b{&ball};
    b.velocity.x = 2.0, b.angular_velocity.x = -5.0, b.centre = {x, 0.4, 0.085}, b.key = 3;
    const Imprint a = w.at(t, k * dt, wheel);
    const Imprint ims[2] = {reversed ? b : a, reversed ? a : b};
    t.step(ims, dt);
  }
  EXPECT_GT(t.spray_counts().created, 0);
  return t.state_hash();
}

}  // namespace

TEST(Spray, SameHashForOneTwoFourThreadsAndEitherOrderOfTheBodies) {
  const std::uint64_t one = two_bodies(1, false);
  EXPECT_EQ(two_bodies(2, false), one);
  EXPECT_EQ(two_bodies(4, false), one);
  EXPECT_EQ(two_bodies(2, true), one);
}

TEST(Spray, TheStateHashCoversTheParticles) {
  // Two seeds, stopped right after the first particles are thrown: particles elsewhere.
  std::uint64_t hashes[2];
  for (int n = 0; n < 2; ++n) {
    TerrainSettings s = sand();
    s.spray.seed = 1000 + n;
    Terrain t(s);
    const SpinningWheel w;
    shore::EnvelopeRaster env;
    for (int k = 0; k < 400 && t.spray_counts().created == 0; ++k) {
      const Imprint im = w.at(t, k / 240.0, env);
      t.step({&im, 1}, 1.0 / 240);
    }
    ASSERT_GT(t.spray_counts().created, 0);
    hashes[n] = t.state_hash();
  }
  EXPECT_NE(hashes[0], hashes[1]);
}

TEST(Spray, TheParticleLimitIsKeptAndTheRestLaidAtOnce) {
  TerrainSettings s = sand();
  s.spray.max_particles = 3;
  Terrain t(s);
  SpinningWheel w;
  w.rim_speed = 6.0;
  VolumeWatch watch;
  shore::EnvelopeRaster env;
  for (int k = 0; k < 240; ++k) {
    const Imprint im = w.at(t, k / 240.0, env);
    watch.after(t, t.step({&im, 1}, 1.0 / 240));
    ASSERT_LE(t.spray_particles().size(), 3u);
  }
  EXPECT_GT(t.spray_counts().limited, 0);
  EXPECT_LT(watch.worst, 1e-12);
}

TEST(Spray, ParticlesLeavingTheRegionAreCountedLost) {
  TerrainSettings s = sand();
  s.spray.x_min = -0.05;  // the wheel throws backward, toward -x
  s.spray.x_max = 10.0;
  Terrain t(s);
  SpinningWheel w;
  w.rim_speed = 6.0;
  VolumeWatch watch;
  shore::EnvelopeRaster env;
  for (int k = 0; k < 120; ++k) {
    const Imprint im = w.at(t, k / 240.0, env);
    watch.after(t, t.step({&im, 1}, 1.0 / 240));
  }
  EXPECT_GT(t.spray_counts().lost, 0);
  EXPECT_GT(t.volume().lost, 0.0);
  EXPECT_LT(watch.worst, 1e-12) << "lost volume is counted, never dropped";
}

TEST(Spray, ABodyThatLeavesTheStepSetsItsSoilDown) {
  Terrain t(sand());
  SpinningWheel w;
  shore::EnvelopeRaster env;
  for (int k = 0; k < 60; ++k) {
    const Imprint im = w.at(t, k / 240.0, env);
    t.step({&im, 1}, 1.0 / 240);
  }
  const SprayCounts before = t.spray_counts();
  ASSERT_GT(before.clinging_cells, 0);
  const double clinging = t.volume().clinging;
  ASSERT_GT(clinging, 0.0);
  t.step({}, 0.0);  // no time passes: nothing moves
  EXPECT_EQ(t.volume().clinging, clinging);
  EXPECT_EQ(t.spray_counts().particles, before.particles);
  t.step({}, 1.0 / 240);  // the wheel is gone: its soil goes down at once
  EXPECT_EQ(t.spray_counts().clinging_cells, 0);
  EXPECT_EQ(t.volume().clinging, 0.0);
  EXPECT_EQ(t.spray_counts().set_down, before.set_down + before.clinging_cells);
}

TEST(Spray, SavedMidFlightItLoadsBitExactAndContinuesIdentically) {
  Terrain a(sand());
  SpinningWheel w;
  shore::EnvelopeRaster env;
  int k = 0;
  for (; k < 100; ++k) {
    const Imprint im = w.at(a, k / 240.0, env);
    a.step({&im, 1}, 1.0 / 240);
  }
  ASSERT_GT(a.spray_counts().particles, 0);
  ASSERT_GT(a.spray_counts().clinging_cells, 0);
  const auto file = std::filesystem::temp_directory_path() / "shore_terrain_test_spray.state";
  a.save(file);
  Terrain b = Terrain::load(file);
  EXPECT_EQ(b.state_hash(), a.state_hash());
  EXPECT_EQ(b.spray_counts().created, a.spray_counts().created);
  EXPECT_EQ(b.volume().airborne, a.volume().airborne);
  EXPECT_TRUE(b.settings().spray.enabled);
  for (; k < 160; ++k)
    for (Terrain* t : {&a, &b}) {
      const Imprint im = w.at(*t, k / 240.0, env);
      t->step({&im, 1}, 1.0 / 240);
    }
  EXPECT_EQ(b.state_hash(), a.state_hash());
  std::filesystem::remove(file);
}

// Saved after a step its cadence skipped (cadence 2, on an odd step), the wheel's body must
// remember when its soil was last stepped: the next step covers two steps' time.
TEST(Spray, SavedBetweenTheTwoStepsOfACadenceItContinuesIdentically) {
  Terrain a(sand());
  SpinningWheel w;
  shore::EnvelopeRaster env;
  const auto step = [&](Terrain& t, int k) {
    Imprint im = w.at(t, k / 240.0, env);
    im.cling_every = k < 100 || (k / 3) % 2 == 0 ? 2 : 1;  // 2, then switching on either parity
    t.step({&im, 1}, 1.0 / 240);
  };
  int k = 0;
  for (; k < 99; ++k) step(a, k);  // 99 steps: the last one (98) clung
  const std::vector<unsigned char> at_its_step = a.save_bytes();
  step(a, k++);  // step 99, odd: kept as it is
  ASSERT_GT(a.volume().clinging, 0.0) << "nothing clings: this tests nothing";
  const std::vector<unsigned char> bytes = a.save_bytes();
  ASSERT_GT(bytes.size(), 8u);
  EXPECT_EQ(at_its_step[8], 5) << "a terrain of one material, every body stepped on the last step: as before";
  EXPECT_EQ(bytes[8], 9) << "a body between two clinging steps needs the format that keeps its last one";
  Terrain b = Terrain::load_bytes(bytes, "between");
  EXPECT_EQ(b.state_hash(), a.state_hash());
  EXPECT_EQ(b.save_bytes(), bytes);
  for (; k < 160; ++k)
    for (Terrain* t : {&a, &b}) step(*t, k);
  EXPECT_EQ(b.state_hash(), a.state_hash());
  EXPECT_EQ(b.volume().clinging, a.volume().clinging);
}

// A body's last clinging step lies 1 to 2^20 steps before the spray's (cadences of 1 to
// 16 never skip more in a row): a file saying otherwise is refused, naming it.
TEST(Spray, ABodysLastClingingStepOutOfRangeIsRefused) {
  ShedCadence plate(ShedCadence::settings());
  for (int k = 0; k < 5 || plate.t.save_bytes()[8] != 9; ++k) {
    ASSERT_LT(k, 10) << "the plate never rested between two clinging steps";
    plate.step(k, 2);
  }
  const std::vector<unsigned char> good = plate.t.save_bytes();
  // The body's record: u64 key, f64 centre[3], f64 q[4], then i64 stepped.
  unsigned char key[8];
  std::memcpy(key, &ShedCadence::kKey, sizeof key);
  const auto found = std::search(good.begin(), good.end(), std::begin(key), std::end(key));
  ASSERT_NE(found, good.end());
  const auto at = static_cast<std::size_t>(found - good.begin()) + 8 + 3 * 8 + 4 * 8;
  std::int64_t stepped = 0;
  std::memcpy(&stepped, good.data() + at, sizeof stepped);
  const std::int64_t step = stepped + 2;  // cadence 2, between its two steps
  const auto with_stepped = [&](std::int64_t value) {
    std::vector<unsigned char> bytes = good;
    std::memcpy(bytes.data() + at, &value, sizeof value);
    reseal(bytes);
    try {
      (void)Terrain::load_bytes(bytes, "stepped");
    } catch (const shore::FileError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(with_stepped(stepped), "") << "the file as written";
  EXPECT_EQ(with_stepped(step - (std::int64_t{1} << 20)), "") << "the most steps a body may wait";
  for (const std::int64_t bad : {step, step + 7, step - (std::int64_t{1} << 20) - 1,
                                 std::numeric_limits<std::int64_t>::min(), std::numeric_limits<std::int64_t>::max()})
    EXPECT_TRUE(mentions(with_stepped(bad), "a spray body last stepped on step " + std::to_string(bad)))
        << with_stepped(bad);
}

TEST(Spray, BadParametersAndInputsAreRefusedByName) {
  auto bad = [](const std::function<void(TerrainSettings&)>& edit) {
    TerrainSettings s;
    edit(s);
    return message_of<shore::InvalidSetting>([&] { Terrain t(s); });
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(mentions(bad([](auto& s) { s.material.spray.adhesion = -1e-3; }), "Material(sand).spray.adhesion"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.material.spray.half_life = 0.0; }), "spray.half_life = 0"));
  EXPECT_TRUE(mentions(bad([nan](auto& s) { s.material.spray.speed_scale = nan; }), "spray.speed_scale"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.material.spray.exponent = 0.0; }), "spray.exponent"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.material.spray.particle_size = -0.004; }), "spray.particle_size"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.material.spray.min_speed = -1.0; }), "spray.min_speed"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.material.spray.jitter = 1.5; }), "spray.jitter = 1.5"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.material.spray.drag = -0.1; }), "spray.drag"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.spray.max_particles = -1; }), "TerrainSettings.spray.max_particles"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.spray.gravity = 0.0; }), "spray.gravity"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.spray.max_flight = 0.0; }), "spray.max_flight"));
  EXPECT_TRUE(mentions(bad([](auto& s) { s.spray.x_min = 1.0, s.spray.x_max = 1.0; }), "spray.x_min / x_max"));
  EXPECT_TRUE(mentions(bad([nan](auto& s) { s.spray.y_max = nan; }), "spray.y_min / y_max"));

  Terrain t(sand());
  const shore::EnvelopeRaster env = sphere_envelope(t, 0.0, 0.0, 0.09, 0.1);
  auto step_error = [&](const std::function<void(Imprint&)>& edit, double dt = 0.01) {
    Imprint im{&env};
    edit(im);
    return message_of<shore::InvalidSetting>([&] { t.step({&im, 1}, dt); });
  };
  EXPECT_TRUE(mentions(step_error([](Imprint&) {}, -0.01), "terrain.Terrain.step.dt"));
  EXPECT_TRUE(mentions(step_error([](Imprint&) {}, nan), "step.dt"));
  EXPECT_TRUE(mentions(step_error([nan](Imprint& im) { im.angular_velocity.z = nan; }),
                       "terrain.Imprint[0].angular_velocity.z"));
  EXPECT_TRUE(mentions(step_error([](Imprint& im) { im.cling_every = 0; }), "terrain.Imprint[0].cling_every = 0"));
  EXPECT_TRUE(mentions(step_error([](Imprint& im) { im.cling_every = 17; }), "cling_every = 17"));
  EXPECT_TRUE(
      mentions(step_error([](Imprint& im) { im.centre.x = std::numeric_limits<double>::infinity(); }), "centre.x"));
  EXPECT_TRUE(mentions(step_error([](Imprint& im) { im.orientation.w = 0.0; }), "terrain.Imprint[0].orientation"));
  const Imprint two[2] = {{&env}, {&env}};
  EXPECT_TRUE(mentions(message_of<shore::InvalidSetting>([&] { t.step(two, 0.01); }), "terrain.Imprint[1].key"));
  EXPECT_EQ(message_of<shore::InvalidSetting>([&] { t.step(two, 0.0); }), "(no exception)")
      << "keys only matter when time passes";
  EXPECT_EQ(t.spray_counts().created, 0);
}
