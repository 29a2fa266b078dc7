#pragma once
// Internal: the wheels of the btRaycastVehicles a TerrainCoupling serves. A raycast wheel
// has no body: Bullet's vehicle finds the ground with a ray (it hits the tiles, so the rut
// the wheel sits in) and carries the chassis on its suspension. On soft ground Shore adds
// what the ray cannot feel:
// - sinkage: the wheel's cylinder, resting where its ray hit, is pressed into the terrain
//   as far as the column model needs to carry the wheel's suspension force (Terrain::
//   bearing_offset, with the columns' memory of earlier passes) on its front arc when it
//   rolls, on the whole rim when it stands (Bekker's rolling and static wheels); the next
//   ray finds the rut;
// - compaction resistance: the columns' push on the cylinder's sloped front, resolved along
//   the wheel's heading, acts on the chassis at the wheel's contact point.
// Traction and side force stay Bullet's (m_frictionSlip).

#include <memory>
#include <span>
#include <vector>

#include <BulletCollision/CollisionDispatch/btCollisionWorld.h>
#include <BulletCollision/CollisionShapes/btCylinderShape.h>
#include <BulletDynamics/Vehicle/btRaycastVehicle.h>

#include "shore/bullet/envelope.h"
#include "shore/bullet/ground_frame.h"
#include "shore/core/envelope.h"
#include "shore/terrain/terrain.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

class RaycastWheels {
 public:
  /// Throws InvalidSetting (naming the field, value and what is allowed) for a null vehicle,
  /// one added already, a width count other than its wheel count, a width not in (0, 10] m
  /// or a wheel the rasterizer cannot take on cells of `cell` m.
  void add(btRaycastVehicle* vehicle, std::span<const double> widths, double cell, const EnvelopeOptions& options);
  void remove(const btRaycastVehicle* vehicle);
  /// Where the terrain lies in the world: the wheels' rays and contact points are taken
  /// into its coordinates, their pushes back into the world's.
  void set_frame(const GroundFrame& frame) {
    framed_ = !frame.identity();
    to_ground_ = frame.to_ground();
  }
  /// Vehicles whose chassis the world no longer holds are dropped (by address, never read).
  /// Returns how many.
  int forget_lost(const btCollisionWorld& world);
  /// One substep: each wheel on the terrain's ground (`on_ground(contact point)`) has its
  /// resistance applied to the chassis and, if the terrain deforms this substep, its
  /// imprint added to `imprints` (valid until the next serve).
  template <class OnGround>
  void serve(const terrain::Terrain& terrain, EnvelopeRasterizer& rasterizer, double h, bool deforms,
             std::vector<terrain::Imprint>& imprints, OnGround&& on_ground) {
    for (Vehicle& v : vehicles_)
      for (std::size_t k = 0; k < v.wheels.size(); ++k) {
        const btWheelInfo& info = v.vehicle->getWheelInfo(static_cast<int>(k));
        v.wheels[k].push = 0.0;
        if (!info.m_raycastInfo.m_isInContact || !on_ground(info.m_raycastInfo.m_contactPointWS)) continue;
        if (const terrain::Imprint* im = press(terrain, rasterizer, h, deforms, *v.vehicle, info, v.wheels[k]))
          imprints.push_back(*im);
      }
  }
  /// N, the terrain's push on wheel k along its heading in the last substep (negative: it
  /// resists forward motion); 0 for a wheel off the terrain or a vehicle not added.
  [[nodiscard]] double push(const btRaycastVehicle* vehicle, int k) const;

 private:
  struct Wheel {
    std::unique_ptr<btCylinderShapeX> shape;  ///< axis along the wheel's local x (its axle)
    double reach = 0.0;                       ///< m (check_rasterizable)
    EnvelopeRaster envelope;                  ///< the whole cylinder: what it presses
    EnvelopeRaster bearing_part;              ///< what bears its load (the front arc when rolling)
    terrain::Imprint imprint;
    double push = 0.0;  ///< N along the heading, last substep
  };
  struct Vehicle {
    btRaycastVehicle* vehicle = nullptr;
    const btCollisionObject* chassis = nullptr;
    std::vector<Wheel> wheels;
  };
  /// The wheel's rut and resistance; its imprint if the terrain deforms, else null.
  const terrain::Imprint* press(const terrain::Terrain& terrain, EnvelopeRasterizer& rasterizer, double h, bool deforms,
                                btRaycastVehicle& vehicle, const btWheelInfo& info, Wheel& wheel);
  std::vector<Vehicle> vehicles_;
  bool framed_ = false;
  btTransform to_ground_ = btTransform::getIdentity();
};

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
