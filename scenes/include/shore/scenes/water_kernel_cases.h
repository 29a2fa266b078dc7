#pragma once
// Water kernel cases: node-steps per second of the surface kernels, and the machine's
// memory floor measured beside them. Shared by shore_water_bench and shore-bench.
//
// Bytes counted per node-step (the floor: state read once and written once per step):
//   fast 3-D:        in-plane u and v (4 floats) and vertical u_z, v_z (2 fixed-point
//                    doubles) read and written, 1 flag byte read                     = 65 B
//   vertical-only:   u_z and v_z (2 doubles) read and written, 1 flag byte read      = 33 B
//   reference 3-D:   u (3 floats) and v (3 floats), 1 flag: 49 B (its AoS node is 40 B
//                    with a force scratch); reference vertical-only: 17 B
// The floor is a STREAM-style triad a[i] = b[i] + s * c[i] over float arrays far larger
// than the caches, counted as 12 bytes per element (2 reads and 1 write, as STREAM does).

#include <cstddef>
#include <string>
#include <vector>

#include "shore/water/surface_settings.h"

namespace shore::scenes {

enum class KernelVariant {
  fast_3d,             ///< Surface, SurfaceMode::full_3d (guard included)
  reference_3d,        ///< ReferenceSurface, full 3-D (plain loops, no guard)
  vertical_only,       ///< Surface, SurfaceMode::vertical_only
  reference_vertical,  ///< ReferenceSurface, vertical-only
};
const char* kernel_variant_name(KernelVariant v);
/// The surface of the cases: n x n nodes of the seed paper's lattice, the variant's mode.
water::SurfaceSettings kernel_case_settings(KernelVariant v, int n, int threads);
double bytes_per_node_step(KernelVariant v);

struct KernelThroughput {
  KernelVariant variant = KernelVariant::fast_3d;
  int n = 0;  ///< grid is n x n nodes
  int threads = 1;
  long steps = 0;  ///< steps timed
  double seconds_per_step = 0.0;
  double node_steps_per_second = 0.0;
  int substeps = 1;  ///< substeps per step taken by the guard (fast variants)
};

/// A surface of n x n nodes (paper lattice, fixed edges, a disturbance in the middle) stepped
/// at dt = 0.3 (one substep for every variant) for at least min_seconds after two untimed
/// steps. tile > 0: the fast variants' tiles of tile x tile nodes instead of the default
/// (water::SleepSettings::tile). Sleeping is off in these cases, so the tile is only the unit
/// of work: the results are the same bits for any tile side, and the difference in time is
/// the kernel's fixed cost per tile and per tile row.
KernelThroughput measure_kernel_throughput(KernelVariant v, int n, int threads, double min_seconds = 0.3, int tile = 0);

/// STREAM-style triad bandwidth in bytes per second over arrays of `floats` floats each.
double triad_bandwidth(std::size_t floats, int threads, double min_seconds = 0.3);

/// Node-steps per second the memory floor allows: bandwidth / bytes_per_node_step.
double floor_node_steps_per_second(KernelVariant v, double bandwidth);

/// Time per step of the seed paper's 50 x 50 grid at its dt = 0.4 (fast 3-D kernel, guard
/// included), seconds. The paper reports 4.8 ms on a 300 MHz Pentium II.
double paper_grid_seconds_per_step(int threads, double min_seconds = 0.3);

struct KernelReport {
  std::vector<KernelThroughput> rows;
  std::vector<double> bandwidth;  ///< bytes/s, indexed by threads - 1
  double paper_grid_ms = 0.0;
  std::string isa;  ///< "avx2" or "generic"
};
/// every (variant, size, threads) of the benchmark's table; sizes default to 64, 256, 1024, 2048.
KernelReport run_kernel_report(const std::vector<int>& sizes, const std::vector<int>& threads, double min_seconds);
/// A plain text table of a report with speed-ups and floor ratios.
std::string format_kernel_report(const KernelReport& r);

}  // namespace shore::scenes
