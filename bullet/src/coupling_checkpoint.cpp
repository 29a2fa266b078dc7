// The couplings' own state in a checkpoint (docs/checkpoints.md): TerrainCoupling's bodies
// (envelopes and their soil contacts) and tiles. The soil contact's fields are written next
// to their definition (TerrainCoupling::save_contact in terrain_coupling.cpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <utility>

#include "checkpoint_bytes.h"
#include "shore/bullet/terrain_coupling.h"
#include "shore/bullet/terrain_tiles.h"
#include "shore/core/byte_io.h"
#include "shore/core/error.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

namespace {
using coupling_detail::shape_type;

constexpr char kSoilMagic[8] = {'S', 'H', 'S', 'O', 'I', 'L', 'C', 'P'};
// Version 2: contact elements and blocks carry the unloading spring (stiffness, preload);
// version 1 states load with every element and block rigid, as they were stepped.
// Version 3: each body's contact keeps the pressure its unloading columns carried; version 2
// states load without that memory (the columns unload from their yield line, as they did).
// Version 4: the soil's clock (TerrainCouplingSettings::soil_interval: substeps and seconds
// since its last step, soil_steps) and whether each body's envelope has been pressed; older
// states load as if the soil had just stepped (it stepped every substep then).
// Version 5: contacts that follow their bodies between soil steps
// (SoilContactSettings::follow_drift): each element's pressure rate, each block's capacity
// rate and approach, each contact's drift, whether each envelope is newer than its contact,
// contacts_followed; older states load with their contacts built afresh at the next substep.
constexpr std::uint32_t kSoilVersion = 5;

void put_envelope(ByteWriter& w, const EnvelopeRaster& e) { coupling_detail::put_window(w, e); }

EnvelopeRaster get_envelope(ByteReader& r) {
  EnvelopeRaster e;
  coupling_detail::get_window(r, e);
  const auto cells = static_cast<std::size_t>(e.nx) * static_cast<std::size_t>(e.ny);
  if (e.lower.size() != cells && !e.lower.empty())  // empty: the body left the soil's region
    r.fail("envelope holds " + std::to_string(e.lower.size()) + " columns, its window " + std::to_string(cells));
  if (!e.upper.empty() && e.upper.size() != e.lower.size()) r.fail("envelope's upper and lower differ in size");
  return e;
}

/// The totals of the statistics (not the last substep's timings: a checkpoint of the same
/// state is the same bytes).
void put_totals(ByteWriter& w, const TerrainCouplingStats& s) {
  w.put(s.substeps), w.put(s.skipped_bodies), w.put(s.yields), w.put(s.rescues), w.put(s.vertices_pushed);
  w.put(s.plastic_work), w.put(s.shear_work);
  w.put(s.soil_steps);
  w.put(s.contacts_followed);
}
void get_totals(ByteReader& r, TerrainCouplingStats& s, std::uint32_t version) {
  for (std::int64_t* v : {&s.substeps, &s.skipped_bodies, &s.yields, &s.rescues, &s.vertices_pushed})
    *v = r.get<std::int64_t>("statistics");
  s.plastic_work = r.get<double>("statistics"), s.shear_work = r.get<double>("statistics");
  if (version >= 4) s.soil_steps = r.get<std::int64_t>("statistics");
  if (version >= 5) s.contacts_followed = r.get<std::int64_t>("statistics");
}
}  // namespace

std::vector<unsigned char> TerrainCoupling::save_state() const {
  ByteWriter w;
  coupling_detail::put_header(w, kSoilMagic, kSoilVersion);
  put_totals(w, stats_);
  w.put(static_cast<std::int32_t>(substeps_since_soil_)), w.put(time_since_soil_);
  w.put(static_cast<std::uint32_t>(bodies_.size()));
  for (const Body& b : bodies_) {
    w.put(static_cast<std::int32_t>(shape_type(*b.body))), w.put(static_cast<std::uint8_t>(b.settings.deform));
    put_envelope(w, b.envelope);
    coupling_detail::put_transform(w, b.envelope_pose);
    w.put(static_cast<std::uint8_t>(b.pressed)), w.put(static_cast<std::uint8_t>(b.envelope_fresh));
    save_contact(*b.contact, w);
  }
  tiles_.save_state(w);
  return std::move(w.bytes);
}

