#pragma once
// A tiny coupled world for the checkpoint fuzz target and its seeds: soil with small
// tiles, a small water grid over it, a ball coupled to both and, with links, a btMultiBody
// (a box base with a wheel on a revolute joint: a robot's smallest part) whose two links
// are coupled to both. A Featherstone world, built the same way every time, so a checkpoint
// of one restores into another (docs/checkpoints.md). The multibody's state (base pose and
// velocities, joint position and rate) is its own section, MBODY: a checkpoint holds it
// exactly when its world has links (the ball-only checkpoints, kept crash inputs among
// them, stay what they were). With a car, the world also holds a small raycast car
// (Shore's SoilVehicle) whose wheels are in both couplings; its wheels' state is the
// section VEHICLE (bullet::save_vehicle).

#include <cmath>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>
#include <btBulletDynamicsCommon.h>

#include "shore/bullet/body_state.h"
#include "shore/bullet/soil_vehicle.h"
#include "shore/bullet/terrain_coupling.h"
#include "shore/bullet/vehicle_state.h"
#include "shore/bullet/water_coupling.h"
#include "shore/core/byte_io.h"
#include "shore/core/checkpoint_file.h"
#include "shore/core/error.h"
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

/// The multibody's evolving state, in MBODY's order: base origin, world-to-base
/// quaternion, base linear and angular velocity, joint position and rate (btScalars).
constexpr int kMultiBodyValues = 3 + 4 + 3 + 3 + 2;

class CoupledWorld {
 public:
  static constexpr double kSubstep = 1.0 / 240.0;
  /// links: the world has the multibody too; car: the raycast car too.
  explicit CoupledWorld(bool links, bool car = false)
      : config_(small_pools()),
        dispatcher_(&config_),
        world_(&dispatcher_, &broadphase_, &solver_, &config_),
        soil_(tiny_soil()),
        surface_(tiny_water()),
        ground_(world_, soil_),
        water_(world_, surface_),
        ball_shape_(btScalar(0.08)),
        base_shape_(btVector3(0.06f, 0.05f, 0.03f)),
        wheel_shape_(btVector3(0.06f, 0.03f, 0.06f)),
        chassis_shape_(btVector3(0.12f, 0.08f, 0.02f)) {
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
    if (links) add_robot();
    if (car) add_car();
  }
  ~CoupledWorld() {
    if (car_) {
      world_.removeAction(car_.get());
      world_.removeRigidBody(chassis_.get());
    }
    if (robot_) {
      world_.removeCollisionObject(wheel_.get());
      world_.removeCollisionObject(base_.get());
      world_.removeMultiBody(robot_.get());
    }
    world_.removeRigidBody(ball_.get());
  }
  CoupledWorld(const CoupledWorld&) = delete;
  CoupledWorld& operator=(const CoupledWorld&) = delete;

  void step() { world_.stepSimulation(btScalar(kSubstep), 1, btScalar(kSubstep)); }

  [[nodiscard]] std::vector<unsigned char> checkpoint() const {
    CheckpointWriter w(bullet::scalar_bytes());
    w.add("TERRAIN", soil_.save_bytes());
    w.add("TERRCP", ground_.save_state());
    w.add("WATER", surface_.save_state());
    w.add("WATERCP", water_.save_state());
    w.add("BODIES", bullet::save_bodies(world_, bodies()));
    if (robot_) w.add("MBODY", save_robot());
    if (car_) w.add("VEHICLE", bullet::save_vehicle(*car_));
    return w.bytes();
  }
  /// The order restores must keep: what the couplings read (soil, water, bodies) first.
  void restore(const CheckpointReader& r) {
    soil_ = terrain::Terrain::load_bytes(r.section("TERRAIN"), r.describe("TERRAIN"));
    surface_.restore_state(r.section("WATER"), r.describe("WATER"));
    bullet::restore_bodies(world_, bodies(), r.section("BODIES"), r.describe("BODIES"));
    if (robot_) restore_robot(r.section("MBODY"), r.describe("MBODY"));
    if (car_) bullet::restore_vehicle(*car_, r.section("VEHICLE"), r.describe("VEHICLE"));
    ground_.restore_state(r.section("TERRCP"), r.describe("TERRCP"));
    water_.restore_state(r.section("WATERCP"), r.describe("WATERCP"));
  }

