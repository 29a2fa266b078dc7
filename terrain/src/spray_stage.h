#pragma once
// Private: the spray stage of a step, after the pipeline has pressed, displaced and eroded
// the soil (Terrain::step):
//   fly       particles in flight move on by dt; those that land add their volume to the
//             column they land on, those that leave the region or the world are lost;
//   cling     each spraying body, in the order of its key, picks soil up, sets it down and
//             sheds it (spray_cling.h); soil of bodies gone from the step is set down;
//   throw     each shed candidate flies if (speed / s)^gamma beats its random number and
//             max_particles allows (else it drops onto the column below, counted), starting
//             at its own time within the step.
// Serial, in fixed orders: particles oldest first, bodies by key, pieces by key.

#include <cstddef>
#include <span>
#include <utility>
#include <vector>

#include "shore/terrain/terrain.h"
#include "spray_cling.h"
#include "spray_flight.h"
#include "spray_state.h"
#include "spray_tops.h"
#include "tile_store.h"

namespace shore::terrain {

class Spray {
 public:
  /// One step of dt seconds (> 0) with these imprints (already checked).
  void step(TileStore& store, const TerrainSettings& s, std::span<const Material> palette,
            std::span<const Imprint> imprints, double dt, StepReport& report);
  [[nodiscard]] std::size_t bytes() const;

  SprayState state;

 private:
  void fly_all(SprayGround& ground, const FlightRules& rules, double dt, StepReport& report);
  /// The particles' flights, with (kMap) or without their palette indices.
  template <bool kMap>
  void fly_each(SprayGround& ground, const FlightRules& rules, double dt, StepReport& report);
  /// Gives the ground the box the particles in flight can reach this step.
  void cover_flights(SprayGround& ground, double dt) const;
  void cling_all(SprayGround& ground, const TerrainSettings& s, std::span<const Material> palette,
                 const FlightRules& rules, std::span<const Imprint> imprints, double dt, StepReport& report);
  void set_gone_down(SprayGround& ground, const ClingingBody& body);
  /// This step's rules over `elapsed` (> 1) steps of dt, made once a step for each count
  /// asked (a body's first clinging step after skipped ones).
  const ClingRules& rules_over(const TerrainSettings& s, std::span<const Material> palette, double dt,
                               std::int64_t elapsed);
  /// Candidates and drops of one body, in order.
  void settle(SprayGround& ground, const TerrainSettings& s, std::span<const Material> palette,
              const FlightRules& rules, StepReport& report);
  /// The flight rules and clocks of the palette's entries (none for one material), and the
  /// particles' indices kept in step with the palette.
  void set_materials(const TerrainSettings& s, std::span<const Material> palette);
  /// The flight rules of a particle of this palette index (`one`: entry 0's, for one material).
  [[nodiscard]] const FlightRules& flight_rules(const FlightRules& one, std::uint8_t index) const {
    return flight_by_index_.empty() ? one : flight_by_index_[index];
  }
  /// Soil straight down onto the column below a point (lost outside the region).
  void drop(SprayGround& ground, const Drop& d);
  void land(SprayGround& ground, const Particle& p, const FlightEnd& end, StepReport& report);

  Cling cling_;
  SampleClock clock_;  ///< drag factors of the particles flying whole steps
  /// A map's: per palette index, its particles' flight rules and sample clock (empty: one
  /// material, `clock_`).
  std::vector<FlightRules> flight_by_index_;
  std::vector<SampleClock> clocks_;
  UntiledTops untiled_tops_;  ///< bounds of blocks no tile covers (derived, kept across steps)
  TiledTops tiled_tops_;      ///< bounds of blocks in one tile, while it does not change (derived)
  Shed shed_;                 ///< one body's candidates, between its cling step and settle
  std::vector<Drop> drops_;
  std::vector<std::size_t> order_;
  std::vector<ClingingBody> next_bodies_;
  /// This step's rules by elapsed step count (rules_over): a few counts at most.
  std::vector<std::pair<std::int64_t, ClingRules>> rules_over_;
};

}  // namespace shore::terrain
