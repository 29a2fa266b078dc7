// A replica soil driven only by deltas matches the server after 10 s of the
// vehicle scene: exactly in exact mode (heights and sinkages, and the soil's whole state
// hash: exact deltas carry the bookkeeping and the spray too), within the quantum when
// quantized. The server's own soil is the reference.
#include <gtest/gtest.h>

#include "shore/scenes/soil_sync.h"

namespace {

TEST(SoilSync, VehicleReplicaMatchesTheServerAfterTenSeconds) {
  shore::terrain::DeltaSettings exact;
  exact.quantum = 0.0;
  const shore::scenes::SyncResult e = shore::scenes::sync_scene("vehicle", 10.0, exact);
  ASSERT_GT(e.changed_columns, 1000.0) << "the vehicle changed almost no soil: this tests nothing";
  EXPECT_EQ(e.max_error, 0.0);
  EXPECT_TRUE(e.same_soil_hash) << "exact mode: the replica's Terrain::state_hash differs from the server's";
  shore::terrain::DeltaSettings quantized;  // 0.1 mm
  const shore::scenes::SyncResult q = shore::scenes::sync_scene("vehicle", 10.0, quantized);
  EXPECT_LE(q.max_error, quantized.quantum);
  EXPECT_GT(q.max_error, 0.0) << "quantized heights came out exact: the quantum is not applied";
  EXPECT_FALSE(q.same_soil_hash) << "a quantized replica cannot hold the server's exact state";
  // The size target: at most 1/8 of SynChrono's 16 B per changed column.
  EXPECT_LE(q.delta_bytes / (16.0 * q.changed_columns), 0.125);
}

}  // namespace
