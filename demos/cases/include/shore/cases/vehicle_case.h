#pragma once
// A four-wheel vehicle (chassis + four cylinder wheels on motorised hinges) driving from
// rigid ground across sand, then mud, then rigid ground again. Each soil is its own
// Terrain in its own region (x in [0, sand_length) sand, then mud_length of mud).

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "shore/cases/soil_cases.h"
#include "shore/terrain/terrain.h"

class btRigidBody;

namespace shore::cases {

struct VehicleCase {
  double cell = 0.02;          ///< m, soil column spacing
  double substep = 1.0 / 240;  ///< s
  int threads = 1;
  double seconds = 6.0;       ///< s simulated
  double target_speed = 2.0;  ///< m/s the wheel motors aim for
  double start_x = -2.0;      ///< m, chassis centre at the start (rigid ground)
  int sand_tiles = 3;         ///< length of the sand strip in tiles of 64 cells
  int mud_tiles = 3;          ///< length of the mud strip in tiles
};

struct VehicleResult {
  double sim_seconds = 0.0;
  double distance = 0.0;               ///< m travelled by the chassis
  double mean_speed_sand = 0.0;        ///< m/s over the sand strip
  double mean_speed_mud = 0.0;         ///< m/s over the mud strip
  double max_sinkage = 0.0;            ///< m, deepest soil sinkage left behind
  std::int64_t fallthrough_count = 0;  ///< wheels that ended below bedrock or were rescued
  int nan_count = 0;
  RunStats stats;
  std::vector<std::shared_ptr<terrain::Terrain>> soils;  ///< sand, mud (for pictures)
  double sand_x0 = 0.0, sand_x1 = 0.0, mud_x1 = 0.0;     ///< strip edges, m
  [[nodiscard]] double realtime_factor() const {
    return stats.wall_seconds > 0 ? sim_seconds / stats.wall_seconds : 0.0;
  }
};

/// The world after one substep, for callers that draw or record the run.
struct VehicleFrame {
  std::int64_t substep = 0;   ///< substeps done so far (1 after the first)
  std::int64_t substeps = 0;  ///< substeps of the whole run
  double time = 0.0;          ///< s simulated so far
  const btRigidBody* chassis = nullptr;
  std::array<const btRigidBody*, 4> wheels{};
  const std::vector<std::shared_ptr<terrain::Terrain>>* soils = nullptr;  ///< sand, mud
};
/// Called after every substep; it must not change the bodies or the soils.
using VehicleFrameCallback = std::function<void(const VehicleFrame&)>;

/// Runs the case; on_substep (optional) sees the world after every substep.
VehicleResult run_vehicle(const VehicleCase& c, const VehicleFrameCallback& on_substep = {});

}  // namespace shore::cases