void TerrainCoupling::restore_state(std::span<const unsigned char> bytes, const std::string& source) {
  ByteReader r(bytes, source);
  const std::uint32_t version =
      coupling_detail::check_header(r, kSoilMagic, 1, kSoilVersion, "a soil coupling's state");
  TerrainCouplingStats stats;
  get_totals(r, stats, version);
  int substeps_since_soil = 0;
  double time_since_soil = 0.0;
  if (version >= 4) {
    substeps_since_soil = r.get<std::int32_t>("substeps since the soil's step");
    time_since_soil = r.get<double>("time since the soil's step");
    if (substeps_since_soil < 0 || !(time_since_soil >= 0.0) || !std::isfinite(time_since_soil))
      r.fail("the soil's clock (" + std::to_string(substeps_since_soil) + " substeps, " +
             std::to_string(time_since_soil) + " s since its step) is not a clock");
  }
  const auto count = r.get<std::uint32_t>("body count");
  if (count != bodies_.size())
    r.fail("holds " + std::to_string(count) + " bodies, the coupling has " + std::to_string(bodies_.size()) +
           " (add the same bodies in the same order)");
  std::vector<Body> saved(count);  // read whole before anything changes
  for (std::uint32_t k = 0; k < count; ++k) {
    const auto type = r.get<std::int32_t>("body shape type");
    const bool deform = r.get<std::uint8_t>("body settings") != 0;
    if (type != shape_type(*bodies_[k].body) || deform != bodies_[k].settings.deform)
      r.fail("body " + std::to_string(k) + " was saved with shape type " + std::to_string(type) +
             (deform ? "" : " not") + " deforming; the coupling's has " + std::to_string(shape_type(*bodies_[k].body)) +
             (bodies_[k].settings.deform ? "" : " not") + " deforming");
    saved[k].envelope = get_envelope(r);
    saved[k].envelope_pose = coupling_detail::get_transform(r, "envelope pose");
    if (!coupling_detail::finite(saved[k].envelope_pose))
      r.fail("body " + std::to_string(k) + "'s envelope pose is not finite");
    saved[k].pressed = version < 4 || r.get<std::uint8_t>("body's envelope pressed") != 0;
    saved[k].envelope_fresh = version < 5 || r.get<std::uint8_t>("body's envelope fresh") != 0;
    restore_contact(r, *saved[k].contact,
                    static_cast<std::size_t>(saved[k].envelope.nx) * static_cast<std::size_t>(saved[k].envelope.ny),
                    version);
  }
  tiles_.restore_state(r);  // last in the bytes; changes the tiles only once all is read
  // Loading the soil marked every column changed. The run that was saved had taken its
  // changes at the end of its last substep, and the tiles are now exactly as saved: taking
  // these keeps them from waking the bodies at rest (which would change the continuation).
  (void)soil_.take_changed();
  stats_ = stats;  // the totals; the last substep's timings start again
  substeps_since_soil_ = substeps_since_soil;
  time_since_soil_ = time_since_soil;
  for (std::uint32_t k = 0; k < count; ++k) {
    Body& b = bodies_[k];
    b.envelope = std::move(saved[k].envelope);
    b.envelope_pose = saved[k].envelope_pose;
    b.pressed = saved[k].pressed;
    b.envelope_fresh = saved[k].envelope_fresh;
    std::swap(b.contact, saved[k].contact);
  }
}

namespace {
struct SavedTile {
  std::int64_t tx = 0, ty = 0;
  HeightfieldTileSettings settings;
  std::vector<double> heights;
  std::uint8_t lagging = 0;
  std::int32_t lag[4] = {0, 0, -1, -1};
};
}  // namespace

