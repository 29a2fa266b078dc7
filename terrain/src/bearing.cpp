#include "bearing.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "bedrock_depth.h"
#include "shore/core/error.h"
#include "shore/core/illinois.h"
#include "shore/terrain/bekker.h"
#include "terrain_impl.h"
#include "validation.h"

namespace shore::terrain {

namespace {
constexpr double kCarriesAnything = std::numeric_limits<double>::infinity();
}  // namespace

std::vector<BearingColumn> bearing_columns(const TileStore& store, const TerrainSettings& s,
                                           std::span<const Material> palette, const EnvelopeRaster& env,
                                           bool only_touching, double offset, std::vector<std::uint8_t>* mats,
                                           std::vector<ColumnLayer>* layers) {
  std::vector<BearingColumn> columns;
  bearing_columns_into(store, s, palette, env, only_touching, offset, mats, layers, columns);
  return columns;
}

void bearing_columns_into(const TileStore& store, const TerrainSettings& s, std::span<const Material> palette,
                          const EnvelopeRaster& env, bool only_touching, double offset, std::vector<std::uint8_t>* mats,
                          std::vector<ColumnLayer>* layers, std::vector<BearingColumn>& columns) {
  if (layers) layers->clear();
  const BedrockDepth depth(palette, s.material.soil_depth);
  const double tol = s.contact_tolerance;
  columns.clear();
  store.for_each_run({env.i0, env.j0, env.nx, env.ny}, [&](const Tile* t, const TileRun& run) {
    const double* lower = env.lower.data() + static_cast<std::size_t>(run.y) * env.nx + run.x;
    const std::int64_t i0 = env.i0 + run.x, j = env.j0 + run.y;
    for (int r = 0; r < run.count; ++r) {
      const double e = lower[r];
      if (e == EnvelopeRaster::kNoLower) continue;  // not covered
      BearingColumn c{i0 + r, j, 0, 0, 0, e};
      if (t) {
        const std::size_t k = run.local + static_cast<std::size_t>(r);
        c.top = t->height[k], c.sink = t->sinkage[k], c.bed = t->base[k] - depth.at(t->material, k);
      } else {
        const double b = store.base_at(i0 + r, j);
        c.top = b, c.sink = 0.0, c.bed = b - depth.at(0);
      }
      if (only_touching && !(e - offset <= c.top + tol)) continue;
      columns.push_back(c);
      if (mats) mats->push_back(t && !t->material.empty() ? t->material[run.local + static_cast<std::size_t>(r)] : 0);
      if (layers) layers->push_back(t ? t->layer(run.local + static_cast<std::size_t>(r)) : ColumnLayer{});
    }
  });
}

double bedrock_offset(std::span<const BearingColumn> columns) {
  double deepest = 0.0;
  for (const BearingColumn& c : columns) deepest = std::max(deepest, c.lower - c.bed);
  return deepest;
}

std::vector<det::FixedPower> bearing_powers(std::span<const Material> palette) {
  std::vector<det::FixedPower> powers;
  powers.reserve(palette.size());
  for (const Material& m : palette) powers.emplace_back(m.bekker_n);
  return powers;
}

bool powers_fit(std::span<const det::FixedPower> powers, std::span<const Material> palette) {
  if (powers.size() != palette.size()) return false;
  for (std::size_t k = 0; k < palette.size(); ++k)
    if (!(powers[k].exponent() == palette[k].bekker_n)) return false;
  return true;
}

Bearing capacity(std::span<const BearingColumn> columns, std::span<const std::uint8_t> mats,
                 std::span<const ColumnLayer> layers, const TerrainSettings& s, std::span<const Material> palette,
                 std::span<const det::FixedPower> powers, double offset, bool with_columns) {
  Bearing out;
  TouchingColumns touching;
  capacity_into(columns, mats, layers, s, palette, powers, offset, with_columns, out, touching);
  return out;
}

namespace {

/// The columns the envelope lowered by offset touches into touching (indices, ascending),
/// visiting those among lists (every column when null); their bounding box into box
/// (i0, j0, i1, j1, inclusive). Returns how many. The columns come row by row (window
/// order), so the first and last touching ones hold the least and the greatest j.
std::size_t find_touching(std::span<const BearingColumn> columns, double offset, double tol, TouchingColumns& touching,
                          const TouchingColumns* among, std::int64_t box[4]) {
  const std::size_t visits = among ? among->count : columns.size();
  if (touching.index.size() < visits) touching.index.resize(visits);
  std::uint32_t* const list = touching.index.data();
  std::int64_t i0 = std::numeric_limits<std::int64_t>::max(), i1 = std::numeric_limits<std::int64_t>::min();
  std::size_t n = 0;
  const auto visit = [&](std::uint32_t k) {
    const BearingColumn& c = columns[k];
    if (!(c.lower - offset <= c.top + tol)) return;
    list[n++] = k;
    i0 = std::min(i0, c.i), i1 = std::max(i1, c.i);
  };
  if (among)
    for (std::size_t t = 0; t < visits; ++t) visit(among->index[t]);
  else
    for (std::size_t k = 0; k < visits; ++k) visit(static_cast<std::uint32_t>(k));
  touching.count = n;
  if (n > 0) box[0] = i0, box[1] = columns[list[0]].j, box[2] = i1, box[3] = columns[list[n - 1]].j;
  return n;
}

}  // namespace

// A column touches when the envelope is within contact_tolerance of its top; its sinkage if
// pressed to the envelope is its plastic sinkage plus how far the envelope lies below its
// top. b is the smaller side of the touching columns' bounding box (each column counts as
// one cell wide). A touched column at bedrock carries anything.
// Pressure: bekker::pressure's expression, z^n from the palette entry's table (det_power.h).
// The touching columns are found in one pass (b needs them all first), then only they are
// visited again: the columns touching no more are tested once, not twice.
void capacity_into(std::span<const BearingColumn> columns, std::span<const std::uint8_t> mats,
                   std::span<const ColumnLayer> layers, const TerrainSettings& s, std::span<const Material> palette,
                   std::span<const det::FixedPower> powers, double offset, bool with_columns, Bearing& out,
                   TouchingColumns& touching, const TouchingColumns* among) {
  out.capacity = 0.0, out.patch_width = 0.0, out.contact_columns = 0;
  std::int64_t box[4];
  const std::size_t n = find_touching(columns, offset, s.contact_tolerance, touching, among, box);
  out.contact_columns = static_cast<int>(n);
  if (n == 0 || !with_columns) out.columns.clear();
  if (n == 0) return;
  const double b = static_cast<double>(std::min(box[2] - box[0] + 1, box[3] - box[1] + 1)) * s.cell;
  out.patch_width = b;
  const bool rigid = s.material.rigid;
  const double cell_area = s.cell * s.cell;
  // Written by index into a sized buffer: push_back's bookkeeping cost as much as the rest.
  // Resized, not cleared first: every entry is written below, and a cleared vector would
  // construct each one again (as much again as writing it).
  if (with_columns) out.columns.resize(n);
  ColumnForce* const written = out.columns.data();
  const std::uint32_t* const list = touching.index.data();
  // force_of(k, z): column k's Bekker force at sinkage z > 0 (one material: its
  // coefficient hoisted out of the loop).
  const auto add_columns = [&](auto force_of) {
    for (std::size_t t = 0; t < n; ++t) {
      const std::size_t k = list[t];
      const BearingColumn& c = columns[k];
      const double e = c.lower - offset;
      double force;
      if (rigid || e <= c.bed || c.top <= c.bed)
        force = kCarriesAnything;
      else {
        const double z = c.sink + std::max(0.0, c.top - e);
        force = z <= 0.0 ? 0.0 : force_of(k, z);
      }
      out.capacity += force;
      if (with_columns) written[t] = {c.i, c.j, force};
    }
  };
  const auto law = [&](std::size_t m) { return palette[m].bekker_kc / b + palette[m].bekker_kphi; };
  if (mats.empty()) {
    const double only = law(0);
    add_columns([&](std::size_t, double z) { return only * powers[0](z) * cell_area; });
  } else if (layers.empty()) {
    add_columns([&](std::size_t k, double z) { return law(mats[k]) * powers[mats[k]](z) * cell_area; });
  } else {
    // The two-piece law (layers.h); an unlayered column's boundary is never reached, so it
    // takes the first piece, the expression above.
    const auto piece = [&](std::uint8_t m, double z) { return z <= 0.0 ? 0.0 : law(m) * powers[m](z); };
    add_columns([&](std::size_t k, double z) {
      if (!layers[k].layered()) return law(mats[k]) * powers[mats[k]](z) * cell_area;
      return layered_pressure(layers[k], mats[k], z, piece) * cell_area;
    });
  }
}

// Capacity grows with the offset (more columns touch, each sinks further), so a bracket
// [lo, hi] with capacity(lo) < load <= capacity(hi) is narrowed by regula falsi (Illinois
// variant), falling back to bisection, until it is 1e-7 m wide; the upper end is returned
// so the soil carries at least the load.
double offset_for_load(std::span<const BearingColumn> columns, std::span<const std::uint8_t> mats,
                       std::span<const ColumnLayer> layers, const TerrainSettings& s, std::span<const Material> palette,
                       std::span<const det::FixedPower> powers, double load) {
  Bearing at;  // buffers reused across the search
  TouchingColumns touching;
  return offset_for_load(columns, load, [&](double o) {
    capacity_into(columns, mats, layers, s, palette, powers, o, false, at, touching);
    return at.capacity;
  });
}

double offset_for_load(std::span<const BearingColumn> columns, double load,
                       const std::function<double(double)>& capacity_at) {
  if (columns.empty()) return 0.0;  // nothing to read (the other overload's first answer)
  return offset_for_load(columns, load, capacity_at, bedrock_offset(columns));
}

double offset_for_load(std::span<const BearingColumn> columns, double load,
                       const std::function<double(double)>& capacity_at, double bedrock) {
  if (columns.empty()) return 0.0;  // the body covers no column: nothing to sink into
  auto f = [&](double o) { return capacity_at(o) - load; };
  double f_lo = f(0.0);
  if (f_lo >= 0.0) return 0.0;
  // Every covered column at bedrock bears anything: that offset closes the bracket.
  const double limit = bedrock;
  double lo = 0.0, hi = std::min(1e-3, limit), f_hi = f(hi);
  while (f_hi < 0.0 && hi < limit) {
    lo = hi, f_lo = f_hi;
    hi = std::min(2.0 * hi, limit);
    f_hi = f(hi);
  }
  if (f_hi < 0.0) return limit;  // unreachable (bedrock carries anything); kept as a guard
  constexpr double kTolerance = 1e-7;
  return illinois_narrow(f, {lo, hi}, f_lo, f_hi, kTolerance).hi;
}

Bearing Terrain::bearing(const EnvelopeRaster& envelope, double offset) const {
  check_envelope(&envelope, "terrain.Terrain.bearing.envelope");
  Check{"terrain.Terrain.bearing"}.non_negative("offset", offset);
  std::vector<std::uint8_t> mats;
  std::vector<ColumnLayer> layers;
  const bool layered = impl_->tiles.layered();
  const std::vector<BearingColumn> columns =
      bearing_columns(impl_->tiles, impl_->s, impl_->palette, envelope, true, offset,
                      impl_->palette.size() > 1 || layered ? &mats : nullptr, layered ? &layers : nullptr);
  return capacity(columns, mats, layers, impl_->s, impl_->palette, bearing_powers(impl_->palette), offset, true);
}

double Terrain::bearing_offset(const EnvelopeRaster& envelope, double load) const {
  check_envelope(&envelope, "terrain.Terrain.bearing_offset.envelope");
  Check{"terrain.Terrain.bearing_offset"}.non_negative("load", load);
  std::vector<std::uint8_t> mats;
  std::vector<ColumnLayer> layers;
  const bool layered = impl_->tiles.layered();
  const std::vector<BearingColumn> columns =
      bearing_columns(impl_->tiles, impl_->s, impl_->palette, envelope, false, 0.0,
                      impl_->palette.size() > 1 || layered ? &mats : nullptr, layered ? &layers : nullptr);
  return offset_for_load(columns, mats, layers, impl_->s, impl_->palette, bearing_powers(impl_->palette), load);
}

}  // namespace shore::terrain
