// An outside project: uses each of the libraries through the installed package.
#include <cstdio>

#include <shore/bullet/config.h>
#include <shore/bullet/heightfield_tile.h>
#include <shore/mesh/chunked_mesh.h>
#include <shore/terrain/bekker.h>
#include <shore/terrain/mesh_field.h>
#include <shore/water/parameters.h>

int main() {
  const double z = shore::terrain::bekker::plate_sinkage(shore::terrain::Material::sand(), 0.3, 50e3);
  shore::water::PhysicalParameters water;
  const double cw = water.to_lattice().wave_speed();
  shore::bullet::HeightfieldTile tile(shore::bullet::HeightfieldTileSettings{});
  const bool precision_ok = shore::bullet::built_with_double_precision() == (sizeof(btScalar) == 8);
  shore::terrain::Terrain soil{shore::terrain::TerrainSettings{}};  // flat: its mesh is two triangles
  shore::terrain::TerrainField ground(soil, {0, 0, 100, 100});
  shore::mesh::ChunkedMesh mesh;
  const std::size_t triangles = mesh.update(ground).triangles;
  std::printf("plate sinkage %.4f m, wave speed %.3f m/s, tile %d columns, flat mesh %zu triangles, precision %s\n", z,
              cw, tile.columns(), triangles, precision_ok ? "ok" : "MISMATCH");
  return (z > 0.04 && z < 0.05 && cw > 2.0 && triangles == 2 && precision_ok) ? 0 : 1;
}
