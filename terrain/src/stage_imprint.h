#pragma once
// Private: the first stage of a step. The imprints' envelopes are rasterized into the
// region, then every column whose top lies above the collision surface is pushed down to it
// (collision).

#include <cstddef>
#include <span>
#include <vector>

#include "region.h"
#include "shore/terrain/terrain.h"

namespace shore::terrain {

/// What collision found for a region column (ImprintStage::flags). A halo column carries
/// at most kHaloCovered.
enum : unsigned char {
  kInterior = 1,     ///< not in the halo: its 8 neighbours exist
  kCovered = 2,      ///< under a body: a body lies within active_reach above it (or touches it)
  kContact = 4,      ///< touched: a body lies within contact_tolerance of its top
  kHaloCovered = 8,  ///< a halo column under a body (as kCovered): it receives no soil
};

class ImprintStage {
 public:
  struct Collision {
    double displaced = 0.0;  ///< m: sum of how far the columns were pushed down
    int contacts = 0;        ///< columns pressed (held columns not counted)
  };

  /// The lowest (offset) envelope of each kind of imprint over the region.
  void rasterize(const Region& region, std::span<const Imprint> imprints);
  /// Pushes the columns down to the collision surface and grows their sinkage; sets the
  /// flags, the displaced heights, the body surface and region.ht_pressed (every column's
  /// height after collision, halo included).
  Collision collide(Region& region, const TerrainSettings& s);
  /// Flags the halo columns under a body (kHaloCovered).
  void flag_covered_halo(const Region& region, const TerrainSettings& s);
  /// The outcome of a step without bodies (relax): nothing covered, nothing displaced.
  void no_bodies(const Region& region);

  /// Per column: the lowest body surface above it, pressing or holding (+inf: none).
  [[nodiscard]] std::span<const double> body() const { return coll_; }
  /// Per interior column: how far collision pushed it down, m.
  [[nodiscard]] std::span<const double> displaced() const { return disp_; }
  [[nodiscard]] std::span<const unsigned char> flags() const { return flags_; }
  [[nodiscard]] std::size_t bytes() const;

 private:
  void lower_star_neighbourhoods(const Region& region);

  std::vector<double> plain_;     ///< plain pressing imprints
  std::vector<double> star_;      ///< star pressing imprints
  std::vector<double> star_low_;  ///< star envelope, lowest within +-1 column along x
  std::vector<double> true_;      ///< lowest pressing envelope (only with stars_; else coll_'s)
  std::vector<double> coll_;      ///< collision surface; after collide, the body surface
  std::vector<double> hold_;      ///< holding imprints (press nothing)
  std::vector<double> disp_;
  std::vector<unsigned char> flags_;
  bool stars_ = false;  ///< the last rasterize had star pressing imprints
  std::vector<double> row_volume_;
  std::vector<int> row_contacts_;
};

}  // namespace shore::terrain