  [[nodiscard]] const btRigidBody& ball() const { return *ball_; }
  [[nodiscard]] bool links() const { return robot_ != nullptr; }
  [[nodiscard]] bool car() const { return car_ != nullptr; }
  /// The car's chassis (null without a car).
  [[nodiscard]] const btRigidBody* chassis() const { return chassis_.get(); }
  /// The multibody's state as doubles, in MBODY's order (hashes, finiteness); empty
  /// without links.
  [[nodiscard]] std::vector<double> robot_state() const {
    if (!robot_) return {};
    const btMultiBody& m = *robot_;
    const btQuaternion& q = m.getWorldToBaseRot();
    return {m.getBasePos().x(),
            m.getBasePos().y(),
            m.getBasePos().z(),
            q.x(),
            q.y(),
            q.z(),
            q.w(),
            m.getBaseVel().x(),
            m.getBaseVel().y(),
            m.getBaseVel().z(),
            m.getBaseOmega().x(),
            m.getBaseOmega().y(),
            m.getBaseOmega().z(),
            m.getJointPos(0),
            m.getJointVel(0)};
  }
  [[nodiscard]] const terrain::Terrain& soil() const { return soil_; }
  [[nodiscard]] const water::Surface& surface() const { return surface_; }

 private:
  /// The rigid bodies in the order added (save_bodies' list: the world's collision-object
  /// order changes as tiles come and go).
  [[nodiscard]] std::vector<btRigidBody*> bodies() const {
    std::vector<btRigidBody*> out{ball_.get()};
    if (chassis_) out.push_back(chassis_.get());
    return out;
  }
  /// A 4 kg chassis on four 4 cm wheels, a SoilVehicle driving its rear wheels, its wheels
  /// in both couplings; it stands beside the ball, half over the water.
  void add_car() {
    btVector3 inertia;
    chassis_shape_.calculateLocalInertia(btScalar(4.0), inertia);
    chassis_ = std::make_unique<btRigidBody>(btScalar(4.0), nullptr, &chassis_shape_, inertia);
    chassis_->setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(-0.15f, 0.15f, 0.1f)));
    chassis_->setActivationState(DISABLE_DEACTIVATION);
    world_.addRigidBody(chassis_.get());
    btRaycastVehicle::btVehicleTuning tuning;
    raycaster_ = std::make_unique<btDefaultVehicleRaycaster>(&world_);
    car_ = std::make_unique<bullet::SoilVehicle>(tuning, chassis_.get(), raycaster_.get());
    car_->setCoordinateSystem(1, 2, 0);  // right y, up z, forward x
    for (int k = 0; k < 4; ++k) {
      const btVector3 at(k < 2 ? 0.09f : -0.09f, k % 2 == 0 ? 0.07f : -0.07f, -0.01f);
      car_->addWheel(at, btVector3(0, 0, -1), btVector3(0, -1, 0), btScalar(0.05), btScalar(0.04), tuning, k < 2);
      car_->applyEngineForce(btScalar(k < 2 ? 0.0 : 3.0), k);
    }
    world_.addAction(car_.get());
    const double widths[] = {0.03, 0.03, 0.03, 0.03};
    ground_.add_vehicle(car_.get(), widths);
    water_.add_vehicle(car_.get(), widths);
  }
  /// A 2 kg box base, free, with a 0.5 kg wheel hinged to its side (about y), both links of
  /// both couplings; it lands on the soil beside the ball, in the water.
  void add_robot() {
    btVector3 base_inertia, wheel_inertia;
    base_shape_.calculateLocalInertia(btScalar(2.0), base_inertia);
    wheel_shape_.calculateLocalInertia(btScalar(0.5), wheel_inertia);
    robot_ = std::make_unique<btMultiBody>(1, btScalar(2.0), base_inertia, false, false);
    robot_->setBasePos(btVector3(-0.1f, -0.06f, 0.06f));
    robot_->setupRevolute(0, btScalar(0.5), wheel_inertia, -1, btQuaternion::getIdentity(), btVector3(0, 1, 0),
                          btVector3(0.0f, -0.09f, 0.0f), btVector3(0, 0, 0), true);
    robot_->finalizeMultiDof();
    robot_->setBaseVel(btVector3(0.3f, 0.0f, -0.2f));
    robot_->setJointVel(0, btScalar(4.0));
    robot_->setCanSleep(false);
    world_.addMultiBody(robot_.get());
    base_ = std::make_unique<btMultiBodyLinkCollider>(robot_.get(), -1);
    wheel_ = std::make_unique<btMultiBodyLinkCollider>(robot_.get(), 0);
    base_->setCollisionShape(&base_shape_);
    wheel_->setCollisionShape(&wheel_shape_);
    robot_->setBaseCollider(base_.get());
    robot_->getLink(0).m_collider = wheel_.get();
    place_colliders();
    world_.addCollisionObject(base_.get(), btBroadphaseProxy::DefaultFilter, btBroadphaseProxy::AllFilter);
    world_.addCollisionObject(wheel_.get(), btBroadphaseProxy::DefaultFilter, btBroadphaseProxy::AllFilter);
    for (btMultiBodyLinkCollider* link : {base_.get(), wheel_.get()}) {
      ground_.add_link(link);
      water_.add_link(link);
    }
  }
  /// The colliders where the multibody's pose and joint put them.
  void place_colliders() {
    btAlignedObjectArray<btQuaternion> rotations;
    btAlignedObjectArray<btVector3> offsets;
    rotations.resize(2);
    offsets.resize(2);
    robot_->forwardKinematics(rotations, offsets);
    robot_->updateCollisionObjectWorldTransforms(rotations, offsets);
  }
  [[nodiscard]] std::vector<unsigned char> save_robot() const {
    ByteWriter w;
    const std::vector<double> state = robot_state();
    std::vector<btScalar> values(state.begin(), state.end());
    w.put_array(values);
    return std::move(w.bytes);
  }
  /// FileError naming `source` (the multibody unchanged) for a truncated section, another
  /// count, or a state no simulation has (bullet::multibody_state_problem).
  void restore_robot(std::span<const unsigned char> bytes, const std::string& source) {
    ByteReader r(bytes, source);
    std::vector<btScalar> v;
    r.get_array(v, kMultiBodyValues, "the multibody's state");
    if (const std::string problem = bullet::multibody_state_problem(*robot_, v); !problem.empty()) r.fail(problem);
    const btQuaternion q(v[3], v[4], v[5], v[6]);
    robot_->setBasePos(btVector3(v[0], v[1], v[2]));
    robot_->setWorldToBaseRot(q);
    robot_->setBaseVel(btVector3(v[7], v[8], v[9]));
    robot_->setBaseOmega(btVector3(v[10], v[11], v[12]));
    robot_->setJointPos(0, v[13]);
    robot_->setJointVel(0, v[14]);
    place_colliders();
  }

  btDefaultCollisionConfiguration config_;
  btCollisionDispatcher dispatcher_;
  btDbvtBroadphase broadphase_;
  btMultiBodyConstraintSolver solver_;
  btMultiBodyDynamicsWorld world_;
  terrain::Terrain soil_;
  water::Surface surface_;
  bullet::TerrainCoupling ground_;
  bullet::WaterCoupling water_;
  btSphereShape ball_shape_;
  std::unique_ptr<btRigidBody> ball_;
  btBoxShape base_shape_;
  btCylinderShape wheel_shape_;  // its axis along the link's y, the hinge's
  std::unique_ptr<btMultiBody> robot_;
  std::unique_ptr<btMultiBodyLinkCollider> base_, wheel_;
  btBoxShape chassis_shape_;
  std::unique_ptr<btRigidBody> chassis_;
  std::unique_ptr<btDefaultVehicleRaycaster> raycaster_;
  std::unique_ptr<bullet::SoilVehicle> car_;
};

}  // namespace shore::fuzz
