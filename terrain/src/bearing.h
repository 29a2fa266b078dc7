#pragma once
// Private: what the soil under an envelope can bear (Bekker's law on the columns it
// touches), and the offset at which it bears a load.

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "layers.h"
#include "shore/core/det_power.h"
#include "shore/core/envelope.h"
#include "shore/terrain/terrain.h"
#include "tile_store.h"

namespace shore::terrain {

/// One column an envelope covers, with its soil state.
struct BearingColumn {
  std::int64_t i = 0, j = 0;
  double top = 0.0;    ///< m, column top
  double sink = 0.0;   ///< m, plastic sinkage
  double bed = 0.0;    ///< m, bedrock
  double lower = 0.0;  ///< m, the envelope above it
};

/// The columns the envelope covers, in window order. With only_touching, only those the
/// envelope lowered by `offset` touches (bearing at one offset needs no others). With mats,
/// their palette indices into *mats (kept apart: a one-material terrain reads none and its
/// columns stay as compact as they were). With layers, their layering into *layers (layers.h;
/// the caller asks only when the store is layered, and then asks for mats too). Each column's bedrock lies its palette
/// entry's soil depth below its base (bedrock_depth.h: a rigid entry's at its base). Reads only.
[[nodiscard]] std::vector<BearingColumn> bearing_columns(const TileStore& store, const TerrainSettings& s,
                                                         std::span<const Material> palette, const EnvelopeRaster& env,
                                                         bool only_touching, double offset,
                                                         std::vector<std::uint8_t>* mats,
                                                         std::vector<ColumnLayer>* layers = nullptr);
/// bearing_columns() into columns (cleared first), whose buffer it reuses.
void bearing_columns_into(const TileStore& store, const TerrainSettings& s, std::span<const Material> palette,
                          const EnvelopeRaster& env, bool only_touching, double offset, std::vector<std::uint8_t>* mats,
                          std::vector<ColumnLayer>* layers, std::vector<BearingColumn>& columns);
/// The offset at which every column's envelope reaches its bedrock, which carries anything:
/// the largest lower - bed, 0 at least (offset_for_load's bracket limit).
[[nodiscard]] double bedrock_offset(std::span<const BearingColumn> columns);
/// z^n for each palette entry's Bekker exponent n, in palette order: the bearing's power law.
[[nodiscard]] std::vector<det::FixedPower> bearing_powers(std::span<const Material> palette);
/// Whether powers were made by bearing_powers(palette) for a palette with these exponents.
[[nodiscard]] bool powers_fit(std::span<const det::FixedPower> powers, std::span<const Material> palette);
/// Bekker capacity of the columns the envelope, lowered by offset, touches (Terrain::bearing).
/// The columns in window order, row by row (as bearing_columns() gives them).
/// Each column bears by its own material's law: palette[mats[k]] (mats empty: palette[0]),
/// its z^n by powers[mats[k]] (bearing_powers(palette)); a layered column (layers[k], when
/// layers is not empty) by its two-piece law (layers.h).
[[nodiscard]] Bearing capacity(std::span<const BearingColumn> columns, std::span<const std::uint8_t> mats,
                               std::span<const ColumnLayer> layers, const TerrainSettings& s,
                               std::span<const Material> palette, std::span<const det::FixedPower> powers,
                               double offset, bool with_columns);
/// The columns an envelope lowered by one offset touches, as indices into the columns
/// capacity_into() was given, ascending. The buffer only grows (a vector shrunk to each
/// count would zero what it regrows); its first `count` entries are the list.
struct TouchingColumns {
  std::vector<std::uint32_t> index;
  std::size_t count = 0;
};
/// capacity() into out, whose buffers it reuses (out.columns is cleared first); the
/// touching columns into touching. With among (the touching columns at an offset no
/// smaller than this one), only those are visited: a column the envelope lowered by more
/// does not touch, lowered by less does not either (c.lower - offset falls as the offset
/// grows, rounding and all), so the same columns in the same order, the same bits.
void capacity_into(std::span<const BearingColumn> columns, std::span<const std::uint8_t> mats,
                   std::span<const ColumnLayer> layers, const TerrainSettings& s, std::span<const Material> palette,
                   std::span<const det::FixedPower> powers, double offset, bool with_columns, Bearing& out,
                   TouchingColumns& touching, const TouchingColumns* among = nullptr);
/// The offset at which the capacity equals load (Terrain::bearing_offset).
[[nodiscard]] double offset_for_load(std::span<const BearingColumn> columns, std::span<const std::uint8_t> mats,
                                     std::span<const ColumnLayer> layers, const TerrainSettings& s,
                                     std::span<const Material> palette, std::span<const det::FixedPower> powers,
                                     double load);
/// The same solve with the capacity at an offset (N) from capacity_at: every offset it
/// returns was measured by capacity_at, except 0 when columns is empty.
[[nodiscard]] double offset_for_load(std::span<const BearingColumn> columns, double load,
                                     const std::function<double(double)>& capacity_at);
/// The same with the columns' bedrock_offset() given (bedrock): none of them is read again.
[[nodiscard]] double offset_for_load(std::span<const BearingColumn> columns, double load,
                                     const std::function<double(double)>& capacity_at, double bedrock);

}  // namespace shore::terrain
