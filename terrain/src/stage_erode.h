#pragma once
// Private: erosion, the last stage of a step and the whole of Terrain::relax (Sumner et al.
// eq. 1-2). Jacobi passes: each pass computes every column's flow from the heights as the
// pass found them, then applies all of it, so threads never change the result.
//
// Choices where the paper leaves room:
// - with a material map, the giver's material sets the limits (theta_in, theta_out,
//   theta_stop) and sigma of its pairs: soil slides by its own law, whatever it slides onto
//   (sand slumping onto gravel keeps sand's angle). The moved soil keeps its material, so
//   volume is conserved per material (stage_erode_layers.cpp): a giver gives only its top
//   layer; what lands on a column of the same top material thickens that layer, and soil
//   of another material becomes a top layer over an unlayered column (one such material
//   per column and pass: the smallest index among its neighbours'); a layered column takes
//   its lower material under its top layer, and soil of a third material not at all. A pair
//   that may not flow is held, like a pair under a body;
// - a pair is too steep when h_ij - h_kl exceeds dist * tan(theta) (theta_in if column kl
//   lies under a body, theta_out otherwise); the column moves sigma times the average
//   EXCESS over that limit, shared equally among its too-steep downhill neighbours, so
//   slopes settle at the threshold instead of below it;
// - contact columns are held by the body: they neither give nor receive;
// - a column under a body but not touching it (the body overhangs) receives at most the
//   room between its top and the collision surface, split over this pass's givers;
// - no column gives more than it holds above bedrock;
// - only interior columns give; the one-column halo around the region only receives;
// - passes repeat while material moves and (unless to_rest) some moving pair is steeper
//   than theta_stop, up to max_erosion_passes (tolerances in ErosionLimits); a pair whose
//   flow is capped by the body above the lower column does not count (the body holds that
//   slope);
// - after the first pass (unless to_rest), only columns within two of a giver that still
//   had such a steep pair in the last pass give: elsewhere every slope is within the stop
//   tolerance and erosion has ended there, as it would in a region of its own. So a slope
//   does not creep on because a steep pair somewhere else shares its active region.
//
// Work per pass follows the columns that changed. A giver's flow depends only on its own
// height and its neighbours' heights and caps (a cap under a body depends on that column's
// neighbours too), so after the first pass only columns whose inputs changed in the last
// pass are evaluated; any other gives exactly what it gave before: nothing.
//
// One pass, part by part:
// - planning (stage_erode_plan.cpp): the limits, who may give, which columns the pass
//   visits, when passes stop and what carries over to the next step;
// - caps (stage_erode_caps.cpp): what each column under a body may receive per giver;
// - shares (stage_erode_shares.cpp): what each giver gives each too-steep neighbour;
// - flow (stage_erode_flow.cpp): every giver and receiver updates its height.

#include <algorithm>
#include <cstddef>
#include <span>
#include <vector>

#include "column_bits.h"
#include "neighbours.h"
#include "region.h"
#include "shore/terrain/terrain.h"

namespace shore::terrain {

/// The slope limits of an erosion, from the settings. Per direction d (kDx, kDy) and kind
/// of lower column c ([0] in the open: theta_out, [1] under a body: theta_in).
struct ErosionLimits {
  double eps = 0.0;               ///< m: smaller moves are ignored
  double thr[8][2] = {};          ///< m: the height difference a pair may keep
  double steep_limit[8][2] = {};  ///< m: what a moving pair must exceed to count as steep
  double give[8][2] = {};         ///< m: thr + eps, the drop a pair must exceed to flow
  double give_in[8] = {};         ///< m: what a giver must exceed toward a column under a body
  /// m, [0] toward the axis neighbours, [1] the diagonal ones: a column less than this above
  /// (least_give_in: below) all its neighbours of that kind can neither give to nor be given
  /// by them, so most columns are dismissed without the pair tests. (Per kind, because a
  /// diagonal pair's limit is sqrt 2 times an axis pair's.)
  double least_give[2] = {}, least_give_in[2] = {};
  double sigma = 0.0;  ///< share of the excess that moves per pass

