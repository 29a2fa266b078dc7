#pragma once
// What a scene holds, for a viewer or a renderer that draws it live: the world, its soils
// and water surfaces with their couplings, where the scene happens, and what a user may
// drive. Scene::contents() returns it (empty by default); pointers stay valid as long as
// the scene.

#include <functional>
#include <vector>

#include "shore/bullet/terrain_coupling.h"
#include "shore/bullet/terrain_tiles.h"
#include "shore/bullet/water_coupling.h"
#include "shore/scenes/height_grid.h"
#include "shore/terrain/terrain.h"
#include "shore/water/surface.h"

class btCollisionObject;
class btRaycastVehicle;

namespace shore::scenes {

class World;

/// A soil, the world rectangle it owns (clipped to the scene's bounds when drawn) and its
/// coupling (null if the scene steps the soil without one).
struct SoilContents {
  terrain::Terrain* soil = nullptr;
  bullet::TerrainCoupling* coupling = nullptr;
  bullet::Region region;  ///< default: everywhere
};

/// A water surface and its coupling (null: none).
struct WaterContents {
  water::Surface* surface = nullptr;
  bullet::WaterCoupling* coupling = nullptr;
};

/// A world rectangle, m: x in [x0, x1], y in [y0, y1].
struct Bounds {
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
  [[nodiscard]] bool empty() const { return !(x1 > x0 && y1 > y0); }
};

/// The rectangle a height grid covers.
inline Bounds bounds_of(const HeightGrid& g) { return {g.x0, g.y0, g.x(g.nx - 1), g.y(g.ny - 1)}; }

struct SceneContents {
  World* world = nullptr;  ///< null: the scene has nothing to show live
  std::vector<SoilContents> soils = {};
  std::vector<WaterContents> waters = {};
  Bounds bounds = {};  ///< where the scene happens: soils are drawn inside it, the camera frames it
  /// What the camera follows (its origin: a rigid body's or a multibody link's centre of
  /// mass; null: the bounds' centre).
  const btCollisionObject* focus = nullptr;
  /// Drives the scene's vehicle: forward and turn in [-1, 1] (0, 0: the scene's own
  /// script). Empty: nothing to drive.
  std::function<void(double forward, double turn)> drive = {};
  /// The scene's substep counter, which its script reads (null: its script keeps no
  /// clock); checkpoints save and restore it (checkpoint.h).
  int* clock = nullptr;
  /// The scene's raycast vehicles, whose wheels' state checkpoints save and restore beside
  /// their chassis (shore/bullet/vehicle_state.h).
  std::vector<btRaycastVehicle*> vehicles = {};
};

}  // namespace shore::scenes
