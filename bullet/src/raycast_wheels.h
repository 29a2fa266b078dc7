#pragma once
// Internal: the wheels of the btRaycastVehicles a TerrainCoupling serves. A raycast wheel
// has no body: Bullet's vehicle finds the ground with a ray (it hits the tiles, so the rut
// the wheel sits in) and carries the chassis on its suspension. On soft ground Shore adds
// what the ray cannot feel:
// - sinkage: the wheel's cylinder, resting where its ray hit, is pressed into the terrain
//   as far as the column model needs to carry the wheel's suspension force (BearingSolve,
//   Terrain::bearing_offset's answer, with the columns' memory of earlier passes) on its front arc when it
//   rolls, on the whole rim when it stands (Bekker's rolling and static wheels); the next
//   ray finds the rut;
// - compaction resistance: the columns' push on the cylinder's sloped front, resolved along
//   the wheel's heading, acts on the chassis at the wheel's contact point;
// - traction and side force, for a SoilVehicle: the soil's shear on the rim
//   (raycast_traction.h), in place of Bullet's friction, which the vehicle leaves out for
//   wheels on this ground. A stock btRaycastVehicle keeps Bullet's (m_frictionSlip).

#include <functional>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <BulletCollision/CollisionDispatch/btCollisionWorld.h>
#include <BulletCollision/CollisionShapes/btCylinderShape.h>
#include <BulletDynamics/Vehicle/btRaycastVehicle.h>

#include "raycast_traction.h"
#include "raycast_wheel_grid.h"
#include "raycast_wheels_loosening.h"
#include "shore/bullet/envelope.h"
#include "shore/bullet/ground_frame.h"
#include "shore/bullet/soil_vehicle.h"
#include "shore/core/envelope.h"
#include "shore/terrain/bearing_solve.h"
#include "shore/terrain/terrain.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

struct SoftGround;

/// A raycast wheel's pose for its cylinder, in world coordinates: resting on the point its
/// ray hit (Bullet's own wheel transform is made before the ray and lags a falling wheel),
/// local x along its steered axle, local y forward, local z up the suspension.
btTransform wheel_pose(const btWheelInfo& info);
/// Casts the vehicle's wheel rays and finds their suspension forces as the vehicle's next
/// update does first (its own rayCast, updateWheelTransform and updateSuspension). Bullet leaves a wheel's ray
/// uninitialised until the vehicle first updates, and a coupling whose action runs before
/// the vehicle's reads it in that substep: after this it reads what the vehicle would.
void cast_wheel_rays(btRaycastVehicle& vehicle);
/// Throws InvalidSetting (`where` names the call) unless `widths` holds one width in
/// (0, 10] m per wheel of the vehicle and every wheel's radius is positive and finite.
void check_wheel_widths(const btRaycastVehicle& vehicle, std::span<const double> widths, const std::string& where);

/// Where a point one cell across from a column falls along one axis (raycast_wheels.cpp, wall_push).
struct AxisStep {
  std::size_t cell = 0;  ///< the column before it along the axis, from the ring's first
  double t = 0.0;        ///< its fraction from that column to the next
};

/// The window grown by one column on every side: each column's neighbours too.
GridRect ring_of(const GridRect& window);

/// The columns of one window row a rolling wheel's front arc keeps, [first, last)
/// (raycast_wheels.cpp, keep_front).
struct KeptRun {
  std::size_t first = 0, last = 0;
};

/// Scratch of the rut walls' push (raycast_wheels.cpp, wall_push).
struct WallScratch {
  /// The surface over `ring`, read from `terrain` unless the last read was of this ring
  /// since forget(): the caller forgets whenever the terrain may have changed.
  const std::vector<double>& ring_heights(const terrain::Terrain& terrain, const GridRect& ring);
  void forget() { read = GridRect{}; }
  std::vector<double> heights;  ///< the surface over `read`
  GridRect read;                ///< the ring `heights` holds (empty: none)
  /// Per column offset along x (u) and y (v): one cell ahead and behind along the axle.
  std::vector<AxisStep> u_ahead, u_behind, v_ahead, v_behind;
  std::vector<double> force, slope;  ///< per strip along the heading: column forces, slopes across
  std::vector<int> count;            ///< per strip: loaded columns
};

