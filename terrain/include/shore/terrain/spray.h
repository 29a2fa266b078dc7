#pragma once
// Spray: soil that fast bodies throw into the air and that lands where it falls (Sumner,
// O'Brien & Hodgins 1998, "Particle generation"). Where a body touches the soil, each
// piece of its surface picks up a layer of soil (area x adhesion); once that piece has left
// the ground, the soil drops off it with a half-life, as particles that start at the piece
// with its velocity v + w x r (plus jitter), fly ballistically under gravity (with an
// optional linear air drag) and add their volume to the column they land on. A candidate
// particle only flies where (|v + w x r| / s)^gamma beats a uniform random number; the
// others drop straight onto the column below, as clumps. docs/terrain.md, "Spray", gives
// the model as built and the choices made where the paper is silent.
//
// The material's parameters are in SprayMaterial (Material::spray; on a painted terrain
// each clinging piece and particle goes by the palette entry it was picked up from), the
// terrain's switch, limits and random seed in SpraySettings (TerrainSettings::spray); each
// body's velocity, angular velocity, pose and key come with its Imprint (terrain.h).

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>

#include "shore/core/vec3.h"

namespace shore {
struct Check;
}

namespace shore::terrain {

/// How a material sprays. Units at each field; presets in Material::sand(), mud(), snow().
struct SprayMaterial {
  /// m: soil a body's surface picks up per m^2 of contact (Sumner's adhesion constant; the
  /// picked-up volume is area x adhesion). >= 0; 0: the material never sprays.
  double adhesion = 0.001;
  /// s, > 0: once a piece of surface has left the ground, half of its soil has dropped off
  /// after this long (Sumner's half life h).
  double half_life = 0.04;
  /// m/s, > 0: Sumner's s, the speed at and above which every candidate particle flies.
  double speed_scale = 2.5;
  /// > 0: Sumner's gamma; a candidate flies where (speed / speed_scale)^gamma exceeds a
  /// uniform random number in [0, 1).
  double exponent = 2.0;
  /// m, > 0: diameter of one particle (its volume pi d^3 / 6 is Sumner's 1 / phi).
  double particle_size = 0.004;
  /// m/s, >= 0: a piece of surface moving slower than this over the soil picks nothing up,
  /// and soil clinging to a piece that touches the soil this slowly is set back down: bodies
  /// at rest or creeping make no particles and hold no spray memory.
  double min_speed = 0.3;
  /// In [0, 1]: each velocity component of a new particle is perturbed by up to this share
  /// of its speed (uniformly), Sumner's random perturbation.
  double jitter = 0.2;
  /// 1/s, >= 0: linear air drag, dv/dt = g - drag v (terminal speed g / drag); 0: none.
  double drag = 0.6;

  /// Throws shore::InvalidSetting naming the field (prefix: the material's name).
  void validate(const Check& c) const;
  /// m^3: the volume of one particle, pi d^3 / 6.
  [[nodiscard]] double particle_volume() const;
};

/// The terrain's spray switch and limits (TerrainSettings::spray).
struct SpraySettings {
  /// Spray on for this terrain (each body also has Imprint::spray). Steps without a time
  /// step (Terrain::step(imprints), dt = 0) never spray.
  bool enabled = true;
  /// Particles in flight at most, >= 0. A particle that would exceed it is not made: its
  /// volume is laid at once on the column below where it would have started (counted in
  /// SprayCounts::limited). 0: soil is still picked up and shed, but never flies.
  int max_particles = 50000;
  std::uint64_t seed = 0x5eed5a17u;  ///< keys the counter-based random numbers
  double gravity = 9.81;             ///< m/s^2, > 0, along -z
  /// m: the region the particles live in (the terrain's own: where its soil is). A particle
  /// whose path leaves it is lost: its volume is counted in VolumeTotals::lost. Defaults:
  /// everywhere. x_min < x_max, y_min < y_max (infinite allowed).
  double x_min = -std::numeric_limits<double>::infinity();
  double x_max = std::numeric_limits<double>::infinity();
  double y_min = -std::numeric_limits<double>::infinity();
  double y_max = std::numeric_limits<double>::infinity();
  /// s, > 0: a particle still in flight after this long has left the world (lost).
  double max_flight = 10.0;

  /// Throws shore::InvalidSetting naming the field.
  void validate(const Check& c) const;
};

/// One particle in flight, for drawing.
struct SprayParticle {
  Vec3 position;        ///< m, its centre
  double radius = 0.0;  ///< m, of the sphere of its volume
  double volume = 0.0;  ///< m^3
  Vec3 velocity;        ///< m/s (motion blur, streaks)
  int material = 0;     ///< its palette index (Terrain::palette): the soil it flies and lands as
};

/// What spray has done since the terrain was made (totals) and holds now.
struct SprayCounts {
  std::int64_t particles = 0;       ///< in flight now
  std::int64_t clinging_cells = 0;  ///< pieces of body surface holding soil now
  std::int64_t created = 0;         ///< particles made
  std::int64_t landed = 0;          ///< particles that landed on a column
  std::int64_t lost = 0;            ///< particles that left the region or the world
  std::int64_t clumps = 0;          ///< candidates too slow to fly, dropped onto the column below
  std::int64_t limited = 0;         ///< candidates laid at once because max_particles was reached
  /// Pieces of surface whose soil was set back down at once: touching the soil slower than
  /// min_speed, loading from a column of another material (a piece holds one), or their
  /// body gone from the step's imprints (at rest, removed, spray off).
  std::int64_t set_down = 0;
  double picked_volume = 0.0;  ///< m^3 picked up by bodies, in all
  std::size_t bytes = 0;       ///< memory spray holds now (particles, clinging soil, scratch)
};

}  // namespace shore::terrain
