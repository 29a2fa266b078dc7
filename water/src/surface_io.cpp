// The surface's state as bytes (Surface::save_state / restore_state):
//   u32 version; i32 nx, ny, tile side, full_3d; f64 time, last substep; u8 has
//   deformation, f64 max_tension, max_sin; i64 ever awake; u64 tile count; per created
//   tile (slot order): i32 tx, ty, cur, calm; u8 awake, ever_awake; arrays uz, vz, ux, uy,
//   vx, vy, flags; both edge snapshots' z, vz, x, y, vx, vy.
// The sponge is rebuilt from the settings; the pacer (which only picks a thread count) is
// not saved: results never depend on it.

#include <cmath>
#include <string>
#include <vector>

#include "quantum.h"
#include "shore/core/byte_io.h"
#include "shore/core/error.h"
#include "surface_state.h"

namespace shore::water {

namespace {

constexpr std::uint32_t kStateVersion = 1;

void put_tile(ByteWriter& w, const TileData& t) {
  w.put(static_cast<std::int32_t>(t.tx)), w.put(static_cast<std::int32_t>(t.ty));
  w.put(static_cast<std::int32_t>(t.cur)), w.put(static_cast<std::int32_t>(t.calm));
  w.put(static_cast<std::uint8_t>(t.awake)), w.put(static_cast<std::uint8_t>(t.ever_awake));
  w.put_array(t.uz), w.put_array(t.vz), w.put_array(t.ux), w.put_array(t.uy), w.put_array(t.vx), w.put_array(t.vy);
  w.put_array(t.flags);
  for (const TileData::Edges& e : t.edges)
    w.put_array(e.z), w.put_array(e.vz), w.put_array(e.x), w.put_array(e.y), w.put_array(e.vx), w.put_array(e.vy);
}

// Heights and vertical velocities are exact multiples of their quantum within the range the
// state is kept in (quantum.h), which the kernels' exact sums rely on; a saved state holds no
// others (found by fuzz_coupled_checkpoint: a velocity of ~2^62 quanta overflowed a kernel's
// row sum).
void check_quantised(const ByteReader& r, const std::vector<double>& values, const quantum::Quantum& q,
                     const char* what) {
  for (const double x : values)
    if (!(std::fabs(x) <= q.keep) || quantum::round_to(x, q.magic) != x)
      r.fail(std::string(what) + " " + detail::to_text(x) + " is not a multiple of its quantum " +
             detail::to_text(q.q) + " within +-" + detail::to_text(q.keep) + " (corrupt)");
}

void check_finite(const ByteReader& r, const std::vector<float>& values, const char* what) {
  for (const float x : values)
    if (!std::isfinite(x)) r.fail(std::string("a non-finite ") + what + " (corrupt)");
}

void check_tile_values(const ByteReader& r, const TileData& t, const quantum::Quantum& qu, const quantum::Quantum& qv) {
  check_quantised(r, t.uz, qu, "a node height");
  check_quantised(r, t.vz, qv, "a node velocity");
  for (const auto* v : {&t.ux, &t.uy, &t.vx, &t.vy}) check_finite(r, *v, "in-plane node value");
  for (const TileData::Edges& e : t.edges) {
    check_quantised(r, e.z, qu, "an edge height");
    check_quantised(r, e.vz, qv, "an edge velocity");
    for (const auto* v : {&e.x, &e.y, &e.vx, &e.vy}) check_finite(r, *v, "in-plane edge value");
  }
}

// Reads into a tile that obtain() just made, so every array already has its size.
void get_tile(ByteReader& r, TileData& t) {
  t.cur = r.get<std::int32_t>("tile") != 0 ? 1 : 0;
  t.calm = r.get<std::int32_t>("tile");
  t.awake = r.get<std::uint8_t>("tile") != 0;
  t.ever_awake = r.get<std::uint8_t>("tile") != 0;
  for (auto* v : {&t.uz, &t.vz}) r.get_array(*v, v->size(), "tile nodes");
  for (auto* v : {&t.ux, &t.uy, &t.vx, &t.vy}) r.get_array(*v, v->size(), "tile nodes");
  r.get_array(t.flags, t.flags.size(), "tile constraints");
  t.masks_stale = true;
  for (TileData::Edges& e : t.edges) {
    for (auto* v : {&e.z, &e.vz}) r.get_array(*v, v->size(), "tile edges");
    for (auto* v : {&e.x, &e.y, &e.vx, &e.vy}) r.get_array(*v, v->size(), "tile edges");
  }
  for (std::uint8_t f : t.flags)
    if (f > static_cast<std::uint8_t>(NodeConstraint::fixed)) r.fail("a node constraint of " + std::to_string(f));
}

void check_shape(ByteReader& r, const SurfaceSettings& s, int tile, bool full) {
  const int nx = r.get<std::int32_t>("shape"), ny = r.get<std::int32_t>("shape");
  const int t = r.get<std::int32_t>("shape"), f = r.get<std::int32_t>("shape");
  if (nx != s.nx || ny != s.ny || t != tile || (f != 0) != full)
    r.fail("saved from a surface of " + std::to_string(nx) + " x " + std::to_string(ny) + " nodes, tiles of " +
           std::to_string(t) + (f != 0 ? ", 3-D" : ", vertical") + "; this one is " + std::to_string(s.nx) + " x " +
           std::to_string(s.ny) + ", tiles of " + std::to_string(tile) + (full ? ", 3-D" : ", vertical") +
           " (restore into a surface built with the saved settings)");
}

}  // namespace

std::vector<unsigned char> Surface::save_state() const {
  const State& s = *s_;
  ByteWriter w;
  w.put(kStateVersion);
  w.put(static_cast<std::int32_t>(settings_.nx)), w.put(static_cast<std::int32_t>(settings_.ny));
  w.put(static_cast<std::int32_t>(s.T)), w.put(static_cast<std::int32_t>(s.full));
  w.put(s.time), w.put(s.last_substep);
  w.put(static_cast<std::uint8_t>(s.deformation.has_value()));
  const Deformation d = s.deformation.value_or(Deformation{});
  w.put(d.max_tension), w.put(d.max_sin);
  w.put(s.ever_awake);
  w.put(static_cast<std::uint64_t>(s.tiles.size()));
  for (const auto& t : s.tiles) put_tile(w, *t);
  return std::move(w.bytes);
}

void Surface::restore_state(std::span<const unsigned char> bytes, const std::string& source) {
  ByteReader r(bytes, source);
  const auto version = r.get<std::uint32_t>("version");
  if (version != kStateVersion)
    r.fail("water state version " + std::to_string(version) + " (this build reads " + std::to_string(kStateVersion) +
           ")");
  // Read into a fresh surface first: a bad state leaves this one as it was.
  Surface scratch(settings_);
  State& n = *scratch.s_;
  check_shape(r, settings_, n.T, n.full);
  n.time = r.get<double>("time"), n.last_substep = r.get<double>("time");
  const bool has_deformation = r.get<std::uint8_t>("deformation") != 0;
  Deformation d;
  d.max_tension = r.get<double>("deformation"), d.max_sin = r.get<double>("deformation");
  n.deformation = has_deformation ? std::optional<Deformation>(d) : std::nullopt;
  n.ever_awake = r.get<std::int64_t>("ever awake");
  const auto count = r.get<std::uint64_t>("tile count");
  if (count > static_cast<std::uint64_t>(n.tiles_x) * static_cast<std::uint64_t>(n.tiles_y))
    r.fail("tile count " + std::to_string(count) + " (corrupt)");
  for (std::uint64_t k = 0; k < count; ++k) {
    const int tx = r.get<std::int32_t>("tile"), ty = r.get<std::int32_t>("tile");
    if (!n.inside(tx, ty)) r.fail("tile (" + std::to_string(tx) + ", " + std::to_string(ty) + ") off the grid");
    TileData& tile = n.obtain(settings_, tx, ty);
    get_tile(r, tile);
    check_tile_values(r, tile, n.qu, n.qv);
  }
  if (r.remaining() != 0) r.fail("bytes after the last tile (corrupt)");
  n.rebuild_awake_list();
  n.last_stats = StepStats{};
  std::swap(s_, scratch.s_);
  set_threads(settings_.threads);
}

}  // namespace shore::water
