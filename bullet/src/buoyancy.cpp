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

/// Drag on area a moving at u: -(1/2 rho C_d a |u| + rho k a) u.
Vec3 drag_on(double area, Vec3 u, const FluidSettings& f) {
  const double speed = norm(u);
  return u * (-(0.5 * f.density * f.quadratic_drag * area * speed + f.density * f.linear_drag * area));
}

/// The velocity of a point of the body relative to the water there.
Vec3 relative(const Motion& m, Vec3 p, double water_vz) { return m.v + cross(m.w, p - m.com) - Vec3{0, 0, water_vz}; }

/// Drag over the closed wet surface of the polyhedra: every quadrature point (and the cut)
/// by its own velocity, on half its area projected along it (half, because front and back
/// both count: for a translation the sum is the projected area A exactly, for a spin only the
/// normal motion of the surface acts). Adds force and torque about the centre of mass.
void surface_drag(const Submerged& wet, const WaterPlane& w, const Motion& m, const FluidSettings& f, Vec3& force,
                  Vec3& torque) {
  const auto element = [&](Vec3 at, Vec3 area) {
    const Vec3 u = relative(m, at, w.vz);
    const double speed = norm(u);
    if (!(speed > 0.0)) return;
    const Vec3 fd = drag_on(0.5 * std::abs(dot(area, u)) / speed, u, f);
    force = force + fd;
    torque = torque + cross(at - m.com, fd);
  };
  for (const WetFace& face : wet.faces) {
    const double a = norm(face.area);
    if (!(a > 0.0)) continue;
    const Vec3 n = face.area * (1.0 / a);
    for (int k = face.first_point; k < face.first_point + face.points; ++k)
      element(wet.points[std::size_t(k)].at, n * wet.points[std::size_t(k)].weight);
  }
  if (wet.cut_count > 0) element(wet.cut_points * (1.0 / wet.cut_count), wet.cut);
}

/// Scales drag (force and torque together) down to where its impulse over h would just
/// stop the articulated body's motion relative to the water along that impulse: with
/// J = (F, T) h and u the relative (v, w) at the centre, J . u + J^T A J <= 0. J . u is the
/// drag's work on the body (never positive: each element opposes its own relative motion),
/// and J^T A J what the impulse itself adds to the multibody's kinetic energy.
void limit_articulated(const Motion& m, double water_vz, double h, Vec3& drag, Vec3& drag_torque) {
  const Vec3 u_lin = m.v - Vec3{0, 0, water_vz};
  const double u[6] = {u_lin.x, u_lin.y, u_lin.z, m.w.x, m.w.y, m.w.z};
  const double j[6] = {drag.x * h, drag.y * h, drag.z * h, drag_torque.x * h, drag_torque.y * h, drag_torque.z * h};
  double work = 0.0, response = 0.0;
  for (int r = 0; r < 6; ++r) {
    work += j[r] * u[r];
    for (int c = 0; c < 6; ++c) response += j[r] * m.mobility[r][c] * j[c];
  }
  if (!(work < 0.0)) {  // no drag (or rounding's): nothing to oppose
    drag = Vec3{}, drag_torque = Vec3{};
    return;
  }
  if (response > -work) {
    const double scale = -work / response;
    drag = drag * scale, drag_torque = drag_torque * scale;
  }
}

}  // namespace

BodyWater water_forces(const Submerged& wet, double sampled_volume, Vec3 sampled_moment, const WaterPlane& w,
                       const FluidSettings& fluid, const Motion& m, double h) {
  BodyWater out;
  out.water_level = w.height(m.com.x, m.com.y);
  const double volume = wet.volume + sampled_volume;
  if (!(volume > 0.0)) return out;
  const Vec3 cb = (wet.moment + sampled_moment) * (1.0 / volume);
  out.submerged_volume = volume;
  out.centre_of_buoyancy = to_bt(cb);
  const Vec3 lift{0, 0, fluid.density * fluid.gravity * volume};
  const Vec3 lift_torque = cross(cb - m.com, lift);
  // The velocity Bullet hands the coupling is the one the body moved with in this substep
  // (gravity added, buoyancy not yet): drag acts on it. Polyhedra: over their surface;
  // balls: their centre's motion (a spin moves no surface along its normal); meshes: the
  // area of a ball of their wet volume at their centre of buoyancy.
  Vec3 drag{}, drag_torque{};
  surface_drag(wet, w, m, fluid, drag, drag_torque);
  for (const WetBall& b : wet.balls) {
    const Vec3 u = relative(m, b.centre, w.vz);
    const double speed = norm(u);
    if (!(speed > 0.0)) continue;
    const WetBall one[1] = {b};
    Submerged alone;
    alone.balls.assign(one, one + 1);
    const Vec3 fd = drag_on(projected_area(alone, w, u * (1.0 / speed)), u, fluid);
    drag = drag + fd;
    drag_torque = drag_torque + cross(b.centre - m.com, fd);
  }
  const Vec3 uc = relative(m, cb, w.vz);
  const double speed = norm(uc);
  if (sampled_volume > 0.0 && speed > 0.0) {
    const Vec3 fd = drag_on(det::pow(sampled_volume, 2.0 / 3.0), uc, fluid);
    drag = drag + fd;
    drag_torque = drag_torque + cross(cb - m.com, fd);
  }
  if (speed > 0.0) out.projected_area = projected_area(wet, w, uc * (1.0 / speed));
  // Never more than stops the relative motion (or the spin) within the substep; a mass of
  // 0 (kinematic) is moved regardless.
  if (m.articulated) {
    limit_articulated(m, w.vz, h, drag, drag_torque);
  } else if (m.mass > 0.0) {
    const double dv = norm(drag) * h / m.mass;
    if (dv > speed) drag = drag * (speed / std::max(dv, 1e-300));
    const double spin = norm(m.w), dw = (m.inv_inertia * to_bt(drag_torque)).length() * h;
    if (dw > spin) drag_torque = drag_torque * (spin / std::max(dw, 1e-300));
  }
  out.buoyancy = to_bt(lift);
  out.drag = to_bt(drag);
  out.force = to_bt(lift + drag);
  out.torque = to_bt(lift_torque + drag_torque);
  return out;
}
}  // namespace water_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