class RaycastWheels {
 public:
  RaycastWheels();
  ~RaycastWheels();
  RaycastWheels(const RaycastWheels&) = delete;
  RaycastWheels& operator=(const RaycastWheels&) = delete;
  /// Where the coupling's deforming ground is: a wheel whose contact point it holds is
  /// served (pressed, resisted and, on a SoilVehicle, given the soil's traction).
  void set_ground(std::function<bool(const btVector3&)> holds);
  /// Throws InvalidSetting (naming the field, value and what is allowed) for a null vehicle,
  /// one added already, a width count other than its wheel count, a width not in (0, 10] m
  /// or a wheel the rasterizer cannot take on cells of `cell` m.
  /// `rises`: the vehicle casts its rays with a SoilRaycaster, and its wheels rise onto soil
  /// that carries more than their load (rise).
  void add(btRaycastVehicle* vehicle, std::span<const double> widths, double cell, const EnvelopeOptions& options,
           bool rises = false);
  void remove(const btRaycastVehicle* vehicle);
  /// Where the terrain lies in the world: the wheels' rays and contact points are taken
  /// into its coordinates, their pushes back into the world's.
  void set_frame(const GroundFrame& frame) {
    framed_ = !frame.identity();
    to_ground_ = frame.to_ground();
  }
  /// Columns around each wheel's imprint for the soil step (terrain::Imprint::margin; 0:
  /// the terrain's active_margin).
  void set_margin(int margin) { margin_ = margin; }
  /// s: the time the terrain's next step covers (the wheels' clinging soil, rim_stays).
  void set_soil_step(double seconds) { soil_step_ = seconds; }
  /// Vehicles whose chassis the world no longer holds are dropped (by address, never read).
  /// Returns how many.
  int forget_lost(const btCollisionWorld& world);
  /// One substep: each wheel on the ground (set_ground) has its resistance (and a
  /// SoilVehicle's wheel its traction) applied to the chassis and, if the terrain deforms
  /// this substep, its imprint added to `imprints` (valid until the next serve).
  void serve(const terrain::Terrain& terrain, EnvelopeRasterizer& rasterizer, double h, bool deforms,
             std::vector<terrain::Imprint>& imprints);
  /// N, the terrain's push on wheel k along its heading in the last substep (negative: it
  /// resists forward motion); 0 for a wheel off the terrain or a vehicle not added.
  [[nodiscard]] double push(const btRaycastVehicle* vehicle, int k) const;
  /// N, the rut walls' push on wheel k along its axle's horizontal direction (wall_push).
  [[nodiscard]] double side_push(const btRaycastVehicle* vehicle, int k) const;

