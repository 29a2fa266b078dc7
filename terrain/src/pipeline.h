#pragma once
// Private: one step's work on one active region, stage after stage:
//   gather      the region plus a one-column halo, from the tiles   (region.h)
//   imprint     rasterize the envelopes, collide                     (stage_imprint.h)
//   contour     distance from each contact column to open soil       (stage_contour.h)
//   displace    carry the displaced soil down the contour levels     (stage_displace.h)
//   erode       Jacobi passes on too-steep slopes                    (stage_erode.h)
//   loosen      soil laid on a column lowers its recorded sinkage
//   scatter     back into the tiles, marking what changed            (region.h)
// Each stage owns its scratch arrays and reads the others' results by const reference.
// Rows of the parallel stages run on the pipeline's own team (shore/core/team.h, created at
// the first region that forks) when the region has at least parallel_min_columns columns
// and the pacer measures parallel steps faster than serial ones.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "region.h"
#include "shore/core/pacer.h"
#include "shore/core/team.h"
#include "shore/terrain/terrain.h"
#include "stage_contour.h"
#include "stage_displace.h"
#include "stage_erode.h"
#include "stage_imprint.h"
#include "tile_store.h"

namespace shore::terrain {

class Pipeline {
 public:
  /// One step over `region` (halo excluded) for all imprints.
  /// palette: the terrain's materials (Terrain::palette; entry 0 is s.material).
  StepReport run(TileStore& store, const TerrainSettings& s, std::span<const Material> palette, const GridRect& region,
                 std::span<const Imprint> imprints);
  /// Erosion alone, to rest, over `region` (Terrain::relax).
  StepReport relax(TileStore& store, const TerrainSettings& s, std::span<const Material> palette,
                   const GridRect& region);
  /// After run or relax: the slopes the pass cap left too steep (ErodeStage::still_flowing).
  [[nodiscard]] const GridRect& still_flowing() const { return erode_.still_flowing(); }
  [[nodiscard]] std::size_t bytes() const;

 private:
  /// Gathers the region (plus halo) and decides whether its rows fork onto the team.
  void gather(TileStore& store, const TerrainSettings& s, std::span<const Material> palette, const GridRect& region);
  /// After a step or relax of `columns`: tells the pacer how long it took.
  void record(const TerrainSettings& s, std::int64_t columns, double seconds);

  std::unique_ptr<Team> team_;
  Pacer pacer_;  ///< per column of the region (halo included), over whole steps
  Region region_;
  std::vector<double> alpha_;  ///< per palette entry
  ImprintStage imprint_;
  ContourStage contour_;
  DisplaceStage displace_;
  ErodeStage erode_;
};

}  // namespace shore::terrain
