#pragma once
// A scene's soils sent to replicas by deltas: the scene runs as shore-demo runs
// it; every 1/20 s each soil's changes since its last sync are encoded
// (terrain::SoilDelta::encode) and applied to a replica soil that only ever sees deltas.
// Used by shore_scene_sync_bench and the replica tests.

#include <string>
#include <vector>

#include "shore/terrain/soil_delta.h"

namespace shore::scenes {

struct SyncResult {
  double sim_seconds = 0.0;
  int soils = 0, syncs = 0;
  double delta_bytes = 0.0;      ///< all deltas sent
  double changed_columns = 0.0;  ///< columns in them (what SynChrono's format would send, 16 B each)
  double encode_seconds = 0.0, decode_seconds = 0.0;
  /// m, the replica's largest |height| or |sinkage| difference from the server over the
  /// scene's bounds after the run.
  double max_error = 0.0;
  /// Every replica's Terrain::state_hash equals its server's after the run (expected in
  /// exact mode, where deltas carry the spray and bookkeeping too; not when quantised).
  bool same_soil_hash = false;
};

/// Runs `scene` (one thread, no files) for `seconds` with 20 Hz soil deltas of `settings`.
/// InvalidSetting for an unknown scene or one without soils.
SyncResult sync_scene(const std::string& scene, double seconds, const terrain::DeltaSettings& settings);

}  // namespace shore::scenes
