// The fast kernel against the plain reference kernel, and bit-identical results for any
// thread count.

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <string>

#include "shore/core/error.h"
#include "shore/water/reference_surface.h"
#include "shore/water/surface.h"

using namespace shore::water;

namespace {

SurfaceSettings mixed_settings(SurfaceMode mode) {
  SurfaceSettings s = SurfaceSettings::paper();  // 50 x 50, h 1, m 4, c 7, gamma 0.05
  s.nx = 53;                                     // not a multiple of the vector width
  s.ny = 47;
  s.mode = mode;
  s.boundary = Boundary::vertical_only;
  s.threads = 1;
  return s;
}

template <class S>
void add_island_and_drops(S& surf) {
  for (int j = 20; j < 24; ++j)
    for (int i = 30; i < 33; ++i) surf.set_constraint(i, j, NodeConstraint::fixed);
  surf.set_constraint(10, 10, NodeConstraint::vertical_only);
  surf.disturb(Disturbance::point_height(15.0, 20.0, 2.0, 1.0));
  surf.disturb(Disturbance::point_velocity(35.5, 30.0, 1.5, 0.5));
  surf.disturb(Disturbance::area_height(25.0, 10.0, 5.0, 3.0, 1.0, -0.3));
}

class FastAgainstReference : public ::testing::TestWithParam<SurfaceMode> {};

TEST_P(FastAgainstReference, AgreeAfter1000Steps) {
  const SurfaceSettings s = mixed_settings(GetParam());
  Surface fast(s);
  ReferenceSurface ref(s);
  add_island_and_drops(fast);
  add_island_and_drops(ref);
  // dt = 0.3: below the guard's largest possible need for substeps (12 c / m gives
  // w dt = 1.37 < 1.8), so both take exactly the same single step.
  const double dt = 0.3;
  for (int k = 0; k < 1000; ++k) {
    ASSERT_EQ(fast.step(dt).substeps, 1);
    ref.step(dt);
  }
  const DenseState v = fast.dense_state();
  const bool full = GetParam() == SurfaceMode::full_3d;
  double diff_u = 0.0, scale_u = 0.0, diff_v = 0.0, scale_v = 0.0, diff_p = 0.0, scale_p = 0.0;
  for (int j = 0; j < s.ny; ++j) {
    for (int i = 0; i < s.nx; ++i) {
      const auto k = static_cast<std::size_t>(j * s.nx + i);
      const ReferenceSurface::Node& n = ref.node(i, j);
      const double rest[3] = {s.origin_x + i * s.lattice.spacing, s.origin_y + j * s.lattice.spacing, s.rest_height};
      for (int c = 0; c < 3; ++c) {
        const bool moves = full || c == 2;
        const double u = !moves ? 0.0 : c == 0 ? v.ux[k] : c == 1 ? v.uy[k] : v.uz[k];
        const double w = !moves ? 0.0 : c == 0 ? v.vx[k] : c == 1 ? v.vy[k] : v.vz[k];
        diff_u = std::max(diff_u, std::abs(u - n.u[c]));
        diff_v = std::max(diff_v, std::abs(w - n.v[c]));
        scale_u = std::max(scale_u, std::abs(static_cast<double>(n.u[c])));
        scale_v = std::max(scale_v, std::abs(static_cast<double>(n.v[c])));
        diff_p = std::max(diff_p, std::abs((rest[c] + u) - (rest[c] + n.u[c])));
        scale_p = std::max(scale_p, std::abs(rest[c] + n.u[c]));
      }
    }
  }
  ASSERT_GT(scale_u, 1e-3);
  // World positions to 1e-6 relative.
  EXPECT_LT(diff_p, 1e-6 * scale_p);
  // Stronger, against the size of the motion itself. Both kernels round in float but sum
  // in different orders (the fast one spring by spring along rows); each step's
  // spring force carries ~1e-7 relative rounding, amplified 1 / (1 - rest_ratio) = 10x in
  // the tension c (1 - L0 / l) of the 3-D springs, and 1000 steps accumulate it. Linear
  // vertical-only motion keeps the differences near float resolution.
  const double tol_u = full ? 1e-4 : 1e-5, tol_v = full ? 1e-3 : 1e-5;
  EXPECT_LT(diff_u, tol_u * scale_u) << "displacement scale " << scale_u;
  EXPECT_LT(diff_v, tol_v * scale_v) << "velocity scale " << scale_v;
  RecordProperty("relative_difference_position", std::to_string(diff_p / scale_p));
  RecordProperty("relative_difference_u", std::to_string(diff_u / scale_u));
  RecordProperty("relative_difference_v", std::to_string(diff_v / scale_v));
}

INSTANTIATE_TEST_SUITE_P(Modes, FastAgainstReference,
                         ::testing::Values(SurfaceMode::vertical_only, SurfaceMode::full_3d),
                         [](const ::testing::TestParamInfo<SurfaceMode>& c) {
                           return std::string(c.param == SurfaceMode::full_3d ? "Full3d" : "VerticalOnly");
                         });

class ThreadCount : public ::testing::TestWithParam<SurfaceMode> {};

TEST_P(ThreadCount, StateHashIsTheSameFor1To4Threads) {
  std::uint64_t hashes[3] = {};
  const int threads[3] = {1, 2, 4};
  for (int t = 0; t < 3; ++t) {
    SurfaceSettings s = mixed_settings(GetParam());
    s.threads = threads[t];
    s.parallel_min_nodes = 0;  // fork every substep, however small the grid
    s.sleep.tile = 16;
    Surface surf(s);
    add_island_and_drops(surf);
    surf.disturb(Disturbance::point_height(26.0, 23.0, 2.0, 20.0));  // violent: substeps too
    int substeps = 0;
    for (int k = 0; k < 60; ++k) substeps += surf.step(0.4).substeps;
    if (GetParam() == SurfaceMode::full_3d) {
      EXPECT_GT(substeps, 60);
    }
    hashes[t] = surf.state_hash();
  }
  EXPECT_EQ(hashes[0], hashes[1]);
  EXPECT_EQ(hashes[0], hashes[2]);
}

INSTANTIATE_TEST_SUITE_P(Modes, ThreadCount, ::testing::Values(SurfaceMode::vertical_only, SurfaceMode::full_3d),
                         [](const ::testing::TestParamInfo<SurfaceMode>& c) {
                           return std::string(c.param == SurfaceMode::full_3d ? "Full3d" : "VerticalOnly");
                         });

/// A vectorised kernel (AVX2 or AVX-512) and the generic one in one process: in the
/// cross-platform deterministic build (the default) they must give the same bits, so a
/// state pinned on one machine holds on every other, whichever kernel its CPU runs.
struct WideKernel {
  SurfaceMode mode;
  KernelChoice kernel;
  const char* isa;
};
class KernelVariants : public ::testing::TestWithParam<WideKernel> {};

TEST_P(KernelVariants, AgreeBitwiseWithGenericAfter1000ViolentSteps) {
  const WideKernel c = GetParam();
  if (!Surface::kernel_available(c.kernel)) GTEST_SKIP() << "no " << c.isa << " kernel in this build or on this CPU";
  SurfaceSettings s = mixed_settings(c.mode);
  s.kernel = c.kernel;
  Surface wide(s);
  s.kernel = KernelChoice::generic;
  Surface generic(s);
  EXPECT_STREQ(wide.kernel_isa(), c.isa);
  EXPECT_STREQ(generic.kernel_isa(), "generic");
  for (Surface* surf : {&wide, &generic}) {
    add_island_and_drops(*surf);
    surf->disturb(Disturbance::point_height(26.0, 23.0, 2.0, 20.0));  // violent: the guard substeps
    surf->disturb(Disturbance::point_velocity(12.0, 33.0, 1.0, 8.0));
  }
  int substeps = 0;
  for (int k = 0; k < 1000; ++k) {
    substeps += wide.step(0.4).substeps;
    generic.step(0.4);
  }
  if (c.mode == SurfaceMode::full_3d) {
    EXPECT_GT(substeps, 1000);  // the disturbance was violent enough to need substeps
  }
  const DenseState a = wide.dense_state(), g = generic.dense_state();
  std::size_t differing = 0;
  for (std::size_t k = 0; k < a.uz.size(); ++k)
    differing += std::bit_cast<std::uint64_t>(a.uz[k]) != std::bit_cast<std::uint64_t>(g.uz[k]);
#ifdef SHORE_CROSS_PLATFORM_DETERMINISTIC
  EXPECT_EQ(differing, 0u) << "nodes whose height differs in any bit";
  EXPECT_EQ(wide.state_hash(), generic.state_hash());
#else
  RecordProperty("differing_heights", std::to_string(differing));
  GTEST_SKIP() << differing << " heights differ: without SHORE_CROSS_PLATFORM_DETERMINISTIC the " << c.isa
               << " kernel may fuse multiply-adds";
#endif
}

// The same on a sleeping, tiled surface with an open edge: tiles fall asleep and wake
// during the run, and threads take tiles in any order.
TEST_P(KernelVariants, AgreeBitwiseWithGenericOnASleepingTiledSurface) {
  const WideKernel c = GetParam();
  if (!Surface::kernel_available(c.kernel)) GTEST_SKIP() << "no " << c.isa << " kernel in this build or on this CPU";
  SurfaceSettings s = mixed_settings(c.mode);
  s.nx = 101;
  s.ny = 93;
  s.boundary = Boundary::open;
  s.open.width = 10;
  s.sleep.tile = 16;
  s.sleep.height = 0.02;    // m, with h = 1 m and a 5 m bump: tiles the rings have left fall asleep
  s.lattice.damping = 0.5;  // amplitude e-folding time 16 s
  s.threads = 2;
  s.parallel_min_nodes = 0;
  s.kernel = c.kernel;
  Surface wide(s);
  s.kernel = KernelChoice::generic;
  s.threads = 1;
  Surface generic(s);
  for (Surface* surf : {&wide, &generic}) {
    add_island_and_drops(*surf);
    surf->disturb(Disturbance::point_height(70.0, 60.0, 2.0, 5.0));
  }
  std::int64_t slept = 0;
  for (int k = 0; k < 600; ++k) {
    wide.step(0.4);
    generic.step(0.4);
    slept = std::max<std::int64_t>(slept, wide.tile_stats().created - wide.tile_stats().awake);
    if (k == 300) {
      for (Surface* surf : {&wide, &generic}) surf->disturb(Disturbance::point_velocity(20.0, 70.0, 1.5, 0.5));
    }
  }
  EXPECT_GT(slept, 0) << "no tile slept: the case does not test sleeping";
#ifdef SHORE_CROSS_PLATFORM_DETERMINISTIC
  EXPECT_EQ(wide.state_hash(), generic.state_hash());
#else
  GTEST_SKIP() << "without SHORE_CROSS_PLATFORM_DETERMINISTIC the " << c.isa << " kernel may fuse multiply-adds";
#endif
}

INSTANTIATE_TEST_SUITE_P(Modes, KernelVariants,
                         ::testing::Values(WideKernel{SurfaceMode::vertical_only, KernelChoice::avx2, "avx2"},
                                           WideKernel{SurfaceMode::full_3d, KernelChoice::avx2, "avx2"},
                                           WideKernel{SurfaceMode::vertical_only, KernelChoice::avx512, "avx512"},
                                           WideKernel{SurfaceMode::full_3d, KernelChoice::avx512, "avx512"}),
                         [](const ::testing::TestParamInfo<WideKernel>& c) {
                           return std::string(c.param.kernel == KernelChoice::avx512 ? "Avx512" : "Avx2") +
                                  (c.param.mode == SurfaceMode::full_3d ? "Full3d" : "VerticalOnly");
                         });

// Threads never hurt: below parallel_min_nodes a step never wakes the team (a 53 x 47 grid
// at the default), above it (here forced) it does.
TEST(Threads, SmallGridsNeverForkTheTeam) {
  SurfaceSettings s = mixed_settings(SurfaceMode::vertical_only);
  s.threads = 2;
  Surface small(s);
  small.disturb(Disturbance::point_height(15.0, 20.0, 2.0, 1.0));
  EXPECT_EQ(small.step(0.3).parallel_substeps, 0);
  s.parallel_min_nodes = 0;
  Surface forced(s);
  forced.disturb(Disturbance::point_height(15.0, 20.0, 2.0, 1.0));
  EXPECT_EQ(forced.step(0.3).parallel_substeps, 1);
}

TEST(KernelChoice, WideKernelsAreRefusedWhereTheyCannotRun) {
  SurfaceSettings s = mixed_settings(SurfaceMode::full_3d);
  for (KernelChoice k : {KernelChoice::avx2, KernelChoice::avx512}) {
    s.kernel = k;
    if (Surface::kernel_available(k)) {
      EXPECT_NO_THROW(Surface{s});
    } else {
      try {
        Surface surf(s);
        FAIL() << "expected InvalidSetting";
      } catch (const shore::InvalidSetting& e) {
        EXPECT_NE(std::string(e.what()).find("water.SurfaceSettings.kernel"), std::string::npos) << e.what();
      }
    }
  }
  // automatic takes the widest variant this CPU runs
  s.kernel = KernelChoice::automatic;
  EXPECT_STREQ(Surface(s).kernel_isa(), Surface::fast_kernel_isa());
  s.kernel = static_cast<KernelChoice>(7);
  EXPECT_THROW(Surface{s}, shore::InvalidSetting);
}

}  // namespace
