#include "shore/terrain/bearing_solve.h"

#include <vector>

#include "bearing.h"
#include "shore/core/error.h"
#include "terrain_impl.h"
#include "validation.h"

namespace shore::terrain {

struct BearingSolve::State {
  const Terrain::Impl* terrain = nullptr;
  std::vector<BearingColumn> columns;
  std::vector<std::uint8_t> mats;
  std::vector<ColumnLayer> layers;
  std::vector<det::FixedPower> powers;  ///< the palette's z^n, kept while its exponents stay
  /// Every offset measured since the reset with its bearing; entries past `used` are
  /// spare buffers from earlier envelopes.
  std::vector<double> offsets;
  std::vector<Bearing> measured;
  std::size_t used = 0;

  const Bearing* find(double offset) const {
    for (std::size_t k = 0; k < used; ++k)
      if (offsets[k] == offset) return &measured[k];
    return nullptr;
  }
  const Bearing& measure(double offset) {
    if (const Bearing* known = find(offset)) return *known;
    if (used == measured.size()) measured.emplace_back(), offsets.push_back(0.0);
    offsets[used] = offset;
    capacity_into(columns, mats, layers, terrain->s, terrain->palette, powers, offset, true, measured[used]);
    return measured[used++];
  }
};

BearingSolve::BearingSolve() : state_(std::make_unique<State>()) {}
BearingSolve::~BearingSolve() = default;
BearingSolve::BearingSolve(BearingSolve&&) noexcept = default;
BearingSolve& BearingSolve::operator=(BearingSolve&&) noexcept = default;

void BearingSolve::reset(const Terrain& terrain, const EnvelopeRaster& envelope) {
  check_envelope(&envelope, "terrain.BearingSolve.reset.envelope");
  State& st = *state_;
  st.terrain = terrain.impl_.get();
  if (!powers_fit(st.powers, st.terrain->palette)) st.powers = bearing_powers(st.terrain->palette);
  st.used = 0;
  st.mats.clear();
  const bool layered = st.terrain->tiles.layered();
  bearing_columns_into(st.terrain->tiles, st.terrain->s, st.terrain->palette, envelope, false, 0.0,
                       st.terrain->palette.size() > 1 || layered ? &st.mats : nullptr, layered ? &st.layers : nullptr,
                       st.columns);
  if (!layered) st.layers.clear();
}

double BearingSolve::offset(double load) {
  Check{"terrain.BearingSolve.offset"}.non_negative("load", load);
  State& st = *state_;
  if (st.terrain == nullptr)
    throw InvalidSetting("terrain.BearingSolve.offset", "no envelope", "must follow reset(terrain, envelope)");
  if (st.columns.empty()) (void)st.measure(0.0);  // offset_for_load measures nothing: 0 is the answer
  return offset_for_load(st.columns, load, [&](double o) { return st.measure(o).capacity; });
}

double BearingSolve::offset(double load, const std::function<double(const Bearing&)>& capacity_of) {
  Check{"terrain.BearingSolve.offset"}.non_negative("load", load);
  State& st = *state_;
  if (st.terrain == nullptr)
    throw InvalidSetting("terrain.BearingSolve.offset", "no envelope", "must follow reset(terrain, envelope)");
  if (st.columns.empty()) (void)st.measure(0.0);
  return offset_for_load(st.columns, load, [&](double o) { return capacity_of(st.measure(o)); });
}

const Bearing& BearingSolve::bearing(double offset) const {
  const Bearing* b = state_->find(offset);
  if (b == nullptr)
    throw InvalidSetting("terrain.BearingSolve.bearing(offset)", detail::to_text(offset),
                         "must be an offset offset() returned since the last reset");
  return *b;
}

}  // namespace shore::terrain