  /// The limits of soil of material m.
  [[nodiscard]] static ErosionLimits from(const TerrainSettings& s, const Material& m);
};

class ErodeStage {
 public:
  /// Runs the passes on region.ht. flags: ImprintStage::flags; body: the body surface above
  /// each column (ImprintStage::body). to_rest: run until nothing moves (theta_stop
  /// ignored). Returns the number of passes that moved soil.
  /// Each giver moves soil by its own material's limits and sigma (region.mat indexes
  /// palette; empty: palette[0] everywhere), whatever its receivers' materials.
  /// loosens: the step will loosen the deposits after erosion (pipeline.cpp) and has
  /// region.ht_pressed; relax does not. Then settle_layers.
  int run(Region& region, std::span<const unsigned char> flags, std::span<const double> body, const TerrainSettings& s,
          std::span<const Material> palette, bool to_rest, bool loosens = false);
  /// After run (and after the deposits' loosening, which moves sinkage): the columns whose
  /// layering erosion changed, into region.relayered, each layer's boundary from its final
  /// sinkage. Nothing without a map.
  void settle_layers(Region& region) const;
  /// Set by run when it stopped at max_erosion_passes with slopes still too steep: the
  /// bounding box of the last pass's givers that had such a pair (global columns), to carry
  /// on with next step; else nx = 0.
  [[nodiscard]] const GridRect& still_flowing() const { return still_flowing_; }
  [[nodiscard]] std::size_t bytes() const;

 private:
  // planning
  void set_limits(const Region& region, const TerrainSettings& s, std::span<const Material> palette);
  void assign_roles(const Region& region, std::span<const unsigned char> flags);
  void plan_pass(int pass, bool to_rest);
  void find_still_flowing(const Region& region, int passes, int max_passes);
  // caps
  void compute_caps(const Region& region, std::span<const unsigned char> flags, std::span<const double> body);
  template <bool kMap>
  void compute_caps_as(const Region& region, std::span<const unsigned char> flags, std::span<const double> body);
  // shares
  bool compute_shares(const Region& region);
  template <bool kMap>
  bool compute_shares_as(const Region& region);
  // flow
  void mark_receivers(const Region& region);
  void move_soil(Region& region);
  void clear_givers(const Region& region);
  // layers (with a map only: stage_erode_layers.cpp)
  /// Exposes the region's layers (Region::expose_layers: mat becomes each column's exposed
  /// index) and reads each layered column's kind, thickness and lower index.
  void start_layers(Region& region, std::span<const Material> palette, bool loosens);
  /// Whether column j (at x, y), of another top material than m, takes soil of material m
  /// this pass (the rules: stage_erode_layers.cpp). Inline: the shares ask it per pair.
  [[nodiscard]] bool takes(const Region& region, std::size_t j, int x, int y, std::uint8_t m) const;
  /// After move_soil: each changed column's top layer and material (what it gave was its
  /// top layer; what it took, its top material or a new top layer).
  void track_layers(Region& region);

