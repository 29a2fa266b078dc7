#pragma once
// The bearing of one envelope solved for several loads in turn (a raycast wheel's
// suspension load, then the larger load its slipping, loosened soil feels). The columns the
// envelope covers are read once, and every capacity the solves find is kept with its
// per-column forces, so a later load re-measures none of the offsets an earlier one
// measured and brackets its answer from them, and the answer's Bearing is the one the
// solve measured last, not a fresh one. The plain solve's results are bit-identical to
// Terrain::bearing_offset(envelope, load) and Terrain::bearing(envelope, that offset).

#include <functional>
#include <memory>

#include "shore/core/envelope.h"
#include "shore/terrain/terrain.h"

namespace shore::terrain {

class BearingSolve {
 public:
  BearingSolve();
  ~BearingSolve();
  BearingSolve(BearingSolve&&) noexcept;
  BearingSolve& operator=(BearingSolve&&) noexcept;

  /// Reads the columns `envelope` covers on `terrain` and forgets earlier loads (its
  /// buffers are kept for the next envelope). The terrain must outlive the solves and stay
  /// unchanged until the next reset. Throws InvalidSetting on a bad envelope, like
  /// Terrain::bearing_offset.
  void reset(const Terrain& terrain, const EnvelopeRaster& envelope);
  /// The offset (m, >= 0) at which the soil carries `load` (N, >= 0): exactly
  /// Terrain::bearing_offset's. Throws InvalidSetting on a negative or NaN load, or before
  /// the first reset.
  [[nodiscard]] double offset(double load);
  /// The same search, the soil's capacity at each offset measured taken as
  /// `capacity_of(bearing(offset))` (N, growing with the offset as the plain capacity does):
  /// the caller's share of each column's force, as a slipping wheel's loosened soil. The
  /// offsets earlier solves measured are not measured again: the deepest that falls short
  /// and the shallowest that carries are the first bracket (steps of 10 um, growing
  /// fourfold, past the deepest where none carries), narrowed to 1e-7 m like the plain
  /// solve's. Before any plain solve since the reset, the plain solve's search.
  [[nodiscard]] double offset(double load, const std::function<double(const Bearing&)>& capacity_of);
  /// The offset (m, >= 0) at which the soil carries a load that eases as the envelope
  /// sinks: `load - spring * offset` (N; load >= 0 N, spring >= 0 N/m), an envelope held
  /// on a spring that relaxes as it sinks (a raycast wheel raised above its ray's hit: its
  /// suspension gives the less the deeper it sinks back). capacity(o) + spring o grows with
  /// o, so it reaches `load` at one offset: the plain solve's search on that sum (bracket
  /// from 1 mm, doubled up to bedrock_offset(), narrowed to 1e-7 m), the end that carries
  /// returned: capacity >= load - spring * offset there. One search, where searching the
  /// load with offset() nested would solve once for every load it tries. Offsets measured
  /// since the reset are not measured again. With spring 0 exactly offset(load). Throws
  /// InvalidSetting on a negative or NaN load or spring, or before the first reset.
  [[nodiscard]] double offset_under_spring(double load, double spring);
  /// What the soil bears with the envelope lowered by an offset offset() or
  /// offset_under_spring() returned since the last reset: exactly Terrain::bearing(envelope,
  /// offset). Valid until the next solve or reset(). Throws InvalidSetting for an offset no
  /// solve measured.
  [[nodiscard]] const Bearing& bearing(double offset) const;
  /// What the soil bears with the envelope lowered by `offset` (m, >= 0 and finite), measured
  /// now if no solve since the last reset measured it: exactly Terrain::bearing(envelope,
  /// offset). For a caller that stops short of a solve's answer (a raycast wheel whose ray
  /// reaches no deeper). Valid until the next solve, measure or reset(). Throws
  /// InvalidSetting for a bad offset, or before the first reset.
  [[nodiscard]] const Bearing& measure(double offset);
  /// The largest offset (m) measured since the last reset (0 before any solve).
  [[nodiscard]] double deepest() const noexcept;
  /// The offset (m) at which every covered column stands at bedrock, where the solve's
  /// bracket stops growing (0 if the envelope covers no column). A solve whose deepest()
  /// stays below it measured the same offsets as on any envelope holding these columns and
  /// more that touch at none of them, and answered the same.
  [[nodiscard]] double bedrock_offset() const noexcept;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace shore::terrain
