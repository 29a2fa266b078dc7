#include "shore/scenes/raycast_car.h"

#include "shore/bullet/soil_vehicle.h"

namespace shore::scenes {

RaycastCar::RaycastCar(World& world, const RaycastCarSettings& settings, const btVector3& at,
                       bullet::TerrainCoupling* soil)
    : world_(world), settings_(settings) {
  const RaycastCarSettings& s = settings_;
  auto box =
      std::make_unique<btBoxShape>(btVector3(btScalar(s.half_length), btScalar(s.half_width), btScalar(s.half_height)));
  // The chassis' own axes are the ground's (x forward, z up), so the vehicle's coordinate
  // system below holds in any world: a Y-up one turns the chassis, not the vehicle.
  chassis_ = world.ground().identity()
                 ? world.add_body(std::move(box), s.mass, at)
                 : world.add_body(std::move(box), s.mass, world.to_world(btTransform(btQuaternion::getIdentity(), at)));
  // A car parked on the ground must not fall asleep with its engine running.
  chassis_->setActivationState(DISABLE_DEACTIVATION);

  btRaycastVehicle::btVehicleTuning tuning;
  tuning.m_suspensionStiffness = btScalar(s.suspension_stiffness);
  tuning.m_suspensionCompression = btScalar(s.damping_compression);
  tuning.m_suspensionDamping = btScalar(s.damping_relaxation);
  tuning.m_frictionSlip = btScalar(s.friction_slip);
  tuning.m_maxSuspensionTravelCm = btScalar(s.max_suspension_travel_cm);
  if (soil != nullptr) {
    auto raycaster = std::make_unique<bullet::SoilRaycaster>(*soil);
    soil_raycaster_ = raycaster.get();
    raycaster_ = std::move(raycaster);
  } else {
    raycaster_ = std::make_unique<btDefaultVehicleRaycaster>(&world.world());
  }
  if (s.soil_traction)
    vehicle_ = std::make_unique<bullet::SoilVehicle>(tuning, chassis_, raycaster_.get());
  else
    vehicle_ = std::make_unique<btRaycastVehicle>(tuning, chassis_, raycaster_.get());
  vehicle_->setCoordinateSystem(1, 2, 0);  // right y, up z, forward x
  const btVector3 down(0, 0, -1), axle(0, -1, 0);
  for (int k = 0; k < 4; ++k) {
    const bool front = k < 2;
    const double x = front ? s.axle_offset : -s.axle_offset, y = (k % 2 == 0) ? s.track_half : -s.track_half;
    const btVector3 connection(btScalar(x), btScalar(y), btScalar(s.connection_height));
    btWheelInfo& w = vehicle_->addWheel(connection, down, axle, btScalar(s.suspension_rest), btScalar(s.wheel_radius),
                                        tuning, front);
    w.m_rollInfluence = btScalar(0.1);
  }
  world.world().addAction(vehicle_.get());
}

RaycastCar::~RaycastCar() { world_.world().removeAction(vehicle_.get()); }

void RaycastCar::drive(double engine_force, double brake, double steering) {
  for (int k = 0; k < vehicle_->getNumWheels(); ++k) {
    const bool front = k < 2;
    vehicle_->applyEngineForce(btScalar(front && !settings_.four_wheel_drive ? 0.0 : engine_force), k);
    vehicle_->setBrake(btScalar(brake), k);
    vehicle_->setSteeringValue(btScalar(front ? steering : 0.0), k);
  }
}

int RaycastCar::wheels_on_ground() const {
  int n = 0;
  for (int k = 0; k < vehicle_->getNumWheels(); ++k) n += vehicle_->getWheelInfo(k).m_raycastInfo.m_isInContact;
  return n;
}

}  // namespace shore::scenes
