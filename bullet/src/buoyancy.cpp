#include "shore/bullet/buoyancy.h"

#include <algorithm>
#include <cmath>

#include "shore/core/error.h"

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

namespace {
/// Visits every sample the body covers with its submerged segment [bottom, top].
template <class Visit>
void for_each_wet_sample(const EnvelopeRaster& env, double origin_x, double origin_y, double cell,
                         const WaterSampler& water, Visit&& visit) {
  const bool has_upper = !env.upper.empty();
  for (int b = 0; b < env.ny; ++b)
    for (int a = 0; a < env.nx; ++a) {
      const std::size_t k =
          static_cast<std::size_t>(b) * static_cast<std::size_t>(env.nx) + static_cast<std::size_t>(a);
      if (!env.covers(k)) continue;
      const double x = origin_x + double(env.i0 + a) * cell, y = origin_y + double(env.j0 + b) * cell;
      const double surface = water.height(x, y);
      const double bottom = env.lower[k];
      const double top = has_upper ? env.upper[k] : bottom;
      const double wet_top = std::min(top, surface);
      if (wet_top > bottom) visit(k, x, y, bottom, wet_top);
    }
}
}  // namespace

double submerged_lengths(const EnvelopeRaster& env, double origin_x, double origin_y, double sample_cell,
                         const WaterSampler& water, std::vector<double>& lengths) {
  lengths.assign(env.lower.size(), 0.0);
  double volume = 0.0;
  for_each_wet_sample(env, origin_x, origin_y, sample_cell, water,
                      [&](std::size_t k, double, double, double bottom, double top) {
                        lengths[k] = top - bottom;
                        volume += (top - bottom) * sample_cell * sample_cell;
                      });
  return volume;
}

WaterImpulse water_impulse(const EnvelopeRaster& env, double origin_x, double origin_y, double sample_cell,
                           const WaterSampler& water, const FluidSettings& fluid, const btVector3& com,
                           const btVector3& v, const btVector3& w, double body_mass, double h) {
  WaterImpulse out;
  const double area = sample_cell * sample_cell;
  double vol = 0.0, cx = 0.0, cy = 0.0, cz = 0.0;
  btVector3 drag(0, 0, 0), drag_torque(0, 0, 0), mean_rel(0, 0, 0);
  for_each_wet_sample(env, origin_x, origin_y, sample_cell, water,
                      [&](std::size_t, double x, double y, double bottom, double top) {
                        const double s = top - bottom, dv = s * area;
                        vol += dv;
                        cx += dv * x;
                        cy += dv * y;
                        cz += dv * 0.5 * (bottom + top);
                        // Drag on the wetted part: the bottom face (area) for vertical motion,
                        // the side strip (s * sample_cell) for horizontal motion.
                        const btVector3 at(btScalar(x), btScalar(y), btScalar(0.5 * (bottom + top)));
                        const btVector3 r = at - com;
                        btVector3 u = v + w.cross(r);
                        if (water.velocity) u -= water.velocity(x, y);
                        const double speed = u.length();
                        const double side = s * sample_cell;
                        const btVector3 wetted{btScalar(side), btScalar(side), btScalar(area)};
                        const double k = fluid.density * (fluid.linear_drag + 0.5 * fluid.quadratic_drag * speed);
                        const btVector3 f = -btScalar(k) * (u * wetted);
                        drag += f;
                        drag_torque += r.cross(f);
                        mean_rel += u * btScalar(dv);
                      });
  out.submerged_volume = vol;
  if (vol <= 0.0) return out;
  out.centroid = btVector3(btScalar(cx / vol), btScalar(cy / vol), btScalar(cz / vol));
  const btVector3 buoyancy(0, 0, btScalar(fluid.density * fluid.gravity * vol * h));
  // Drag may slow the body relative to the water, never reverse it within a substep.
  btVector3 drag_impulse = drag * btScalar(h), drag_angular = drag_torque * btScalar(h);
  const double rel_speed = (mean_rel / btScalar(vol)).length();
  const double dv_drag = drag_impulse.length() / body_mass;
  if (dv_drag > rel_speed && dv_drag > 0.0) {
    const btScalar scale = btScalar(rel_speed / dv_drag);
    drag_impulse *= scale;
    drag_angular *= scale;
  }
  out.linear = buoyancy + drag_impulse;
  out.angular = (out.centroid - com).cross(buoyancy) + drag_angular;
  return out;
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
