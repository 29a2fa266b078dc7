// Rigid columns on deforming ground: a palette entry with rigid = true (a road, a rock)
// painted on a sand terrain. Its columns carry any load without sinking (bedrock at their
// untouched top), are never pressed, carried off or eroded below that top, and take loose
// soil on top like any ground; the sand beside them keeps Bekker's law; volume is conserved.

#include <gtest/gtest.h>

#include <cmath>

#include "shore/core/error.h"
#include "shore/terrain/bekker.h"
#include "terrain_fixtures.h"

namespace shore::terrain {
namespace {

using testing::box_envelope;

constexpr int kPlate = 15;  // columns: a 0.3 m plate on 2 cm columns

Material road() {
  Material m = Material::rigid_ground();
  m.name = "road";
  m.soil_depth = Material::sand().soil_depth;  // every entry shares the soil depth
  return m;
}

/// Sand on 2 cm columns, a road painted over i in [0, 40), every j.
Terrain road_beside_sand() {
  Terrain t(testing::coarse_sand());
  t.set_palette({Material::sand(), road()});
  t.paint_rect({0, -40, 40, 120}, 1);
  return t;
}

TEST(RigidColumns, ARoadCarriesAnyLoadAndSandBesideItBekkers) {
  Terrain t = road_beside_sand();
  const double width = kPlate * t.settings().cell, p = 50e3, load = p * width * width;
  EXPECT_EQ(t.bedrock(10, 10), t.base_height(10, 10));
  EXPECT_EQ(t.bedrock(60, 10), t.base_height(60, 10) - Material::sand().soil_depth);
  // On the road: no sinkage for any load (Bekker's k -> infinity).
  for (const double w : {load, 100.0 * load})
    EXPECT_EQ(t.bearing_offset(box_envelope(10, 10, kPlate, kPlate, 0.0), w), 0.0);
  // On the sand beside it: Bekker's plate sinkage.
  const double z = t.bearing_offset(box_envelope(60, 10, kPlate, kPlate, 0.0), load);
  EXPECT_NEAR(z, bekker::plate_sinkage(Material::sand(), width, p), 1e-3 * z);
}

TEST(RigidColumns, APressAcrossTheRoadEdgeLeavesTheRoadAndConservesVolume) {
  Terrain t = road_beside_sand();
  // A 0.4 m box pressed 3 cm into the ground across the edge (i 30 to 50).
  for (int k = 1; k <= 10; ++k) {
    const EnvelopeRaster env = box_envelope(30, 10, 20, 20, -0.003 * k);
    const Imprint im{&env};
    t.step({&im, 1});
  }
  double lowest_road = 1.0, pressed_sand = 0.0;
  for (std::int64_t j = 0; j < 40; ++j)
    for (std::int64_t i = 20; i < 60; ++i) {
      if (i < 40) lowest_road = std::min(lowest_road, t.height(i, j) - t.base_height(i, j));
      if (i >= 40 && i < 50 && j >= 10 && j < 30) pressed_sand = std::max(pressed_sand, -t.height(i, j));
    }
  EXPECT_GE(lowest_road, 0.0) << "a road column was pressed or carried below its top";
  for (std::int64_t j = 10; j < 30; ++j)
    for (std::int64_t i = 30; i < 40; ++i) EXPECT_GE(t.height(i, j), 0.0) << i << ", " << j;
  EXPECT_NEAR(pressed_sand, 0.03, 1e-12) << "the sand under the box is pressed to it";
  const VolumeTotals v = t.volume();
  EXPECT_NEAR(v.ground + v.compacted, 0.0, 1e-15) << "ground " << v.ground << ", compacted " << v.compacted;
}

TEST(RigidColumns, SandSlumpsOntoTheRoadButNeverErodesIt) {
  Terrain t = road_beside_sand();
  // A sand bank 10 cm high beside the road (i 40 to 45), relaxed to rest.
  for (std::int64_t j = 0; j < 20; ++j)
    for (std::int64_t i = 40; i < 45; ++i) t.set_height(i, j, 0.1);
  const double added = t.volume().edited;
  // And a cut into the road's edge region: heights set below the road's top are raised to it.
  t.set_height(38, 5, -0.05);
  EXPECT_EQ(t.height(38, 5), t.base_height(38, 5));
  for (int k = 0; k < 20; ++k) t.relax({20, -10, 40, 40});
  double on_road = 0.0, lowest_road = 1.0;
  for (std::int64_t j = -10; j < 30; ++j)
    for (std::int64_t i = 20; i < 40; ++i) {
      on_road += t.height(i, j) - t.base_height(i, j);
      lowest_road = std::min(lowest_road, t.height(i, j) - t.base_height(i, j));
    }
  EXPECT_GT(on_road, 0.0) << "the bank slumped onto the road";
  EXPECT_GE(lowest_road, 0.0);
  EXPECT_NEAR(t.volume().ground, added, 1e-15);
}

TEST(RigidColumns, OnlyEntriesAfterTheFirstMayBeRigidAndOnlyOnDeformingGround) {
  Terrain sand(testing::coarse_sand());
  try {
    sand.set_palette({road(), Material::sand()});
    ADD_FAILURE() << "a rigid entry 0 on deforming ground";
  } catch (const InvalidSetting& e) {
    EXPECT_EQ(e.field(), "terrain.Terrain.set_palette[0].rigid");
  }
  TerrainSettings s = testing::coarse_sand();
  s.material = road();
  Terrain rigid(s);
  try {
    rigid.set_palette({road(), Material::sand()});
    ADD_FAILURE() << "a soft entry on rigid ground";
  } catch (const InvalidSetting& e) {
    EXPECT_EQ(e.field(), "terrain.Terrain.set_palette[1].rigid");
  }
  EXPECT_EQ(sand.palette().size(), 1u);
  EXPECT_EQ(rigid.palette().size(), 1u);
}

}  // namespace
}  // namespace shore::terrain
