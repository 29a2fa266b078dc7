#pragma once
// Internal: a btMultiBody link (or its base) as a coupled body, through its collider.
//
// The couplings see one rigid part: its centre of mass, how it moves, how an impulse there
// changes that. An articulated part answers through the multibody's Jacobian at its centre,
// the way Bullet's own multibody contacts do:
// - motion: the link's spatial velocity, J qdot, J the 6 x (6 + dofs) Jacobian of the
//   link's centre (its collider's origin: Bullet's link frames sit at the centre of mass)
//   and qdot the multibody's generalized velocity (base spin and velocity, joint rates);
// - an impulse P at the centre and an angular impulse L move every joint:
//   dqdot = M^-1 J^T (P, L), applied with applyDeltaVeeMultiDof.
//
// The soil's contact solver sees the link's full mobility A = J M^-1 J^T (6 x 6: the
// change of the centre's velocity and the link's angular velocity per impulse and angular
// impulse there, through the whole articulation; `mobility`, SolverBody::articulated): a
// foot at a table's corner is lighter than the table, a wheel on an axle cannot slide
// sideways, and each block's push stays within what its soil bears.
//
// The water's drag is limited through A too (water_forces.h: a link's mass and inertia
// cannot be taken apart).
//
// inverse_mass and inverse_inertia (the one mass and inertia of the CoupledBody interface,
// used where a scalar plan is enough: holding a body at rest, debug arrows) are A's linear
// block along `up` (opposite gravity: the soil's push is mostly
// along it) and A's angular block, made invertible by a thousandth of its mean (a direction
// the joints lock looks very stiff, not infinitely). For a multibody of one free base A is
// exactly the base's 1/m and I^-1.
//
// The pose-correcting operations act on the whole articulation, because a link cannot
// move alone without breaking its joints:
// - correct_motion / stop: the link's motion is changed to exactly what the solver found,
//   by the impulse at its centre that does it, (P, L) = A^-1 (dv, dw) (directions the
//   joints lock left out), applied through the Jacobian; every joint's position then moves
//   by its dqdot times h (what Bullet's integration would have done with it). After the
//   soil's solve, which planned with A itself, that is the solver's own impulse; after a
//   rest hold, planned with the scalar mass, it is the impulse that truly stops the link.
// - set_linear_velocity: the same, with the angular motion kept.
// - apply_impulse (water's buoyancy and drag) is exact: J^T (P, L) through M^-1.
// - translate: moves the whole multibody (its base) by the offset; a fixed or kinematic
//   base stays: an anchored arm is where its game put it, and nothing lifts it.
//
// A link whose multibody is no longer in the world (removed with removeMultiBody, perhaps
// deleted, while its collider stayed) is never read: its motion is non-finite, so the
// couplings skip and count it. The check is by address against the world's multibodies.

#include <vector>

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include "coupled_body.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

/// Whether the world holds this multibody (by address: never reads it).
[[nodiscard]] bool holds_multibody(const btMultiBodyDynamicsWorld& world, const btMultiBody* body);

/// The multibody world a link may be added to: `world` as one, after checking the link
/// (not null, its multibody and collider in the world, a finite pose and motion). Throws
/// InvalidSetting naming `what` and the problem.
[[nodiscard]] const btMultiBodyDynamicsWorld& link_world(btDiscreteDynamicsWorld& world,
                                                         const btMultiBodyLinkCollider* link, const char* what);

/// Throws InvalidSetting naming `what` when the coupling holds the link already (`held`):
/// a link is added once (a second add_link would silently replace the first's settings,
/// most often by mistake: two parts of a game adding the same foot).
void refuse_if_added(bool held, const btMultiBodyLinkCollider& link, const char* what);

/// The link's motion (its centre's velocity and its angular velocity, world frame), for a
/// link whose multibody the world holds; non-finite velocities otherwise.
[[nodiscard]] Motion link_motion(const btMultiBodyDynamicsWorld& world, const btMultiBodyLinkCollider& link);
/// The same in any world (non-finite velocities outside a btMultiBodyDynamicsWorld).
[[nodiscard]] Motion link_motion(const btCollisionWorld& world, const btMultiBodyLinkCollider& link);

