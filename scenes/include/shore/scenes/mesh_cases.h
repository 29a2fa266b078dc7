#pragma once
// Mesh cases (shore/mesh/chunked_mesh.h): the seed paper's simplified water, the large
// field, and a wheel rolling over soil while a mesh follows it. Shared by the mesh tests
// and shore-bench's mesh sweep.

#include <cstdint>
#include <memory>

#include "shore/mesh/chunked_mesh.h"
#include "shore/terrain/terrain.h"
#include "shore/water/surface.h"

namespace shore::scenes {

/// The seed paper's 50 x 50 surface, triangulated in full: 2 (50 - 1)^2 triangles.
inline constexpr std::size_t kSeedFullTriangles = 4802;

/// The seed paper's water (SurfaceSettings::paper(): 50 x 50 nodes 1 m apart, its
/// lattice, fixed edges) 16 s after a drop: a Gaussian kick of the vertical velocity,
/// 2 m/s, radius 2 m, at the centre, then 40 steps of the paper's 0.4 s. Rings cover most
/// of the pool.
std::unique_ptr<water::Surface> seed_water();

/// The view the paper's figures take of its pool: from beyond the middle of one edge, 20 m
/// out and 20 m up (the whole pool in a 60 degree, 1080-line view, 28 m to 72 m away).
mesh::Camera seed_water_camera();

/// The large field: 1 km x 1 km of 1 cm soil columns over flat ground, with one wheel rut
/// 100 m long along x through the middle, pressed in with Terrain::set_height (a stand-in
/// for a vehicle's drive with the same structure: touched tiles along the rut, untouched
/// ground elsewhere). The rut: 25 cm wide, 3 cm deep, rounded walls, 1 cm berms each side
/// out to 20 cm, a 2 mm tread pattern every 5 cm and 0.5 mm of deterministic roughness.
struct LargeField {
  std::unique_ptr<terrain::Terrain> soil;
  shore::GridRect region;                          ///< the 1 km x 1 km of columns (100001 x 100001)
  double rut_x0 = 0.0, rut_x1 = 0.0, rut_y = 0.0;  ///< m, where the rut runs
};
LargeField large_field(double side_m = 1000.0, double rut_m = 100.0);

/// 2 m above the middle of the rut, 60 degrees, 1080 lines.
mesh::Camera large_field_camera(const LargeField& f);

/// A wheel (D 0.6 m, 25 cm wide) towed along x over a soil 3 cm deep at `speed`, one
/// Terrain::step per substep (no Bullet): what a mesh of driven-over ground must follow.
class RollingWheel {
 public:
  RollingWheel(terrain::Terrain& soil, double x0, double y, double speed = 2.0, double substep = 1.0 / 240.0);
  void step();
  [[nodiscard]] double x() const noexcept { return x_; }
  [[nodiscard]] double y() const noexcept { return y_; }

 private:
  terrain::Terrain* soil_;
  double x_, y_, speed_, substep_;
};

}  // namespace shore::scenes
