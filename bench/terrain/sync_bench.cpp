// shore_sync_bench: soil deltas and checkpoints on a 100 m track (the benchmark of the
// terrain part). A wheel-sized sphere ploughs a rut 3 cm deep along x at 2 m/s, 100 steps
// per second, synced at 20 Hz. Prints JSON: delta bytes per second and per changed
// column against SynChrono's 16 B per node (absolute, uncompressed), encode and decode time
// per sync, and the terrain checkpoint's size and save / load time.
//   build/release/bench/terrain/shore_sync_bench [--quantum 1e-4] [--length 100]
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>

#include "shore/core/checkpoint_file.h"
#include "shore/core/envelope.h"
#include "shore/terrain/soil_delta.h"
#include "shore/terrain/terrain.h"

namespace {

using namespace shore::terrain;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

TerrainSettings track() {
  TerrainSettings s;
  s.cell = 0.02;
  s.tile_columns = 64;
  s.threads = 1;
  return s;
}

shore::EnvelopeRaster sphere(const Terrain& t, double cx, double cy, double cz, double r) {
  shore::EnvelopeRaster env;
  const std::int64_t i0 = t.column_i(cx - r) - 1, j0 = t.column_j(cy - r) - 1;
  const int n = static_cast<int>(2 * r / t.settings().cell) + 3;
  env.resize(i0, j0, n, n, false);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double dx = t.column_x(i0 + x) - cx, dy = t.column_y(j0 + y) - cy, rr = dx * dx + dy * dy;
      if (rr < r * r) env.lower[env.index(i0 + x, j0 + y)] = cz - std::sqrt(r * r - rr);
    }
  return env;
}

struct Totals {
  double delta_bytes = 0, columns = 0, encode_s = 0, decode_s = 0, max_error = 0;
  int syncs = 0;
};

}  // namespace

int main(int argc, char** argv) {
  DeltaSettings ds;
  double length = 100.0;
  for (int k = 1; k + 1 < argc; k += 2) {
    if (std::strcmp(argv[k], "--quantum") == 0) ds.quantum = std::stod(argv[k + 1]);
    if (std::strcmp(argv[k], "--length") == 0) length = std::stod(argv[k + 1]);
  }
  constexpr double kSpeed = 2.0, kStep = 0.01, kRadius = 0.35;
  const int steps = static_cast<int>(length / kSpeed / kStep);
  Terrain server(track()), replica(track());
  std::uint64_t sent = server.generation(), mirrored = sent;
  Totals t;
  for (int k = 0; k < steps; ++k) {
    const shore::EnvelopeRaster env = sphere(server, 0.5 + kSpeed * kStep * k, 0.0, kRadius - 0.03, kRadius);
    Imprint imprint;
    imprint.envelope = &env;
    imprint.velocity.x = kSpeed;
    server.step(std::span<const Imprint>(&imprint, 1));
    if (k % 5 != 4) continue;
    DeltaStats st;
    auto start = Clock::now();
    const auto delta = SoilDelta::encode(server, sent, ds, &st);
    t.encode_s += seconds_since(start);
    sent = server.generation();
    start = Clock::now();
    mirrored = SoilDelta::apply(replica, delta, mirrored);
    t.decode_s += seconds_since(start);
    t.delta_bytes += static_cast<double>(st.bytes), t.columns += static_cast<double>(st.columns), ++t.syncs;
  }
  for (std::int64_t i = -5; i < static_cast<std::int64_t>((length + 1.5) / 0.02); ++i)
    for (std::int64_t j = -25; j <= 25; ++j)
      t.max_error = std::max(t.max_error, std::fabs(server.height(i, j) - replica.height(i, j)));
  const auto file = std::filesystem::temp_directory_path() / "shore_sync_bench.ckp";
  auto start = Clock::now();
  shore::CheckpointWriter w;
  w.add("TERRAIN", server.save_bytes());
  w.save(file);
  const double save_s = seconds_since(start);
  start = Clock::now();
  const shore::CheckpointReader r = shore::CheckpointReader::open(file);
  const Terrain loaded = Terrain::load_bytes(r.section("TERRAIN"), r.describe("TERRAIN"));
  const double load_s = seconds_since(start);
  const auto size = std::filesystem::file_size(file);
  std::filesystem::remove(file);
  const double seconds = steps * kStep;
  std::printf("{\n  \"case\": \"sphere r %.2f m ploughing %.0f m at %.1f m/s, 20 Hz sync, quantum %g m\",\n", kRadius,
              length, kSpeed, ds.quantum);
  std::printf("  \"sync.track_delta_bytes_per_s\": %.1f,\n", t.delta_bytes / seconds);
  std::printf("  \"sync.delta_bytes_per_changed_column\": %.3f,\n", t.delta_bytes / t.columns);
  std::printf("  \"sync.delta_bytes_ratio_vs_synchrono\": %.4f,\n", t.delta_bytes / (16.0 * t.columns));
  std::printf("  \"sync.synchrono_bytes_per_s\": %.1f,\n", 16.0 * t.columns / seconds);
  std::printf("  \"sync.encode_ms_per_sync\": %.4f,\n  \"sync.decode_ms_per_sync\": %.4f,\n",
              1e3 * t.encode_s / t.syncs, 1e3 * t.decode_s / t.syncs);
  std::printf("  \"sync.replica_max_height_error_m\": %.3g,\n", t.max_error);
  std::printf("  \"checkpoint.track_bytes\": %ju,\n  \"checkpoint.track_tiles\": %zu,\n", static_cast<uintmax_t>(size),
              server.tile_count());
  std::printf("  \"checkpoint.save_ms\": %.2f,\n  \"checkpoint.load_ms\": %.2f,\n", 1e3 * save_s, 1e3 * load_s);
  std::printf("  \"checkpoint.identical\": %s\n}\n", loaded.state_hash() == server.state_hash() ? "true" : "false");
  return loaded.state_hash() == server.state_hash() && t.max_error <= ds.quantum ? 0 : 1;
}
