#include "shore/scenes/checkpoint.h"

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <BulletDynamics/Featherstone/btMultiBody.h>

#include "shore/bullet/body_state.h"
#include "shore/bullet/terrain_coupling.h"
#include "shore/bullet/vehicle_state.h"
#include "shore/bullet/water_coupling.h"
#include "shore/core/byte_io.h"
#include "shore/core/error.h"
#include "shore/scenes/contents.h"
#include "shore/scenes/multibody_state.h"
#include "shore/scenes/world.h"
#include "shore/terrain/terrain.h"
#include "shore/water/surface.h"

namespace shore::scenes {
namespace {

/// TERRAIN, TERRAIN1, ...: the k-th part of a kind.
std::string tag(const char* kind, std::size_t k) { return k == 0 ? kind : kind + std::to_string(k); }

SceneContents contents_with_world(Scene& scene) {
  SceneContents c = scene.contents();
  if (c.world == nullptr)
    throw InvalidSetting("scenes.save_checkpoint(scene).contents().world", "null",
                         "the scene must show its world to be checkpointed");
  return c;
}

/// MBODIES: every multibody's values, each as put_array (none in a rigid world: no section).
std::vector<unsigned char> save_multibodies(const World& world) {
  ByteWriter w;
  for (const btMultiBody* m : world.multibodies()) w.put_array(multibody_state(*m));
  return std::move(w.bytes);
}

/// Reads all of MBODIES before changing anything: FileError for a count that does not
/// match the world's multibodies or a state no simulation has (multibody_state_problem).
void restore_multibodies(World& world, std::span<const unsigned char> bytes, const std::string& source) {
  ByteReader r(bytes, source);
  std::vector<std::vector<btScalar>> all;
  for (const btMultiBody* m : world.multibodies()) {
    all.emplace_back();
    r.get_array(all.back(), multibody_state(*m).size(), "a multibody's state");
    if (const std::string problem = bullet::multibody_state_problem(*m, all.back()); !problem.empty())
      r.fail("multibody " + std::to_string(all.size() - 1) + ": " + problem);
  }
  if (r.remaining() != 0) r.fail("holds more multibodies than the scene's world");
  for (std::size_t k = 0; k < all.size(); ++k) set_multibody_state(*world.multibodies()[k], all[k]);
}

}  // namespace

CheckpointWriter save_checkpoint(Scene& scene) {
  const SceneContents c = contents_with_world(scene);
  CheckpointWriter w(bullet::scalar_bytes());
  for (std::size_t k = 0; k < c.soils.size(); ++k) {
    w.add(tag("TERRAIN", k), c.soils[k].soil->save_bytes());
    if (c.soils[k].coupling) w.add(tag("TERRCP", k), c.soils[k].coupling->save_state());
  }
  for (std::size_t k = 0; k < c.waters.size(); ++k) {
    w.add(tag("WATER", k), c.waters[k].surface->save_state());
    if (c.waters[k].coupling) w.add(tag("WATERCP", k), c.waters[k].coupling->save_state());
  }
  w.add("BODIES", bullet::save_bodies(c.world->world(), c.world->bodies()));
  if (!c.world->multibodies().empty()) w.add("MBODIES", save_multibodies(*c.world));
  for (std::size_t k = 0; k < c.vehicles.size(); ++k) w.add(tag("VEHICLE", k), bullet::save_vehicle(*c.vehicles[k]));
  ByteWriter clock;
  clock.put(static_cast<std::int64_t>(c.clock ? *c.clock : -1));
  w.add("SCENE", std::move(clock.bytes));
  return w;
}

void restore_checkpoint(Scene& scene, const CheckpointReader& r) {
  const SceneContents c = contents_with_world(scene);
  // Everything Shore's couplings read comes first: the soils (the tiles copy them) and water.
  for (std::size_t k = 0; k < c.soils.size(); ++k) {
    terrain::Terrain& soil = *c.soils[k].soil;
    const std::string t = tag("TERRAIN", k);
    soil = terrain::Terrain::load_bytes(r.section(t), r.describe(t), soil.settings().base);
  }
  for (std::size_t k = 0; k < c.waters.size(); ++k) {
    const std::string t = tag("WATER", k);
    c.waters[k].surface->restore_state(r.section(t), r.describe(t));
  }
  bullet::restore_bodies(c.world->world(), c.world->bodies(), r.section("BODIES"), r.describe("BODIES"));
  if (!c.world->multibodies().empty()) restore_multibodies(*c.world, r.section("MBODIES"), r.describe("MBODIES"));
  for (std::size_t k = 0; k < c.vehicles.size(); ++k) {
    const std::string t = tag("VEHICLE", k);
    bullet::restore_vehicle(*c.vehicles[k], r.section(t), r.describe(t));
  }
  for (std::size_t k = 0; k < c.soils.size(); ++k)
    if (c.soils[k].coupling) {
      const std::string t = tag("TERRCP", k);
      c.soils[k].coupling->restore_state(r.section(t), r.describe(t));
    }
  for (std::size_t k = 0; k < c.waters.size(); ++k)
    if (c.waters[k].coupling) {
      const std::string t = tag("WATERCP", k);
      c.waters[k].coupling->restore_state(r.section(t), r.describe(t));
    }
  ByteReader clock(r.section("SCENE"), r.describe("SCENE"));
  const auto k = clock.get<std::int64_t>("clock");
  if (c.clock) {
    if (k < 0) clock.fail("holds no clock, the scene has one");
    *c.clock = static_cast<int>(k);
  }
}

}  // namespace shore::scenes
