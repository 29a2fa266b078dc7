#pragma once
// A tiny coupled world for the checkpoint fuzz target and its seeds: soil with small
// tiles, a small water grid over it, and a ball coupled to both. Built the same way every
// time, so a checkpoint of one restores into another (docs/checkpoints.md).

#include <memory>
#include <span>
#include <string>
#include <vector>

#include <btBulletDynamicsCommon.h>

#include "shore/bullet/body_state.h"
#include "shore/bullet/terrain_coupling.h"
#include "shore/bullet/water_coupling.h"
#include "shore/core/checkpoint_file.h"
#include "shore/terrain/terrain.h"
#include "shore/water/surface.h"

namespace shore::fuzz {

inline terrain::TerrainSettings tiny_soil() {
  terrain::TerrainSettings s;
  s.tile_columns = 8;
  s.cell = 0.05;
  s.base_height = -0.05;
  s.max_erosion_passes = 2;
  s.threads = 1;
  return s;
}

inline water::SurfaceSettings tiny_water() {
  water::PhysicalParameters p;
  p.cell = 0.1;
  p.depth = 0.2;
  water::SurfaceSettings s = water::SurfaceSettings::physical(p, 5, 5);
  s.origin_x = -0.2, s.origin_y = -0.2;
  s.sleep.tile = 8;  // the smallest tiles: a state of a few kB, so each input is cheap
  s.threads = 1;
  return s;
}

/// Bullet's default pools hold thousands of manifolds and algorithms, allocated up front;
/// one ball and a few tiles need a handful, and each fuzz input builds two worlds.
inline btDefaultCollisionConstructionInfo small_pools() {
  btDefaultCollisionConstructionInfo info;
  info.m_defaultMaxPersistentManifoldPoolSize = 32;
  info.m_defaultMaxCollisionAlgorithmPoolSize = 32;
  return info;
}

class CoupledWorld {
 public:
  static constexpr double kSubstep = 1.0 / 240.0;
  CoupledWorld()
      : config_(small_pools()),
        dispatcher_(&config_),
        world_(&dispatcher_, &broadphase_, &solver_, &config_),
        soil_(tiny_soil()),
        surface_(tiny_water()),
        ground_(world_, soil_),
        water_(world_, surface_),
        ball_shape_(btScalar(0.08)) {
    world_.setGravity(btVector3(0, 0, btScalar(-9.81)));
    btVector3 inertia;
    ball_shape_.calculateLocalInertia(btScalar(1.0), inertia);
    ball_ = std::make_unique<btRigidBody>(btScalar(1.0), nullptr, &ball_shape_, inertia);
    ball_->setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0.05f, 0.0f, 0.04f)));
    ball_->setLinearVelocity(btVector3(0.6f, 0.2f, -0.3f));
    ball_->setActivationState(DISABLE_DEACTIVATION);
    world_.addRigidBody(ball_.get());
    ground_.add_body(ball_.get());
    water_.add_body(ball_.get());
  }
  ~CoupledWorld() { world_.removeRigidBody(ball_.get()); }
  CoupledWorld(const CoupledWorld&) = delete;
  CoupledWorld& operator=(const CoupledWorld&) = delete;

  void step() { world_.stepSimulation(btScalar(kSubstep), 1, btScalar(kSubstep)); }

  [[nodiscard]] std::vector<unsigned char> checkpoint() const {
    CheckpointWriter w(bullet::scalar_bytes());
    w.add("TERRAIN", soil_.save_bytes());
    w.add("TERRCP", ground_.save_state());
    w.add("WATER", surface_.save_state());
    w.add("WATERCP", water_.save_state());
    w.add("BODIES", bullet::save_bodies(world_));
    return w.bytes();
  }
  /// The order restores must keep: what the couplings read (soil, water, bodies) first.
  void restore(const CheckpointReader& r) {
    soil_ = terrain::Terrain::load_bytes(r.section("TERRAIN"), r.describe("TERRAIN"));
    surface_.restore_state(r.section("WATER"), r.describe("WATER"));
    bullet::restore_bodies(world_, r.section("BODIES"), r.describe("BODIES"));
    ground_.restore_state(r.section("TERRCP"), r.describe("TERRCP"));
    water_.restore_state(r.section("WATERCP"), r.describe("WATERCP"));
  }

  [[nodiscard]] const btRigidBody& ball() const { return *ball_; }
  [[nodiscard]] const terrain::Terrain& soil() const { return soil_; }
  [[nodiscard]] const water::Surface& surface() const { return surface_; }

 private:
  btDefaultCollisionConfiguration config_;
  btCollisionDispatcher dispatcher_;
  btDbvtBroadphase broadphase_;
  btSequentialImpulseConstraintSolver solver_;
  btDiscreteDynamicsWorld world_;
  terrain::Terrain soil_;
  water::Surface surface_;
  bullet::TerrainCoupling ground_;
  bullet::WaterCoupling water_;
  btSphereShape ball_shape_;
  std::unique_ptr<btRigidBody> ball_;
};

}  // namespace shore::fuzz
