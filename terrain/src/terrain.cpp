// shore::terrain::Terrain: the public face of the soil grid. The storage is in
// tile_store.h, one step's work in pipeline.h; docs/terrain.md walks through both.

#include "shore/terrain/terrain.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <span>
#include <string>
#include <utility>

#include "bedrock_depth.h"
#include "capacity_bytes.h"
#include "shore/core/det_math.h"
#include "shore/core/error.h"
#include "shore/core/hash.h"
#include "terrain_impl.h"
#include "validation.h"

namespace shore::terrain {

namespace {

TerrainSettings validated(TerrainSettings s) {
  s.validate();
  return s;
}

}  // namespace

Terrain::Impl::Impl(TerrainSettings settings) : s(validated(std::move(settings))), palette{s.material}, tiles(s) {}

std::size_t Terrain::Impl::bytes() const {
  return sizeof(Impl) + tiles.bytes() + capacity_bytes(unsettled, palette) + planner.bytes() + pipeline.bytes() +
         spray.bytes();
}

Terrain::Terrain(TerrainSettings settings) : impl_(std::make_unique<Impl>(std::move(settings))) {}
Terrain::~Terrain() = default;
Terrain::Terrain(Terrain&&) noexcept = default;
Terrain& Terrain::operator=(Terrain&&) noexcept = default;

const TerrainSettings& Terrain::settings() const noexcept { return impl_->s; }

void Terrain::set_material(const Material& material) {
  material.validate();
  const Material& now = impl_->s.material;
  if (material.soil_depth != now.soil_depth)
    throw InvalidSetting("Terrain::set_material.soil_depth", std::to_string(material.soil_depth),
                         "the present soil_depth (" + std::to_string(now.soil_depth) + " m)");
  if (material.rigid != now.rigid)
    throw InvalidSetting("Terrain::set_material.rigid", material.rigid ? "true" : "false", "the present rigid flag");
  impl_->s.material = material;
  impl_->palette[0] = material;
}

// ---- grid geometry -------------------------------------------------------------------

std::int64_t Terrain::column_i(double x) const {
  return static_cast<std::int64_t>(std::llround((x - impl_->s.origin_x) / impl_->s.cell));
}
std::int64_t Terrain::column_j(double y) const {
  return static_cast<std::int64_t>(std::llround((y - impl_->s.origin_y) / impl_->s.cell));
}
double Terrain::column_x(std::int64_t i) const { return impl_->s.origin_x + static_cast<double>(i) * impl_->s.cell; }
double Terrain::column_y(std::int64_t j) const { return impl_->s.origin_y + static_cast<double>(j) * impl_->s.cell; }

// ---- state of one column -------------------------------------------------------------

double Terrain::height(std::int64_t i, std::int64_t j) const {
  const TileStore& store = impl_->tiles;
  const Tile* t = store.find(store.key_of(i, j));
  return t ? t->height[store.local(i, j)] : store.base_at(i, j);
}
double Terrain::sinkage(std::int64_t i, std::int64_t j) const {
  const TileStore& store = impl_->tiles;
  const Tile* t = store.find(store.key_of(i, j));
  return t ? t->sinkage[store.local(i, j)] : 0.0;
}
double Terrain::base_height(std::int64_t i, std::int64_t j) const {
  const TileStore& store = impl_->tiles;
  const Tile* t = store.find(store.key_of(i, j));
  return t ? t->base[store.local(i, j)] : store.base_at(i, j);
}
double Terrain::bedrock(std::int64_t i, std::int64_t j) const {
  const Material& m = material_at(i, j);
  return base_height(i, j) - (m.rigid && !impl_->s.material.rigid ? 0.0 : impl_->s.material.soil_depth);
}

void Terrain::heights(const GridRect& r, std::span<double> out) const { read_rect(r, out, false); }
void Terrain::base_heights(const GridRect& r, std::span<double> out) const { read_rect(r, out, true); }

void Terrain::read_rect(const GridRect& r, std::span<double> out, bool base) const {
  if (r.nx < 0 || r.ny < 0 || out.size() != static_cast<std::size_t>(r.nx) * static_cast<std::size_t>(r.ny))
    throw InvalidSetting("terrain.Terrain.heights(out).size", detail::to_text(out.size()),
                         "must be nx * ny of the rectangle");
  impl_->tiles.read(r, out, base);
}

void Terrain::set_height(std::int64_t i, std::int64_t j, double h) {
  Check{"terrain.Terrain.set_height"}.finite("h", h);
  TileStore& store = impl_->tiles;
  store.advance_generation();
  const TileKey key = store.key_of(i, j);
  Tile& t = store.tile(key);
  const std::size_t k = store.local(i, j);
  const double value =
      std::max(h, t.base[k] - BedrockDepth(impl_->palette, impl_->s.material.soil_depth).at(t.material, k));
  if (value == t.height[k]) return;
  impl_->edited += (value - t.height[k]) * (impl_->s.cell * impl_->s.cell);
  t.height[k] = value;
  const int li = static_cast<int>(k % static_cast<std::size_t>(store.n()));
  const int lj = static_cast<int>(k / static_cast<std::size_t>(store.n()));
  store.mark_changed(key, t, {li, lj, 1, 1});
}

// ---- physics -------------------------------------------------------------------------

StepReport Terrain::step(std::span<const Imprint> imprints) { return step(imprints, 0.0); }

StepReport Terrain::step(std::span<const Imprint> imprints, double dt) {
  check_imprints(imprints, dt);
  Impl& im = *impl_;
  if (im.s.material.rigid) return {};
  im.tiles.advance_generation();
  im.tiles.tick();
  std::vector<MarginBox> reached;
  for (const Imprint& imprint : imprints)
    if (!imprint.hold)
      if (const GridRect r = im.planner.reach_box(im.tiles, im.s, imprint); r.nx > 0)
        reached.push_back({r, imprint.margin > 0 ? imprint.margin : im.s.active_margin});
  const std::vector<GridRect> carried = std::exchange(im.unsettled, {});
  StepReport total;
  for (const MarginBox& r : ActiveRegions::plan(reached, carried, im.s.active_margin)) {
    const StepReport part = im.pipeline.run(im.tiles, im.s, im.palette, r.box, imprints);
    if (im.pipeline.still_flowing().nx > 0)
      im.unsettled.push_back(ActiveRegions::carry(im.pipeline.still_flowing(), r.margin, im.s.active_margin));
    im.compacted += part.compacted_volume;
    total.active_columns += part.active_columns;
    total.contact_columns += part.contact_columns;
    total.erosion_passes = std::max(total.erosion_passes, part.erosion_passes);
    total.displaced_volume += part.displaced_volume;
    total.compacted_volume += part.compacted_volume;
  }
  // What the bodies reached this step is eroded once more next step: where a body has
  // lifted or moved away, slopes it held at theta_in relax toward theta_out.
  for (const MarginBox& r : reached) im.unsettled.push_back(ActiveRegions::carry(r.box, r.margin, im.s.active_margin));
  // Spray after the soil has been pressed: bodies pick up from, and particles land on, the
  // surface this step leaves.
  if (dt > 0.0 && im.s.spray.enabled) {
    const auto t0 = std::chrono::steady_clock::now();
    im.spray.step(im.tiles, im.s, im.palette, imprints, dt, total);
    im.spray_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  // After spray, which may land on any tile: a tile it touched is no longer idle.
  if (im.s.idle_tile_steps > 0) im.tiles.release_idle(im.s.idle_tile_steps);
  return total;
}

StepReport Terrain::relax(const GridRect& region) {
  check_relax_region(region);
  if (impl_->s.material.rigid || region.nx == 0 || region.ny == 0) return {};
  impl_->tiles.advance_generation();
  return impl_->pipeline.relax(impl_->tiles, impl_->s, impl_->palette, region);
}

// ---- output --------------------------------------------------------------------------

std::vector<GridRect> Terrain::take_changed() { return impl_->tiles.take_changed(); }
std::uint64_t Terrain::generation() const noexcept { return impl_->tiles.generation(); }
std::vector<GridRect> Terrain::changed_since(std::uint64_t g) const { return impl_->tiles.changed_since(g); }

VolumeTotals Terrain::volume() const {
  VolumeTotals v;
  double ground = 0.0;
  for (const TileKey& key : impl_->tiles.sorted_keys()) {
    const Tile& t = *impl_->tiles.find(key);
    double sum = 0.0;
    for (std::size_t k = 0; k < t.height.size(); ++k) sum += t.height[k] - t.base[k];
    ground += sum;
  }
  v.ground = ground * (impl_->s.cell * impl_->s.cell);
  v.compacted = impl_->compacted;
  const SprayState& spray = impl_->spray.state;
  v.clinging = spray.clinging();
  v.airborne = spray.in_flight() + v.clinging;
  v.lost = spray.lost;
  v.edited = impl_->edited;
  return v;
}

std::vector<SprayParticle> Terrain::spray_particles() const {
  std::vector<SprayParticle> out;
  out.reserve(impl_->spray.state.particles.size());
  const SprayState& st = impl_->spray.state;
  for (std::size_t k = 0; k < st.particles.size(); ++k) {
    const Particle& p = st.particles[k];
    const int index = st.particle_materials.empty() ? 0 : st.particle_materials[k];
    out.push_back(
        {p.position, det::pow(p.volume * (3.0 / (4.0 * std::numbers::pi)), 1.0 / 3.0), p.volume, p.velocity, index});
  }
  return out;
}

double Terrain::spray_seconds() const { return impl_->spray_seconds; }

SprayCounts Terrain::spray_counts() const {
  const SprayState& spray = impl_->spray.state;
  SprayCounts c = spray.counts;
  c.particles = static_cast<std::int64_t>(spray.particles.size());
  c.clinging_cells = spray.cell_count();
  c.bytes = impl_->spray.bytes();
  return c;
}

std::uint64_t Terrain::state_hash() const {
  StateHash h;
  h.add(impl_->compacted);
  h.add(impl_->edited);
  for (const TileKey& key : impl_->tiles.sorted_keys()) {
    const Tile& t = *impl_->tiles.find(key);
    if (t.holds_only_base()) continue;  // equals no tile, whether released yet or not
    h.add(key.tx);
    h.add(key.ty);
    h.add(std::span<const double>(t.height));
    h.add(std::span<const double>(t.sinkage));
    // The map only where painted (empty elsewhere): unpainted soil keeps its hashes.
    if (!t.material.empty()) h.add_bytes(t.material.data(), t.material.size());
    // Layers only where a column is layered: unlayered soil keeps its hashes.
    if (t.layered()) {
      h.add(std::span<const double>(t.layer_boundary));
      h.add_bytes(t.layer_lower.data(), t.layer_lower.size());
    }
  }
  // Spray, once a step has had time to make any (so soils that never sprayed keep the
  // hashes they had before spray existed).
  const SprayState& spray = impl_->spray.state;
  if (spray.step > 0 || !spray.particles.empty() || !spray.bodies.empty()) spray.hash_into(h);
  return h.value();
}

std::size_t Terrain::tile_count() const { return impl_->tiles.size(); }

std::size_t Terrain::memory_bytes() const { return impl_->bytes(); }

}  // namespace shore::terrain