void TerrainTiles::save_state(ByteWriter& w) const {
  const int T = soil_.settings().tile_columns;
  std::vector<const Tile*> ordered;  // key order: the file does not depend on the map's
  ordered.reserve(tiles_.size());
  for (const auto& [k, tile] : tiles_) ordered.push_back(&tile);
  std::sort(ordered.begin(), ordered.end(),
            [](const Tile* a, const Tile* b) { return a->j0 != b->j0 ? a->j0 < b->j0 : a->i0 < b->i0; });
  w.put(static_cast<std::int32_t>(T)), w.put(clamped_);
  w.put(static_cast<std::uint64_t>(ordered.size()));
  for (const Tile* t : ordered) {
    const HeightfieldTileSettings& s = t->field->settings();
    w.put(t->i0 / T), w.put(t->j0 / T);
    w.put(s.min_height), w.put(s.max_height), w.put(s.initial_height);
    std::vector<double> h(static_cast<std::size_t>(s.columns) * static_cast<std::size_t>(s.columns));
    for (int b = 0; b < s.columns; ++b)
      for (int a = 0; a < s.columns; ++a) h[static_cast<std::size_t>(b) * s.columns + a] = t->field->height(a, b);
    w.put_array(h);
    w.put(static_cast<std::uint8_t>(t->lagging));
    w.put(static_cast<std::int32_t>(t->lag_a0)), w.put(static_cast<std::int32_t>(t->lag_b0));
    w.put(static_cast<std::int32_t>(t->lag_a1)), w.put(static_cast<std::int32_t>(t->lag_b1));
  }
}

void TerrainTiles::restore_state(ByteReader& r) {
  const int T = soil_.settings().tile_columns;
  if (const auto saved_T = r.get<std::int32_t>("tile size"); saved_T != T)
    r.fail("tiles of " + std::to_string(saved_T) + " columns, this soil's are " + std::to_string(T));
  const auto clamped = r.get<std::int64_t>("tiles");
  const auto count = r.get<std::uint64_t>("tile count");
  const std::size_t vertices = static_cast<std::size_t>(T + 1) * static_cast<std::size_t>(T + 1);
  if (count > r.remaining() / (vertices * sizeof(double))) r.fail("tile count " + std::to_string(count) + " overruns");
  std::vector<SavedTile> saved(static_cast<std::size_t>(count));
  for (SavedTile& t : saved) {
    t.tx = r.get<std::int64_t>("tile"), t.ty = r.get<std::int64_t>("tile");
    constexpr std::int64_t kMaxColumn = std::int64_t{1} << 52;  // the soil's own bound on column indices
    if (t.tx < -kMaxColumn / T || t.tx > kMaxColumn / T || t.ty < -kMaxColumn / T || t.ty > kMaxColumn / T)
      r.fail("tile (" + std::to_string(t.tx) + ", " + std::to_string(t.ty) + ") lies beyond column index 2^52");
    HeightfieldTileSettings& s = t.settings;
    s.columns = T + 1;
    s.cell = soil_.settings().cell;
    s.origin_x = soil_.column_x(t.tx * T), s.origin_y = soil_.column_y(t.ty * T);
    s.min_height = r.get<double>("tile bounds"), s.max_height = r.get<double>("tile bounds");
    s.initial_height = r.get<double>("tile bounds");
    s.friction = friction_;
    if (!(s.min_height < s.max_height) || !(s.initial_height >= s.min_height && s.initial_height <= s.max_height))
      r.fail("tile (" + std::to_string(t.tx) + ", " + std::to_string(t.ty) + ") has broken height bounds");
    r.get_array(t.heights, vertices, "tile heights");
    for (double h : t.heights)
      if (!std::isfinite(h))
        r.fail("tile (" + std::to_string(t.tx) + ", " + std::to_string(t.ty) + ") has a non-finite height");
    t.lagging = r.get<std::uint8_t>("tile lag");
    for (std::int32_t& v : t.lag) v = r.get<std::int32_t>("tile lag");
  }
  if (r.remaining() != 0) r.fail("bytes after the last tile (corrupt)");
  remove_all();
  clamped_ = clamped;
  for (const SavedTile& t : saved) {
    Tile& tile = add(t.tx, t.ty, t.settings, t.heights);
    tile.lagging = t.lagging != 0;
    tile.lag_a0 = t.lag[0], tile.lag_b0 = t.lag[1], tile.lag_a1 = t.lag[2], tile.lag_b1 = t.lag[3];
  }
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
