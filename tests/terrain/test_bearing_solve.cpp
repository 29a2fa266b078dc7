// BearingSolve: one envelope solved for two loads in turn gives exactly what
// Terrain::bearing_offset and Terrain::bearing give for each, on a fresh plate (Bekker's
// sinkage) and on painted, already rutted ground; bad use is refused by name. Under a
// spring that relaxes as it sinks, a plate sinks where Bekker's pressure meets the spring's
// load, and a ball where the nested search on the load (a raised raycast wheel's) answers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "shore/core/error.h"
#include "shore/core/illinois.h"
#include "shore/terrain/bearing_solve.h"
#include "shore/terrain/bekker.h"
#include "shore/terrain/terrain.h"
#include "terrain_fixtures.h"

using namespace shore::terrain;
using namespace shore::terrain::testing;

namespace {

constexpr int kPlate = 30;  // 0.3 m x 0.3 m at 1 cm

/// Both bearings hold the same bits (capacity, width, every column's force).
void expect_same(const Bearing& a, const Bearing& b) {
  EXPECT_EQ(std::memcmp(&a.capacity, &b.capacity, sizeof(double)), 0);
  EXPECT_EQ(a.patch_width, b.patch_width);
  EXPECT_EQ(a.contact_columns, b.contact_columns);
  ASSERT_EQ(a.columns.size(), b.columns.size());
  for (std::size_t k = 0; k < a.columns.size(); ++k) {
    EXPECT_EQ(a.columns[k].i, b.columns[k].i);
    EXPECT_EQ(a.columns[k].j, b.columns[k].j);
    EXPECT_EQ(a.columns[k].force, b.columns[k].force);
  }
}

/// Solves env for each load in turn with one BearingSolve and checks it against the terrain.
void expect_like_terrain(const Terrain& t, const shore::EnvelopeRaster& env, std::initializer_list<double> loads) {
  BearingSolve solve;
  solve.reset(t, env);
  for (const double load : loads) {
    const double o = solve.offset(load);
    EXPECT_EQ(o, t.bearing_offset(env, load)) << "load " << load;
    expect_same(solve.bearing(o), t.bearing(env, o));
  }
}

/// Sand, the soil's work on one thread (the same bits whatever the machine).
TerrainSettings one_thread_sand() {
  TerrainSettings s;
  s.material = Material::sand();
  s.threads = 1;
  return s;
}

/// Sand with a strip four times as stiff (k_phi) and a patch of mud painted across the
/// plates' and balls' footprints.
void paint_packed_and_mud(Terrain& t) {
  Material packed = Material::sand();
  packed.name = "packed";
  packed.bekker_kphi *= 4.0;
  t.set_palette({Material::sand(), packed, Material::mud()});
  t.paint_rect({0, -20, 20, 40}, 1);
  t.paint_rect({-20, 0, 20, 20}, 2);
}

/// Packed sand and mud painted over sand (paint_packed_and_mud), with a ball pressed in off
/// centre: a rut with sinkage the plates then meet.
void rut_painted_ground(Terrain& t) {
  paint_packed_and_mud(t);
  const shore::EnvelopeRaster ball = sphere_envelope(t, 0.05, 0.03, 0.15, 0.12);
  const Imprint im{&ball};
  t.step({&im, 1});
}

}  // namespace

TEST(BearingSolve, FreshPlateSinksAsBekkerForBothLoads) {
  TerrainSettings s;
  s.material = Material::sand();
  const Terrain t(s);
  const shore::EnvelopeRaster env = box_envelope(-15, -15, kPlate, kPlate, 0.0);
  BearingSolve solve;
  solve.reset(t, env);
  for (const double p : {20e3, 50e3}) {  // Pa: the second load re-uses the first's bracket
    const double o = solve.offset(p * 0.09);
    EXPECT_NEAR(o, bekker::plate_sinkage(s.material, 0.3, p), 2e-7) << p << " Pa";
    EXPECT_GE(solve.bearing(o).capacity, p * 0.09);
  }
  expect_like_terrain(t, env, {20e3 * 0.09, 50e3 * 0.09, 10e3 * 0.09});
}

TEST(BearingSolve, RuttedPaintedGroundMatchesTerrainBitForBit) {
  Terrain t(one_thread_sand());
  rut_painted_ground(t);
  {  // the plate sinks (the solve brackets and narrows) for the larger loads
    BearingSolve solve;
    solve.reset(t, box_envelope(-15, -15, kPlate, kPlate, 0.0));
    EXPECT_GT(solve.offset(3000.0), 1e-3);
  }
  for (const double bottom : {0.0, -0.01, -0.04}) {
    const shore::EnvelopeRaster env = box_envelope(-15, -15, kPlate, kPlate, bottom);
    expect_like_terrain(t, env, {200.0, 3000.0, 1500.0, 3000.0, 0.0});
  }
  // A body that covers no column: offset 0 and an empty bearing, as the terrain's.
  shore::EnvelopeRaster none;
  none.resize(0, 0, 4, 4, false);
  expect_like_terrain(t, none, {100.0});
}

