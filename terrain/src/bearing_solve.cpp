#include "shore/terrain/bearing_solve.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "bearing.h"
#include "shore/core/error.h"
#include "shore/core/illinois.h"
#include "terrain_impl.h"
#include "validation.h"

namespace shore::terrain {

namespace {

constexpr double kOffsetTolerance = 1e-7;  // m: offset_for_load's, the width a bracket is narrowed to
constexpr double kFirstStep = 1e-5;        // m: a warm bracket's first step past the deepest short offset

}  // namespace

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
  double bedrock = 0.0;  ///< offset_for_load's bracket limit for these columns
  /// The columns touching at the deepest offset measured since the reset (`reach_offset`,
  /// NaN before the first): a shallower one touches only among them (capacity_into).
  TouchingColumns reach, touching;
  double reach_offset = std::numeric_limits<double>::quiet_NaN();

  const Bearing* find(double offset) const {
    for (std::size_t k = 0; k < used; ++k)
      if (offsets[k] == offset) return &measured[k];
    return nullptr;
  }
  /// The state for a solve named `where`: throws before the first reset. The first
  /// offset is measured here when the envelope covers no column (offset_for_load measures
  /// nothing then: 0 is the answer, and bearing(0) must answer).
  State& ready(const char* where) {
    if (terrain == nullptr) throw InvalidSetting(where, "no envelope", "must follow reset(terrain, envelope)");
    if (columns.empty()) (void)measure(0.0);
    return *this;
  }
  const Bearing& measure(double offset) {
    if (const Bearing* known = find(offset)) return *known;
    if (used == measured.size()) measured.emplace_back(), offsets.push_back(0.0);
    offsets[used] = offset;
    const bool within = offset <= reach_offset;  // false before the first (NaN)
    capacity_into(columns, mats, layers, terrain->s, terrain->palette, powers, offset, true, measured[used], touching,
                  within ? &reach : nullptr);
    if (!within && !std::isnan(offset)) std::swap(reach, touching), reach_offset = offset;
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
  st.reach_offset = std::numeric_limits<double>::quiet_NaN();
  st.mats.clear();
  const bool layered = st.terrain->tiles.layered();
  bearing_columns_into(st.terrain->tiles, st.terrain->s, st.terrain->palette, envelope, false, 0.0,
                       st.terrain->palette.size() > 1 || layered ? &st.mats : nullptr, layered ? &st.layers : nullptr,
                       st.columns);
  if (!layered) st.layers.clear();
  st.bedrock = terrain::bedrock_offset(st.columns);  // once per reset, not once per solve
}

double BearingSolve::offset(double load) {
  Check{"terrain.BearingSolve.offset"}.non_negative("load", load);
  State& st = state_->ready("terrain.BearingSolve.offset");
  return offset_for_load(
      st.columns, load, [&](double o) { return st.measure(o).capacity; }, st.bedrock);
}

double BearingSolve::offset_under_spring(double load, double spring) {
  const Check check{"terrain.BearingSolve.offset_under_spring"};
  check.non_negative("load", load);
  check.non_negative("spring", spring);
  State& st = state_->ready("terrain.BearingSolve.offset_under_spring");
  // capacity(o) >= load - spring o, the spring's share moved to the soil's side: the sum
  // grows with o as the capacity does, so the plain search finds its one root.
  return offset_for_load(
      st.columns, load, [&](double o) { return st.measure(o).capacity + spring * o; }, st.bedrock);
}

double BearingSolve::offset(double load, const std::function<double(const Bearing&)>& capacity_of) {
  Check{"terrain.BearingSolve.offset"}.non_negative("load", load);
  State& st = state_->ready("terrain.BearingSolve.offset");
  const auto cold = [&] {
    return offset_for_load(
        st.columns, load, [&](double o) { return capacity_of(st.measure(o)); }, st.bedrock);
  };
  const auto g = [&](double o) { return capacity_of(st.measure(o)) - load; };
  if (st.used == 0 || st.columns.empty()) return cold();
  // The bracket from what earlier solves measured: capacity_of grows with the offset, so the
  // deepest offset that falls short and the shallowest that carries bound the answer. A
  // slipping wheel's loosened soil mostly needs the plain solve's answer, or a hair more:
  // it is already bracketed to the tolerance, and nothing new is measured.
  Bracket b{-1.0, kInf};
  double g_lo = 0.0, g_hi = 0.0;
  for (std::size_t k = 0; k < st.used; ++k) {
    const double o = st.offsets[k], gk = capacity_of(st.measured[k]) - load;
    if (gk < 0.0 && o > b.lo) b.lo = o, g_lo = gk;
    if (!(gk < 0.0) && o < b.hi) b.hi = o, g_hi = gk;
  }
  if (b.lo < 0.0) {
    if (b.hi == 0.0) return 0.0;  // the soil carries it untouched
    return cold();
  }
  // Only the untouched soil falls short: no scale to step by, the plain search's bracket.
  if (b.lo == 0.0 && !(b.hi < kInf)) return cold();
  // Past an offset where the plain soil carried its load: a short step first, four times
  // longer each time while it still falls short, within what was measured or up to where
  // every column stands at bedrock (which carries anything).
  for (double step = kFirstStep; b.lo > 0.0 && b.hi - b.lo > 2.0 * step;) {
    const double o = std::min(b.lo + step, st.bedrock), go = g(o);
    if (go < 0.0) {
      if (o >= st.bedrock) return st.bedrock;  // unreachable (bedrock carries anything); kept as a guard
      b.lo = o, g_lo = go, step *= 4.0;
    } else {
      b.hi = o, g_hi = go;
    }
  }
  return illinois_narrow(g, b, g_lo, g_hi, kOffsetTolerance).hi;
}

const Bearing& BearingSolve::bearing(double offset) const {
  const Bearing* b = state_->find(offset);
  if (b == nullptr)
    throw InvalidSetting("terrain.BearingSolve.bearing(offset)", detail::to_text(offset),
                         "must be an offset offset() returned since the last reset");
  return *b;
}

const Bearing& BearingSolve::measure(double offset) {
  if (!(offset >= 0.0) || !std::isfinite(offset))
    throw InvalidSetting("terrain.BearingSolve.measure(offset)", detail::to_text(offset), "must be >= 0 and finite");
  return state_->ready("terrain.BearingSolve.measure").measure(offset);
}

double BearingSolve::deepest() const noexcept {
  const State& st = *state_;
  double most = 0.0;
  for (std::size_t k = 0; k < st.used; ++k) most = std::max(most, st.offsets[k]);
  return most;
}

double BearingSolve::bedrock_offset() const noexcept { return state_->bedrock; }

}  // namespace shore::terrain