/// The multibody's generalized velocity: base (angular, linear), then every joint's rates.
[[nodiscard]] std::vector<btScalar> generalized_velocity(const btMultiBody& body);
/// Moves the multibody's base and joints by dq (a generalized velocity) times h, as Bullet's
/// integration would with dq as the velocity, and its colliders with them (nothing for h 0
/// or a non-finite dq). scratch_q, scratch_o: Bullet's workspace, reused.
void step_positions(btMultiBody& body, const std::vector<btScalar>& dq, double h,
                    btAlignedObjectArray<btQuaternion>& scratch_q, btAlignedObjectArray<btVector3>& scratch_o);

class CoupledMultiBodyLink final : public CoupledBody {
 public:
  /// `world` must hold the link's multibody when the link is added (the caller checks).
  CoupledMultiBodyLink(btMultiBodyLinkCollider& link, const btMultiBodyDynamicsWorld& world) noexcept;

  [[nodiscard]] btMultiBodyLinkCollider& link() const noexcept { return *link_; }
  /// Moves under forces: any link but the base of a fixed or kinematic base, while the
  /// world holds its multibody.
  [[nodiscard]] bool dynamic() const override;
  [[nodiscard]] Motion motion() const override;
  [[nodiscard]] double inverse_mass() const override;
  [[nodiscard]] btMatrix3x3 inverse_inertia() const override;
  /// The link's 6 x 6 mobility A at its centre ((P, L) to (dv, dw)), for the soil's solver;
  /// false (a left unset) if it is not finite (before the multibody's first step).
  [[nodiscard]] bool mobility(double a[6][6]) const override;
  void apply_impulse(const btVector3& impulse, const btVector3& angular_impulse) override;
  void correct_motion(const btVector3& linear, const btVector3& angular, double h) override;
  void stop(double h) override;
  void set_linear_velocity(const btVector3& linear) override;
  void translate(const btVector3& offset) override;

 private:
  /// The 6 rows of J (linear x, y, z, then angular x, y, z) at the link's centre, each
  /// 6 + dofs long, and (with `mobility`) M^-1 J^T's 6 columns and A.
  struct Jacobian {
    int size = 0;                  ///< 6 + dofs
    std::vector<btScalar> rows;    ///< 6 x size
    std::vector<btScalar> deltas;  ///< 6 x size: dqdot of a unit impulse along each row
    double a[6][6] = {};           ///< mobility J M^-1 J^T
  };
  [[nodiscard]] bool attached() const;
  void fill(Jacobian& j, bool mobility) const;
  /// The solver's plan: inverse mass along up and the invertible angular block.
  struct Plan {
    double inv_mass = 0.0;
    double inv_inertia[3][3] = {};
  };
  [[nodiscard]] Plan plan() const;
  /// dqdot of the impulse (P, L) at the centre, through J^T and M^-1.
  void impulse_deltas(const btVector3& impulse, const btVector3& angular_impulse, std::vector<btScalar>& dq) const;
  /// dqdot of the impulse at the centre that changes the link's motion by exactly (dv, dw)
  /// (A^-1 through J^T and M^-1; directions the joints lock are left out).
  void velocity_change_deltas(const btVector3& dv, const btVector3& dw, std::vector<btScalar>& dq) const;
  /// Adds dq to the velocities and, over h > 0, moves the positions by dq h.
  void change_velocities(const std::vector<btScalar>& dq, double h);

  btMultiBodyLinkCollider* link_;
  const btMultiBodyDynamicsWorld* world_;
  btVector3 up_;  ///< unit, opposite the world's gravity at add time (+z without gravity)
  // Bullet's scratch space for the Jacobian and M^-1 (reused, never part of the state).
  mutable btAlignedObjectArray<btScalar> scratch_r_;
  mutable btAlignedObjectArray<btVector3> scratch_v_;
  mutable btAlignedObjectArray<btMatrix3x3> scratch_m_;
  mutable btAlignedObjectArray<btQuaternion> scratch_q_;
  mutable btAlignedObjectArray<btVector3> scratch_o_;
};

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