 private:
  struct Wheel {
    std::unique_ptr<btCylinderShapeX> shape;  ///< axis along the wheel's local x (its axle)
    double reach = 0.0;                       ///< m (check_rasterizable)
    /// What it presses: the cylinder, or only its columns that can reach the ground
    /// (rasterize_wheel): the same answers.
    EnvelopeRaster envelope;
    /// m: the envelope holds the columns reaching below the highest ground under the wheel
    /// + the terrain's reach + this (0: the whole cylinder). A solve that measures no offset
    /// this deep answers as on the whole cylinder (cut_ok).
    double cut_depth = 0.0;
    /// The whole cylinder's window: the rut walls read the ground over it, whether the
    /// envelope is cut or not (their bilinear weights depend on a column's place in it).
    GridRect window;
    double last_deepest = 0.0;        ///< m: the deepest offset its last press measured
    EnvelopeRaster bearing_part;      ///< what bears its load (the front arc when rolling)
    std::vector<KeptRun> front_runs;  ///< scratch: each window row's kept run (keep_front)
    terrain::BearingSolve solve;      ///< scratch: bearing_part's columns and capacities
    ColumnOffsets from_centre;        ///< scratch: the envelope's columns from the wheel's centre
    terrain::Imprint imprint;
    double push = 0.0;       ///< N along the heading, last substep
    double wall_push = 0.0;  ///< N along the axle's horizontal direction, last substep (wall_push)
    WallScratch wall;
    std::vector<RimStrip> rim;  ///< scratch: the rim's strips in contact
    /// rad: the rim's arc in contact in this substep's grip (0: none), for its clinging soil
    double contact_angle = 0.0;
    RimLoosening loosening;     ///< scratch: a slipping wheel's loosened columns
    terrain::Bearing loosened;  ///< the bearing it pressed with, loosened
    /// rad/s: a SoilVehicle's wheel's spin in the last substep (NaN: none, off the soil),
    /// where grip's spin search starts; read from the vehicle's record each substep.
    double last_spin = std::numeric_limits<double>::quiet_NaN();
  };
  [[nodiscard]] const Wheel* find(const btRaycastVehicle* vehicle, int k) const;
  struct Vehicle {
    btRaycastVehicle* vehicle = nullptr;
    SoilVehicle* soil = nullptr;  ///< the same vehicle if it takes the soil's traction
    const btCollisionObject* chassis = nullptr;
    std::vector<Wheel> wheels;
    bool rises = false;  ///< built with a SoilRaycaster: its wheels rise (rise)
  };
  /// What press found under a wheel, for its traction.
  struct Pressed {
    btVector3 at;                     ///< the contact point relative to the chassis' centre of mass
    btTransform pose, world_pose;     ///< the wheel's, in ground and world coordinates
    double radius = 0.0, load = 0.0;  ///< m; N, the suspension force plus the rise's
    /// m, the height of the end of the wheel's ray (ground frame): it sinks no lower in a substep.
    double ray_end = -std::numeric_limits<double>::infinity();
  };
  /// The wheel's rut and resistance; its imprint if the terrain deforms, else null.
  const terrain::Imprint* press(const terrain::Terrain& terrain, EnvelopeRasterizer& rasterizer, double h, bool deforms,
                                Vehicle& vehicle, int k);
  /// Rasterizes the wheel at `pose` into its envelope, cut to the columns that can reach the
  /// ground unless `whole` (or no cut is known to be safe). Returns the covered columns.
  static int rasterize_wheel(const terrain::Terrain& terrain, EnvelopeRasterizer& rasterizer, Wheel& wheel,
                             const btTransform& pose, bool whole);
  /// The wheel's bearing part (its front arc when rolling) read into its solve.
  static void read_bearing(const terrain::Terrain& terrain, Wheel& wheel, const Pressed& p, double speed);
  /// The whole cylinder rasterized and its bearing read again (a press deeper than the cut
  /// allows): the offset that carries the plain load.
  static double press_whole(const terrain::Terrain& terrain, EnvelopeRasterizer& rasterizer, Wheel& wheel,
                            const Pressed& p, double speed);
  /// A wheel on soil that carries more than its load at the ray's hit (plain offset 0):
  /// the rise d >= 0 above the hit at which the soil carries the suspension force the ground
  /// raised by d would give, capacity(d) = F + k d (F Bullet's suspension force from the hit,
  /// k its spring: stiffness x chassis mass / the contact's cosine, as updateSuspension).
  /// Bullet's ray lands on the rut's floor whatever the soil carries, so without this a depth
  /// pressed once is kept. The wheel's envelope is left rasterized at `p.pose` raised by a
  /// bound D (m, > 0, the most it may rise) and the solve read there; returns d, its offset
  /// D - d in `offset`; p.pose, p.world_pose and p.load are moved to the raised wheel.
  /// `spring` is k (N/m, > 0).
  static double rise(const terrain::Terrain& terrain, EnvelopeRasterizer& rasterizer, Wheel& wheel, Pressed& p,
                     double speed, double spring, double bound, double& offset);
  /// True if the wheel's solve measured no offset as deep as its envelope's cut (cut_ok):
  /// its answers are the whole envelope's.
  static bool cut_ok(const Wheel& wheel);
  /// The rut walls' push across the wheel (wall_push in the .cpp), applied to the chassis.
  void steer_by_walls(const terrain::Terrain& terrain, const terrain::Bearing& bearing, Vehicle& vehicle, int k,
                      const Pressed& p, double h);
  /// A slipping wheel's soil loosened strip by strip (RimLoosening): the offset at which it
  /// carries the load (the envelope no lower than p.ray_end), its loosened bearing in the wheel's `loosened`.
  double loosen(const terrain::Terrain& terrain, const terrain::Material& m, const RimShear& shear, Wheel& wheel,
                const Pressed& p);
  /// A SoilVehicle's wheel: the soil's shear on its rim (material `m`, the one under the
  /// wheel's centre, gives K and the strength loss), applied to the chassis. Returns the
  /// shear displacement along the rim (a default RimShear, no shear, off the soil).
  RimShear grip(const terrain::Terrain& terrain, const terrain::Bearing& bearing, const terrain::Material& m, double h,
                Vehicle& vehicle, int k, const Pressed& p);
  std::vector<Vehicle> vehicles_;
  std::shared_ptr<SoftGround> ground_;
  bool framed_ = false;
  int margin_ = 0;
  double soil_step_ = 0.0;
  btTransform to_ground_ = btTransform::getIdentity();
};

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
