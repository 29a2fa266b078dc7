// Rigid columns through the Bullet coupling: a plate released on a road (a rigid palette
// entry) painted on sand rests on the road's surface, where on the sand alone it sinks by
// Bekker's law; nothing is rescued from below bedrock.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "shore/scenes/soil_cases.h"
#include "shore/terrain/terrain.h"

using namespace shore;
using namespace shore::scenes;

namespace {

terrain::Material road() {
  terrain::Material m = terrain::Material::rigid_ground();
  m.name = "road";
  m.soil_depth = terrain::Material::sand().soil_depth;
  return m;
}

PlateResult plate(bool on_road) {
  PlateCase c;
  c.settle_seconds = 0.5;
  if (on_road)
    c.run.prepare = [](terrain::Terrain& soil) {
      soil.set_palette({soil.settings().material, road()});
      soil.paint_rect({-200, -200, 400, 400}, 1);
    };
  return run_plate(c);
}

TEST(RigidColumns, APlateRestsOnARoadPaintedOnSand) {
  const PlateResult sand = plate(false), on_road = plate(true);
  std::printf("plate at 50 kPa: %.3f mm on sand (Bekker %.3f), %.4f mm on the road\n", 1e3 * sand.sinkage,
              1e3 * sand.reference, 1e3 * on_road.sinkage);
  ASSERT_GT(sand.sinkage, 0.01) << "the plate barely sank into sand: this tests nothing";
  EXPECT_LT(std::abs(on_road.sinkage), 1e-3) << "the plate sank into the road";
  EXPECT_EQ(on_road.stats.rescues, 0);
  EXPECT_EQ(sand.stats.rescues, 0);
}

}  // namespace
