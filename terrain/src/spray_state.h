#pragma once
// Private: what spray keeps from step to step (saved, loaded and hashed): the particles in
// flight and the soil clinging to bodies, in fixed orders, and the totals.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "shore/core/hash.h"
#include "shore/core/vec3.h"
#include "shore/terrain/spray.h"

namespace shore::terrain {

/// One particle in flight, as it is at the end of the last step.
struct Particle {
  Vec3 position;        ///< m
  Vec3 velocity;        ///< m/s
  double volume = 0.0;  ///< m^3
  double age = 0.0;     ///< s in flight
};

/// Soil clinging to one piece of a body's surface: a cube of one column's side in the
/// body's frame.
struct ClingCell {
  std::uint64_t key = 0;  ///< the cube, packed (cling_key)
  Vec3 local{};           ///< m, body frame: where it last touched the soil
  double volume = 0.0;    ///< m^3 clinging
  /// m^3 of it the half-life says has dropped off but that has not yet made a whole
  /// particle (shed as soon as it does).
  double owed = 0.0;
  /// m^3 the piece will carry away from the column it last touched when it leaves the
  /// ground (adhesion x area, less what it still holds): soil under a body that is still
  /// pressing stays where it bears the body.
  double pending = 0.0;
  std::int64_t i = 0, j = 0;  ///< the column it last touched
  std::int64_t touched = -1;  ///< the spray step it last touched the soil in, moving fast enough
  /// The palette index of the soil it holds (a piece holds one material: the column's it
  /// last loaded from); 0 on a terrain with one material.
  std::uint8_t material = 0;
};

/// The soil clinging to one body, and where and when the body was last seen.
struct ClingingBody {
  std::uint64_t key = 0;         ///< Imprint::key
  std::vector<ClingCell> cells;  ///< sorted by key
  Vec3 centre;                   ///< m, its centre at the last step
  Quat orientation;              ///< then
  /// The spray step its soil was last stepped on: its next step covers (step - stepped)
  /// steps' time, whatever cadence (Imprint::cling_every) it had in between. Always below
  /// SprayState::step. A body loaded from a file that did not keep it (terrain state before
  /// version 9, soil delta before version 6) takes step - 1, as a body at cadence 1 always
  /// has; one such a file caught between the two steps of cadence 2 then sheds one step's
  /// share too little, once (those versions stepped it over cadence x dt on its step).
  std::int64_t stepped = -1;
  /// Whether `stepped` says more than step - 1, the step just done (which a body at cadence 1
  /// always has): only then is it hashed, and only a state holding such a body is saved in
  /// the layout that carries every body's `stepped`, so states without one keep their bytes
  /// and hashes.
  [[nodiscard]] bool between_steps(std::int64_t step) const { return stepped != step - 1; }
};

struct SprayState {
  std::vector<Particle> particles;  ///< in flight, oldest first
  /// The palette index of each particle (the material it flies and lands as), in the order
  /// of `particles`; empty: every particle is entry 0's. Kept apart from Particle so that a
  /// terrain with one material (which never fills it) moves the particles it always moved.
  std::vector<std::uint8_t> particle_materials;
  std::vector<ClingingBody> bodies;  ///< sorted by key
  std::int64_t step = 0;             ///< steps with a time step so far (keys the random numbers)
  double lost = 0.0;                 ///< m^3 that left the region or the world
  SprayCounts counts;                ///< totals (particles and clinging_cells filled on demand)

  /// m^3 in flight and clinging, summed in their fixed order.
  [[nodiscard]] double in_flight() const;
  [[nodiscard]] double clinging() const;
  [[nodiscard]] std::int64_t cell_count() const;
  /// The largest palette index a particle or a clinging piece holds (0 if none).
  [[nodiscard]] int largest_material() const;
  /// Whether some particle or piece holds a palette index other than 0.
  [[nodiscard]] bool has_materials() const { return largest_material() > 0; }
  /// Whether some body's soil was last stepped before the step just done (a body between
  /// the two clinging steps of a cadence above 1): the state needs each body's `stepped`.
  [[nodiscard]] bool has_bodies_between_steps() const;
  void hash_into(StateHash& h) const;
  [[nodiscard]] std::size_t bytes() const;
};

}  // namespace shore::terrain