  /// The limits of palette[0], except least_give_in and least_give: the least over the
  /// palette, as a column's cap must count givers of any material and the shares' first
  /// filter passes a giver of any material.
  ErosionLimits lim_;
  std::vector<ErosionLimits> lims_;  ///< per palette entry (used with a map only)
  /// What lim_ and lims_ were computed from (set_limits): a material's erosion fields.
  struct LimitInputs {
    double theta_in = 0.0, theta_out = 0.0, theta_stop = 0.0, sigma = 0.0;
    [[nodiscard]] static LimitInputs of(const Material& m) { return {m.theta_in, m.theta_out, m.theta_stop, m.sigma}; }
    bool operator==(const LimitInputs&) const = default;
  };
  std::vector<LimitInputs> limits_of_;  ///< per entry (one without a map)
  double limits_cell_ = 0.0;
  bool limits_set_ = false, limits_map_ = false;
  // Per column.
  std::vector<double> q_;                ///< a giver's share per too-steep neighbour, m
  std::vector<double> out_;              ///< what a giver gives in all, m
  std::vector<double> cap_;              ///< the most one neighbour may give it: 0 in contact, +inf in the open
  std::vector<unsigned char> mask_;      ///< a giver's too-steep directions (bit d)
  std::vector<unsigned char> cover_;     ///< 1 under a body: selects the limit toward it
  std::vector<unsigned char> row_flow_;  ///< per row: something flows this pass
  // Per column, with a map only: its layering as erosion keeps it (region.mat is the top).
  enum Kind : unsigned char { kUnlayered = 0, kCrust = 1, kBroken = 2 };
  std::vector<unsigned char>
      kind_;                   ///< kUnlayered: one material; kCrust: top layer over lower_; kBroken: lower_ exposed
  std::vector<double> thick_;  ///< kCrust: top layer's thickness, m; kBroken: boundary - sinkage (< 0)
  std::vector<std::uint8_t> lower_;       ///< kCrust, kBroken: the lower index
  std::vector<unsigned char> spent_;      ///< a crust giver gives its whole top layer this pass
  std::vector<unsigned char> rigid_;      ///< per palette entry: rigid (takes any soil as its own)
  std::vector<unsigned char> row_cross_;  ///< per row: a pair of another material or a layer moves soil
  /// Givers whose soil crosses a border or moves a layer this pass (or that are layered):
  /// only they and their receivers can change a layering (track_layers).
  ColumnBits cross_givers_;
  ColumnBits track_;  ///< track_layers' scratch: cross_givers_ and their receivers
  ColumnBits dirty_;  ///< layering changed by this erosion
  struct Retop {
    std::size_t k;
    std::uint8_t top;
  };
  std::vector<Retop> retop_;  ///< track_layers' new top materials, applied after the pass
  bool map_ = false;
  // Column sets.
  ColumnBits givable_;       ///< may give: interior, not in contact
  ColumnBits overhang_;      ///< under a body, not in contact: capped
  ColumnBits cand_;          ///< evaluated this pass
  ColumnBits changed_;       ///< height changed in the last pass
  ColumnBits givers_;        ///< give this pass
  ColumnBits near_;          ///< givers and their receivers (and, planning, what changed)
  ColumnBits recap_;         ///< caps to recompute this pass
  ColumnBits steep_givers_;  ///< givers with a pair steeper than theta_stop
  ColumnBits live_;          ///< planning scratch: steep givers grown by one
  GridRect still_flowing_;
};

inline bool ErodeStage::takes(const Region& region, std::size_t j, int x, int y, std::uint8_t m) const {
  if (kind_[j] == kCrust) return m == lower_[j];  // into its lower layer, under its top one
  if (kind_[j] == kBroken) return false;          // its top is its lower layer: m is a third
  const std::uint8_t own = region.mat[j];
  if (rigid_[own]) return true;
  // The smallest index among its neighbours of another material than its own (in any
  // order: the least is the same).
  unsigned smallest = 256;
  const auto see = [&](std::uint8_t other) {
    if (other != own) smallest = std::min<unsigned>(smallest, other);
  };
  if (x > 0 && y > 0 && x < region.w - 1 && y < region.h - 1) {
    const std::uint8_t* p = region.mat.data() + j;
    const std::ptrdiff_t w = region.w;
    for (const std::ptrdiff_t r : {-w, std::ptrdiff_t{0}, w}) {
      see(p[r - 1]);
      see(p[r + 1]);
      if (r != 0) see(p[r]);
    }
  } else {
    for (int d = 0; d < 8; ++d) {
      const int nx = x + kDx[d], ny = y + kDy[d];
      if (nx < 0 || ny < 0 || nx >= region.w || ny >= region.h) continue;
      see(region.mat[region.at(nx, ny)]);
    }
  }
  return m == smallest;
}

}  // namespace shore::terrain
