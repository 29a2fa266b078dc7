// The vertical-only tile kernels one tile at a time (water/src/kernel.h, internal): every
// compiled variant of the fused kernel against the unfused reference on the same tile, its
// new state and everything it reports (the exact sums and each activity: the whole tile,
// each side, each corner). The surface-level tests see the activity only through which
// tiles sleep, where a lower or higher value rarely changes a decision; here any bit of it
// counts. Tiles with and without fixed nodes, with and without the open boundary's sponge,
// every side live, frozen or absent, even and odd row counts, and a spike (one node far from
// the others) at every node of the tile in turn, so that each spring in turn is the largest.

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "kernel.h"
#include "quantum.h"

namespace shore::water::kernel {
namespace {

constexpr int kStride = 16;

struct TileCase {
  int w = kStride, h = kStride;
  int stride = kStride;      // of the storage (the block's is stride + 2)
  bool fixed_nodes = false;  // a few fixed nodes (the masked passes)
  bool sponge = false;
  Side sides[kSides] = {};
};

/// One tile's inputs: its storage, its flags and sponge, the block with the ghost ring.
struct TileInputs {
  std::vector<double> uz, vz, block, sigma;
  std::vector<std::uint8_t> flags;
};

Coefficients coefficients() {
  const quantum::Quantum qu = quantum::Quantum::for_scale(0.05, quantum::kKeepBitsHeight);
  const quantum::Quantum qv = quantum::Quantum::for_scale(2.0, quantum::kKeepBitsVelocity);
  Coefficients k;
  k.kappa = 0.21;
  k.beta = 0.013;
  k.dt_z = 1.0 / 240;
  k.u_magic = qu.magic;
  k.u_inv = qu.inv;
  k.u_keep = qu.keep;
  k.v_magic = qv.magic;
  k.v_inv = qv.inv;
  k.v_keep = qv.keep;
  k.activity = true;
  k.u_scale = 1.0 / (1e-5 * 0.05);
  k.v_scale = 1.0 / 1e-4;
  return k;
}

/// Heights and velocities of a few hundred quanta, one node `spike` (row-major over the
/// tile and its ring) far higher, and the ring's values from the same field.
TileInputs inputs(const TileCase& c, int spike, std::mt19937& rng, const Coefficients& k) {
  const double qu = 1.0 / k.u_inv, qv = 1.0 / k.v_inv;
  std::uniform_int_distribution<int> small(-300, 300);
  const int stride = c.stride, bs = stride + 2;
  TileInputs in;
  in.uz.assign(stride * stride, 0.0);
  in.vz.assign(stride * stride, 0.0);
  in.flags.assign(stride * stride, 0);
  in.block.assign(static_cast<std::size_t>(bs) * bs, 0.0);
  for (int r = -1; r <= c.h; ++r)
    for (int i = -1; i <= c.w; ++i) {
      const bool at_spike = (r + 1) * (c.w + 2) + (i + 1) == spike;
      const double u = (at_spike ? 40000 : small(rng)) * qu;
      in.block[static_cast<std::size_t>((r + 1) * bs + i + 1)] = u;  // the unfused kernel reads the interior here
      if (r >= 0 && r < c.h && i >= 0 && i < c.w) {
        in.uz[static_cast<std::size_t>(r * stride + i)] = u;
        in.vz[static_cast<std::size_t>(r * stride + i)] = small(rng) * qv;
      }
    }
  if (c.fixed_nodes)
    for (const int n : {0, stride + 3, 5 * stride + 5, (c.h - 1) * stride + c.w - 1})
      if (n % stride < c.w && n / stride < c.h) in.flags[static_cast<std::size_t>(n)] = 2;
  if (c.sponge) {
    in.sigma.assign(stride * stride, 0.0);
    for (int n = 0; n < stride * stride; ++n) in.sigma[static_cast<std::size_t>(n)] = 0.25 * (n % 7);
  }
  return in;
}

struct Stepped {
  TileResult result;
  std::vector<double> uz, vz;
};

Stepped step(Variant v, const TileCase& c, TileInputs in, const Coefficients& k) {
  std::vector<unsigned char> scratch(workspace_bytes(c.stride) + 64);
  void* ws = reinterpret_cast<void*>((reinterpret_cast<std::uintptr_t>(scratch.data()) + 63) & ~std::uintptr_t{63});
  Tile t;
  t.w = c.w;
  t.h = c.h;
  t.stride = c.stride;
  t.block_stride = c.stride + 2;
  t.uz = in.uz.data();
  t.vz = in.vz.data();
  t.flags = in.flags.data();
  t.bz = in.block.data() + t.block_stride + 1;
  t.sponge = c.sponge ? in.sigma.data() : nullptr;
  for (int s = 0; s < kSides; ++s) t.sides[s] = c.sides[s];
  Stepped out;
  out.result = step_vertical(v, t, k, ws);
  out.uz = in.uz;
  out.vz = in.vz;
  return out;
}

void expect_same(const Stepped& a, const Stepped& b, const std::string& what) {
  EXPECT_TRUE(a.result.v_before == b.result.v_before) << what;
  EXPECT_TRUE(a.result.damped == b.result.damped) << what;
  EXPECT_TRUE(a.result.v_after == b.result.v_after) << what;
  EXPECT_TRUE(a.result.rise == b.result.rise) << what;
  EXPECT_EQ(a.result.activity, b.result.activity) << what;
  for (int s = 0; s < kSides; ++s)
    EXPECT_EQ(a.result.side_activity[s], b.result.side_activity[s]) << what << ", side " << s;
  EXPECT_EQ(a.uz, b.uz) << what;
  EXPECT_EQ(a.vz, b.vz) << what;
}

/// The fused variants this CPU runs, each compared with the unfused reference.
std::vector<Variant> fused_variants() {
  std::vector<Variant> fused{Variant::generic};
  if (avx2_available()) fused.push_back(Variant::avx2);
  if (avx512_available()) fused.push_back(Variant::avx512);
  return fused;
}

/// Steps one tile case by the unfused reference and by each fused variant and expects the
/// same bits; returns how many variants were compared. `note` ends the failure's label.
int compare_with_unfused(const std::vector<Variant>& fused, const TileCase& c, const TileInputs& in,
                         const Coefficients& k, const std::string& note) {
  const Stepped reference = step(Variant::unfused, c, in, k);
  for (const Variant v : fused)
    expect_same(step(v, c, in, k), reference,
                "variant " + std::to_string(static_cast<int>(v)) + ", " + std::to_string(c.w) + " x " +
                    std::to_string(c.h) + (c.fixed_nodes ? ", fixed nodes" : "") + (c.sponge ? ", sponge" : "") + note);
  return static_cast<int>(fused.size());
}

TEST(VerticalTileKernels, ReportTheUnfusedKernelsSumsAndActivityToTheBit) {
  const std::vector<Variant> fused = fused_variants();
  const Coefficients k = coefficients();
  std::mt19937 rng(7);
  int compared = 0;
  for (const int h : {16, 15, 2, 1})
    for (const int w : {16, 13, 1})
      for (const bool fixed_nodes : {false, true})
        for (const bool sponge : {false, true}) {
          TileCase c;
          c.w = w;
          c.h = h;
          c.fixed_nodes = fixed_nodes;
          c.sponge = sponge;
          for (int s = 0; s < kSides; ++s) c.sides[s] = static_cast<Side>((s + w + h) % 3);
          const int nodes = (w + 2) * (h + 2);
          for (int spike = 0; spike < nodes; ++spike) {
            compared += compare_with_unfused(fused, c, inputs(c, spike, rng, k), k, ", spike " + std::to_string(spike));
            if (::testing::Test::HasFailure()) return;  // one case's messages are enough
          }
        }
  EXPECT_GT(compared, 1000);
}

// The default tile (64 nodes a row, rows back to back) with no fixed node and no sponge and
// an even number of rows runs all its pairs in one call (pair_run in kernel_impl.inc), other
// tiles a call per pair: the same bits as the unfused reference either way, with the
// activity measured or not, and row counts where the run's loop covers most of the pairs or
// none (6 rows: the first pair and the last two only). A spike
// every 53 nodes, and at the corners of the tile and its ring.
TEST(VerticalTileKernels, RunTheDefaultTilesPairsToTheUnfusedKernelsBits) {
  const std::vector<Variant> fused = fused_variants();
  std::mt19937 rng(13);
  int compared = 0;
  for (const bool activity : {true, false})
    for (const int h : {64, 63, 8, 6, 5, 4})
      for (const int w : {64, 63})
        for (const bool fixed_nodes : {false, true})
          for (const bool sponge : {false, true}) {
            Coefficients k = coefficients();
            k.activity = activity;
            TileCase c;
            c.stride = 64;
            c.w = w;
            c.h = h;
            c.fixed_nodes = fixed_nodes;
            c.sponge = sponge;
            for (int s = 0; s < kSides; ++s) c.sides[s] = static_cast<Side>((s + h + fixed_nodes) % 3);
            const int nodes = (w + 2) * (h + 2);
            std::vector<int> spikes{0, w + 1, nodes - w - 2, nodes - 1, w + 3, nodes - w - 4};
            for (int spike = 17; spike < nodes; spike += 53) spikes.push_back(spike);
            for (const int spike : spikes) {
              compared += compare_with_unfused(
                  fused, c, inputs(c, spike, rng, k), k,
                  std::string(activity ? "" : ", no activity") + ", spike " + std::to_string(spike));
              if (::testing::Test::HasFailure()) return;  // one case's messages are enough
            }
          }
  EXPECT_GT(compared, 1000);
}

// The pair pass groups a node's impulse as its 3 x 3 box of K less (live neighbours + 1)
// times its own K, the unfused kernel as eight neighbours less the count times its own:
// equal only while every partial sum is exact. At a stable substep kappa is below
// omega / 6 and the height quantum below 2 / omega velocity quanta, so a height at its
// bound (2^50 height quanta) makes a K of at most 2^50 / 3 velocity quanta; the largest
// such K with neighbours of both signs must still give the reference's bits.
TEST(VerticalTileKernels, SumTheImpulsesExactlyAtTheStatesExtremes) {
  const std::vector<Variant> fused = fused_variants();
  Coefficients k = coefficients();
  k.kappa = (1.0 / 3.0) * (k.u_inv / k.v_inv);  // K = kappa u reaches 2^50 / 3 quanta at u = u_keep
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> sign(0, 1);
  std::uniform_int_distribution<int> slack(0, 1000);
  const double qu = 1.0 / k.u_inv;
  for (const int h : {16, 15})
    for (const int w : {16, 13}) {
      TileCase c;
      c.w = w;
      c.h = h;
      for (int s = 0; s < kSides; ++s) c.sides[s] = Side::live;
      TileInputs in = inputs(c, -1, rng, k);
      const int bs = kStride + 2;
      for (int r = -1; r <= h; ++r)
        for (int i = -1; i <= w; ++i) {
          const double u = (sign(rng) ? 1.0 : -1.0) * (k.u_keep - slack(rng) * qu);
          in.block[static_cast<std::size_t>((r + 1) * bs + i + 1)] = u;
          if (r >= 0 && r < h && i >= 0 && i < w) in.uz[static_cast<std::size_t>(r * kStride + i)] = u;
        }
      compare_with_unfused(fused, c, in, k, "");
    }
}

}  // namespace
}  // namespace shore::water::kernel
