// Buoyancy and drag of one body from its submerged parts (buoyancy.h).
#include <algorithm>
#include <cmath>

#include "shore/core/det_math.h"
#include "shore/core/error.h"
#include "water_forces.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

void FluidSettings::validate() const {
  const Check c{"bullet.FluidSettings"};
  c.positive("density", density);
  c.positive("gravity", gravity);
  c.non_negative("linear_drag", linear_drag);
  c.non_negative("quadratic_drag", quadratic_drag);
  if (samples_per_cell < 1 || samples_per_cell > 16)
    throw InvalidSetting(c.name("samples_per_cell"), detail::to_text(samples_per_cell), "must be in [1, 16]");
}

namespace water_detail {
namespace {

using envelope_detail::cross;
using envelope_detail::dot;
using envelope_detail::norm;

btVector3 bt(V3 v) { return {btScalar(v.x), btScalar(v.y), btScalar(v.z)}; }

/// Drag on area a moving at u: -(1/2 rho C_d a |u| + rho k a) u.
V3 drag_on(double area, V3 u, const FluidSettings& f) {
  const double speed = norm(u);
  return u * (-(0.5 * f.density * f.quadratic_drag * area * speed + f.density * f.linear_drag * area));
}

/// The faces' drag against their velocity relative to the centre of buoyancy (rotation),
/// over each face's quadrature points: a box rolling about its long axis turns half its
/// bottom into the water even though the bottom's centre does not move.
void spin_drag(const Submerged& wet, V3 cb, V3 omega, V3 com, const FluidSettings& f, V3& force, V3& torque) {
  for (const WetFace& face : wet.faces) {
    const double a = norm(face.area);
    if (!(a > 0.0)) continue;
    const V3 n = face.area * (1.0 / a);
    for (int k = face.first_point; k < face.first_point + face.points; ++k) {
      const FacePoint& p = wet.points[std::size_t(k)];
      const V3 u = cross(omega, p.at - cb);
      const double speed = norm(u);
      if (!(speed > 0.0)) continue;
      const double facing = p.weight * dot(n, u) / speed;  // its area projected along u
      if (facing <= 0.0) continue;                           // moving away from the water
      const V3 fd = drag_on(facing, u, f);
      force = force + fd;
      torque = torque + cross(p.at - com, fd);
    }
  }
}

}  // namespace

BodyWater water_forces(const Submerged& wet, double sampled_volume, V3 sampled_moment, const WaterPlane& w,
                       const FluidSettings& fluid, const Motion& m, double h) {
  BodyWater out;
  out.water_level = w.height(m.com.x, m.com.y);
  const double volume = wet.volume + sampled_volume;
  if (!(volume > 0.0)) return out;
  const V3 cb = (wet.moment + sampled_moment) * (1.0 / volume);
  out.submerged_volume = volume;
  out.centre_of_buoyancy = bt(cb);
  const V3 lift{0, 0, fluid.density * fluid.gravity * volume};
  const V3 lift_torque = cross(cb - m.com, lift);
  // The velocity Bullet hands the coupling is the one the body moved with in this substep
  // (gravity added, buoyancy not yet): drag acts on it.
  const V3 v = m.v, omega = m.w;
  // Translation: the whole wet part on the relative velocity of the centre of buoyancy.
  const V3 u = v + cross(omega, cb - m.com) - V3{0, 0, w.vz};
  const double speed = norm(u);
  V3 drag{}, drag_torque{};
  if (speed > 0.0) {
    // Meshes (sampled) have no faces: the area of a ball of their wet volume stands in.
    out.projected_area = projected_area(wet, w, u * (1.0 / speed)) + (sampled_volume > 0.0 ? det::pow(sampled_volume, 2.0 / 3.0) : 0.0);
    drag = drag_on(out.projected_area, u, fluid);
    // Never more than stops the relative motion within the substep.
    const double dv = m.mass > 0.0 ? norm(drag) * h / m.mass : 0.0;  // mass 0: kinematic, moved regardless
    if (dv > speed) drag = drag * (speed / dv);
    drag_torque = cross(cb - m.com, drag);
  }
  V3 spin_force{}, spin_torque{};
  spin_drag(wet, cb, omega, m.com, fluid, spin_force, spin_torque);
  const double spin = norm(omega), dw = (m.inv_inertia * bt(spin_torque)).length() * h;
  if (dw > spin && dw > 0.0) {
    spin_force = spin_force * (spin / dw);
    spin_torque = spin_torque * (spin / dw);
  }
  out.buoyancy = bt(lift);
  out.drag = bt(drag + spin_force);
  out.force = bt(lift + drag + spin_force);
  out.torque = bt(lift_torque + drag_torque + spin_torque);
  return out;
}

}  // namespace water_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
