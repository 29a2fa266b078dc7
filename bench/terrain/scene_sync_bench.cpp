// shore_scene_sync_bench: soil deltas of a coupled scene at a 20 Hz sync (the
// benchmark for the vehicle and footprints scenes; scenes/soil_sync.h). Prints JSON: delta
// bytes per second against SynChrono's format on the same changed columns (16 B per node:
// int32 x, y and a double height, uncompressed), encode and decode time per sync, and the
// replica's largest height and sinkage error over the scene's soil after the run. Exits
// non-zero if the replica strays beyond the quantum (exact mode: any difference).
//   build/release/bench/terrain/shore_scene_sync_bench [--scene vehicle] [--seconds 10] [--quantum 1e-4]
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>

#include "shore/scenes/soil_sync.h"

int main(int argc, char** argv) {
  std::string name = "vehicle";
  double seconds = 10.0;
  shore::terrain::DeltaSettings ds;
  for (int k = 1; k + 1 < argc; k += 2) {
    if (std::strcmp(argv[k], "--scene") == 0) name = argv[k + 1];
    if (std::strcmp(argv[k], "--seconds") == 0) seconds = std::stod(argv[k + 1]);
    if (std::strcmp(argv[k], "--quantum") == 0) ds.quantum = std::stod(argv[k + 1]);
  }
  const shore::scenes::SyncResult r = shore::scenes::sync_scene(name, seconds, ds);
  const double columns = std::max(r.changed_columns, 1.0);
  const int syncs = std::max(r.syncs, 1);
  std::printf("{\n  \"case\": \"%s scene, %.1f s, %d soils, 20 Hz sync, quantum %g m\",\n", name.c_str(), r.sim_seconds,
              r.soils, ds.quantum);
  std::printf("  \"sync.%s_delta_bytes_per_s\": %.1f,\n", name.c_str(), r.delta_bytes / r.sim_seconds);
  std::printf("  \"sync.synchrono_bytes_per_s\": %.1f,\n", 16.0 * r.changed_columns / r.sim_seconds);
  std::printf("  \"sync.delta_bytes_ratio_vs_synchrono\": %.4f,\n", r.delta_bytes / (16.0 * columns));
  std::printf("  \"sync.delta_bytes_per_changed_column\": %.3f,\n", r.delta_bytes / columns);
  std::printf("  \"sync.encode_ms_per_sync\": %.4f,\n  \"sync.decode_ms_per_sync\": %.4f,\n",
              1e3 * r.encode_seconds / syncs, 1e3 * r.decode_seconds / syncs);
  std::printf("  \"sync.replica_max_error_m\": %.3g,\n", r.max_error);
  // Exact deltas carry the spray too: the replica's whole soil state hash must match.
  std::printf("  \"sync.replica_same_soil_hash\": %s\n}\n", r.same_soil_hash ? "true" : "false");
  const bool exact_ok = ds.quantum != 0.0 || r.same_soil_hash;
  return r.max_error <= ds.quantum && exact_ok ? 0 : 1;
}
