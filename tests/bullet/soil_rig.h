#pragma once
// A Bullet world over flat soil of one material (2 cm cells, one thread) with its coupling:
// the rig of the raycast-wheel tests.

#include "shore/bullet/terrain_coupling.h"
#include "shore/scenes/world.h"
#include "shore/terrain/terrain.h"

struct SoilRig {
  explicit SoilRig(const shore::terrain::Material& m) : soil(settings(m)), coupling(world.world(), soil) {}
  static shore::terrain::TerrainSettings settings(const shore::terrain::Material& m) {
    shore::terrain::TerrainSettings s;
    s.cell = 0.02;
    s.material = m;
    s.threads = 1;
    return s;
  }
  shore::scenes::World world;
  shore::terrain::Terrain soil;
  shore::bullet::TerrainCoupling coupling;
};
