#pragma once
// Internal: what the terrain coupling keeps of one body it serves, and the checks of the
// body's shape (one concept: can the terrain take this body, and what did it make of it).

#include <LinearMath/btTransform.h>

#include "contact_solver.h"
#include "coupled_body.h"
#include "shore/bullet/config.h"
#include "shore/bullet/envelope.h"
#include "shore/bullet/terrain_coupling.h"
#include "shore/core/envelope.h"
#include "shore/terrain/contact.h"
#include "terrain_contact.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

/// The shape a body had when the terrain last checked it, and what the check found.
struct ShapeCheck {
  const btCollisionShape* shape = nullptr;
  btVector3 scaling{1, 1, 1};
  double reach = 0.0;  ///< m, from check_rasterizable
  bool fits = true;    ///< the terrain can take it
};

struct TerrainBody {
  TerrainBodySettings settings;
  ShapeCheck shape;
  /// The body's underside at envelope_pose: this substep's imprint, the next one's contact.
  EnvelopeRaster envelope;
  btTransform envelope_pose = btTransform::getIdentity();
  /// The envelope was made since the terrain last stepped: the next step presses it, even
  /// if the body has come to rest by then.
  bool imprint_pending = false;
  contact_detail::TerrainContact contact;
  /// Where the body was when the terrain last stepped (its envelope pose then), if it had
  /// an envelope: a body that has since moved farther than its footprint is imprinted along
  /// the way, so that a fast or thin one leaves an unbroken track.
  btTransform stepped_pose = btTransform::getIdentity();
  bool stepped_pose_known = false;
  /// This substep's imprint when it is swept from stepped_pose (else the envelope itself).
  EnvelopeRaster swept;

  // This substep's solve (not saved: each substep sets them before reading them).
  /// serve_push ran to its end: serve_press makes the envelope and imprint.
  bool to_press = false;
  /// Its contact's push was solved (it moves under forces, awake, on soft soil).
  bool pushed = false;
  /// Its blocks were solved (not held at rest): solved_body is the solve's body, whose
  /// slip advances the contact memory once every solve of the substep is done.
  bool solved = false;
  contact_detail::SolverBody solved_body;
  /// The change its own soil push made to its motion (a link solved again with the other
  /// links of its multibody takes it out first), and the solve's work and yield, which a
  /// solve again replaces in the statistics.
  btVector3 own_dv{0, 0, 0}, own_dw{0, 0, 0};
  btVector3 solved_impulse{0, 0, 0}, solved_angular_impulse{0, 0, 0};  ///< N s, N m s: its last solve's
  double solved_work = 0.0, solved_shear_work = 0.0;
  bool solved_yielded = false;
};

/// The body's true shape, without Bullet's collision margin: Shore, not Bullet, makes the
/// contact of added bodies with soft soil (and a sharp cylinder rasterizes in closed form).
EnvelopeOptions nominal_solid();

/// Checks a shape the terrain is to take: InvalidSetting if it cannot be rasterized on
/// cells of `cell` m or covers no area seen from below. Returns its reach (check_rasterizable).
double check_terrain_shape(const btCollisionShape& shape, double cell, const EnvelopeOptions& options);

/// Whether the terrain can take the body's present shape: checked again only when the
/// shape or its scaling changed since the last check (then the old envelope is dropped).
bool shape_still_fits(const CoupledBody& body, TerrainBody& record, double cell, const EnvelopeOptions& options);

/// The body's underside at any point, for sub-cell coverage at its footprint's edges.
class ShapeProbe final : public terrain::SurfaceProbe {
 public:
  ShapeProbe(EnvelopeRasterizer& rasterizer, const btCollisionShape& shape, const btTransform& pose)
      : rasterizer_(&rasterizer), shape_(&shape), pose_(pose) {}
  [[nodiscard]] double lower_at(double x, double y) const override {
    return rasterizer_->lower_at(*shape_, pose_, x, y);
  }

 private:
  EnvelopeRasterizer* rasterizer_;
  const btCollisionShape* shape_;
  btTransform pose_;
};

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