TEST(BearingSolve, BadUseIsRefusedByName) {
  const Terrain t(TerrainSettings{});
  BearingSolve solve;
  EXPECT_THROW((void)solve.offset(1.0), shore::InvalidSetting);  // before any reset
  shore::EnvelopeRaster bad = box_envelope(0, 0, 4, 4, 0.0);
  bad.lower.pop_back();
  EXPECT_THROW(solve.reset(t, bad), shore::InvalidSetting);
  solve.reset(t, box_envelope(0, 0, 4, 4, 0.0));
  try {
    (void)solve.offset(-1.0);
    FAIL() << "a negative load was taken";
  } catch (const shore::InvalidSetting& e) {
    EXPECT_NE(std::string(e.what()).find("load"), std::string::npos) << e.what();
  }
  const double o = solve.offset(50.0);
  EXPECT_THROW((void)solve.bearing(o + 1e-3), shore::InvalidSetting);  // never measured
  try {
    (void)solve.offset_under_spring(50.0, -1.0);
    FAIL() << "a negative spring was taken";
  } catch (const shore::InvalidSetting& e) {
    EXPECT_NE(std::string(e.what()).find("spring"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)BearingSolve{}.offset_under_spring(1.0, 1.0), shore::InvalidSetting);  // before any reset
}

// measure(offset) at an offset no solve reached (a raycast wheel stopped short of its
// solve's answer by its ray) gives exactly what Terrain::bearing gives there, on rutted,
// painted ground, before any solve and between solves; and a bad offset is refused by name.
TEST(BearingSolve, MeasureAtAnyOffsetMatchesTerrainBitForBit) {
  Terrain t(one_thread_sand());
  rut_painted_ground(t);
  const shore::EnvelopeRaster env = box_envelope(-15, -15, kPlate, kPlate, -0.01);
  BearingSolve solve;
  solve.reset(t, env);
  expect_same(solve.measure(0.0021), t.bearing(env, 0.0021));  // before any solve
  const double o = solve.offset(3000.0);
  for (const double at : {0.5 * o, o, 1.5 * o, 0.0}) expect_same(solve.measure(at), t.bearing(env, at));
  EXPECT_EQ(solve.offset(3000.0), o) << "a solve after measuring answers as before";
  for (const double bad : {-1e-3, std::numeric_limits<double>::infinity(), std::nan("")}) {
    try {
      (void)solve.measure(bad);
      FAIL() << "offset " << bad << " was taken";
    } catch (const shore::InvalidSetting& e) {
      EXPECT_NE(std::string(e.what()).find("offset"), std::string::npos) << e.what();
    }
  }
}

// A plate on a spring that gives `load` untouched and k N less per metre it sinks: Bekker's
// plate pressure (k_c/b + k_phi) z^n times its area meets load - k z at the offset found,
// z = plate_sinkage((load - k z) / A) to the solve's tolerance. With k = 0 it is the plain
// solve's answer, bit for bit.
TEST(BearingSolve, UnderASpringAPlateSinksWhereBekkersPressureMeetsTheSpring) {
  TerrainSettings s;
  s.material = Material::sand();
  const Terrain t(s);
  const shore::EnvelopeRaster env = box_envelope(-15, -15, kPlate, kPlate, 0.0);
  const double area = 0.09, load = 50e3 * area;  // m^2, N
  for (const double k : {1e5, 1e6}) {            // N/m: the spring takes 10 to 60 % of the load off
    BearingSolve solve;
    solve.reset(t, env);
    const double z = solve.offset_under_spring(load, k);
    const double pressure = (load - k * z) / area;
    EXPECT_LT(pressure, 0.9 * 50e3) << k;  // the spring's relief is not lost in the tolerance
    EXPECT_NEAR(z, bekker::plate_sinkage(s.material, 0.3, pressure), 3e-7) << k;
    EXPECT_GE(solve.bearing(z).capacity, load - k * z) << k;  // the end that carries
  }
  BearingSolve solve;
  solve.reset(t, env);
  EXPECT_EQ(solve.offset_under_spring(load, 0.0), t.bearing_offset(env, load));
}

// A raised raycast wheel's equilibrium, once searched on the load (each load's offset a
// plain solve, the load L where L = F + k (D - o(L)), to 1e-3 N) and now on the offset: a
// ball raised D above where it had pressed into rutted sand, packed sand and mud, the same
// offset to the plain solve's tolerance.
TEST(BearingSolve, UnderASpringABallSinksWhereTheNestedSearchOnTheLoadDoes) {
  Terrain t(one_thread_sand());
  paint_packed_and_mud(t);
  const shore::EnvelopeRaster rut = box_envelope(-10, -10, 12, 12, -0.004);
  const Imprint im{&rut};
  t.step({&im, 1});
  const double r = 0.15, bound = 0.01;  // m: the ball pressed 2 cm in, raised 1 cm
  const shore::EnvelopeRaster raised = sphere_envelope(t, 0.02, 0.01, r - 0.02 + bound, r);
  const double at_hit = t.bearing(raised, bound).capacity;
  ASSERT_GT(at_hit, 100.0);
  for (const double k : {2e4, 2e5}) {  // N/m: a car's suspension and a stiff one
    const double force = 0.5 * at_hit;
    BearingSolve nested;
    nested.reset(t, raised);
    const auto phi = [&](double load) { return load - force - k * (bound - nested.offset(load)); };
    const double f_lo = phi(force), f_hi = phi(force + k * bound);
    ASSERT_LT(f_lo, 0.0);
    ASSERT_GE(f_hi, 0.0);
    const shore::Bracket b = shore::illinois_narrow(phi, {force, force + k * bound}, f_lo, f_hi, 1e-3);
    const double expected = nested.offset(b.hi);
    BearingSolve solve;
    solve.reset(t, raised);
    const double o = solve.offset_under_spring(force + k * bound, k);
    EXPECT_GT(o, 0.0) << k;
    EXPECT_LT(o, bound) << k;  // it rises
    EXPECT_NEAR(o, expected, 2e-7) << k;
    EXPECT_GE(solve.bearing(o).capacity, force + k * (bound - o)) << k;
  }
}

// The caller's capacity (a share of each column's force, as a slipping wheel's loosened
// soil): a plate whose columns bear half their Bekker force sinks as Bekker's plate under
// twice the pressure, and its offset is the plain solve's for twice the load.
TEST(BearingSolve, ColumnsBearingHalfSinkAsUnderTwiceTheLoad) {
  TerrainSettings s;
  s.material = Material::sand();
  const Terrain t(s);
  const shore::EnvelopeRaster env = box_envelope(-15, -15, kPlate, kPlate, 0.0);
  BearingSolve solve;
  solve.reset(t, env);
  const auto half = [](const Bearing& b) {
    double sum = 0.0;
    for (const ColumnForce& c : b.columns) sum += 0.5 * c.force;
    return sum;
  };
  const double p = 20e3;  // Pa
  const double o = solve.offset(p * 0.09, half);
  EXPECT_NEAR(o, bekker::plate_sinkage(s.material, 0.3, 2 * p), 2e-7);
  EXPECT_GE(half(solve.bearing(o)), p * 0.09);
  EXPECT_EQ(o, t.bearing_offset(env, 2 * p * 0.09));
}

// After a plain solve, the caller's capacity brackets from the offsets that solve measured:
// its answer carries the load and lies within the solve's tolerance (1e-7 m) above the
// offset where the plain capacity carries load / share, whether that is a hair deeper than
// the plain answer (share 0.999) or far deeper (share 0.5: Bekker's plate under twice the
// pressure).
TEST(BearingSolve, ACapacityAfterThePlainSolveBracketsFromItsOffsets) {
  TerrainSettings s;
  s.material = Material::sand();
  const Terrain t(s);
  const shore::EnvelopeRaster env = box_envelope(-15, -15, kPlate, kPlate, 0.0);
  const double p = 20e3, load = p * 0.09;  // Pa, N
  for (const double share : {0.999, 0.5}) {
    BearingSolve solve;
    solve.reset(t, env);
    const double plain = solve.offset(load);
    const auto part = [share](const Bearing& b) {
      double sum = 0.0;
      for (const ColumnForce& c : b.columns) sum += share * c.force;
      return sum;
    };
    const double o = solve.offset(load, part);
    EXPECT_GE(part(solve.bearing(o)), load) << share;
    const double cold = t.bearing_offset(env, load / share);  // the root to 1e-7 from above
    EXPECT_GT(o, plain) << share;
    EXPECT_NEAR(o, cold, 1e-7) << share;
    EXPECT_NEAR(o, bekker::plate_sinkage(s.material, 0.3, p / share), 2e-7) << share;
  }
}
