// WaterCoupling: its bodies, and its substep: each body floated (buoyancy and drag as
// impulses), the water it displaces, then the surface stepped.
#include "shore/bullet/water_coupling.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "coupled_rigid_body.h"
#include "coupling_directory.h"
#include "coupling_util.h"
#include "framed_body.h"
#include "shore/core/error.h"
#include "shore/terrain/terrain.h"
#include "water_coupling_parts.h"
#include "water_forces.h"
#include "water_submersion.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

using coupling_detail::Clock;
using coupling_detail::seconds_since;
using envelope_detail::Frame;
namespace {
using Directory = coupling_detail::WorldDirectory<WaterCoupling>;
}  // namespace

void WaterCouplingSettings::validate() const {
  fluid.validate();
  const Check c{"bullet.WaterCouplingSettings"};
  c.in_closed("displacement_gain", displacement_gain, 0.0, 1.0);
  if (smoothing_passes < 0 || smoothing_passes > 8)
    throw InvalidSetting(c.name("smoothing_passes"), detail::to_text(smoothing_passes), "must be in [0, 8]");
  c.positive("max_speed", max_speed);
  frame.validate("bullet.WaterCouplingSettings.frame");
}

WaterCoupling::WaterCoupling(btDiscreteDynamicsWorld& world, water::Surface& surface, WaterCouplingSettings settings)
    : world_(world),
      surface_(surface),
      settings_(std::move(settings)),
      parts_(std::make_unique<Parts>(world_, surface_, settings_, stats_)) {
  settings_.fluid.density = surface.density();
  settings_.validate();
  world_.addAction(this);
  Directory::enter(&world_, this);
}

WaterCoupling::~WaterCoupling() { detach(); }

void WaterCoupling::detach() {
  if (detached_) return;
  parts_->bodies.clear();
  parts_->vehicles.clear();
  world_.removeAction(this);
  Directory::leave(this);
  detached_ = true;
}

namespace {
/// The rectangle a surface covers: node (i, j) stands for the cell of side h around it.
Region area_of(const water::Surface& s) {
  const double h = s.spacing();
  return {s.node_x(0) - 0.5 * h, s.node_y(0) - 0.5 * h, s.node_x(s.nx() - 1) + 0.5 * h, s.node_y(s.ny() - 1) + 0.5 * h};
}

void check_pose(const btCollisionObject& body, const coupling_detail::Motion& motion) {
  const btTransform& t = body.getWorldTransform();
  const Frame f = envelope_detail::frame_of(t);
  const auto bad = [](double v) { return !std::isfinite(v); };
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (bad(f.r[r][c]))
        throw InvalidSetting("bullet.WaterCoupling.add_body pose", "rotation " + detail::to_text(f.r[r][c]),
                             "must be finite");
  if (bad(f.t.x) || bad(f.t.y) || bad(f.t.z))
    throw InvalidSetting(
        "bullet.WaterCoupling.add_body pose",
        "position (" + detail::to_text(f.t.x) + ", " + detail::to_text(f.t.y) + ", " + detail::to_text(f.t.z) + ")",
        "must be finite");
  if (!(envelope_detail::basis_deviation(f) <= kMaxBasisDeviation))
    throw InvalidSetting("bullet.WaterCoupling.add_body pose", detail::to_text(envelope_detail::basis_deviation(f)),
                         "the basis must be a rotation (deviation <= " + detail::to_text(kMaxBasisDeviation) + ")");
  if (!coupling_detail::finite(motion.linear) || !coupling_detail::finite(motion.angular))
    throw InvalidSetting("bullet.WaterCoupling.add_body velocity", "not finite", "must be finite");
}
}  // namespace

void WaterCoupling::add_body(btRigidBody* body, WaterBodySettings body_settings) {
  const char* what = "bullet.WaterCoupling.add_body(body)";
  if (body == nullptr) throw InvalidSetting(what, "null", "must be a rigid body");
  if (detached_) throw InvalidSetting(what, "after detach()", "a detached coupling takes no bodies: make a new one");
  if (body->getCollisionShape() == nullptr)
    throw InvalidSetting("bullet.WaterCoupling.add_body shape", "null", "the body must have a collision shape");
  check_pose(*body, coupling_detail::CoupledRigidBody(*body).motion());
  parts_->enroll(*this,
                 coupling_detail::couple(std::make_unique<coupling_detail::CoupledRigidBody>(*body), settings_.frame),
                 body_settings, what, "body");
}

void WaterCoupling::Parts::enroll(const WaterCoupling& self, std::unique_ptr<coupling_detail::CoupledBody> coupled,
                                  WaterBodySettings body_settings, const char* what, const char* kind) {
  const btCollisionObject& object = coupled->object();
  Directory::for_each_other(&world, &self, [&](const WaterCoupling& other) {
    const Region mine = area_of(surface), theirs = area_of(other.surface_);
    if (other.parts_->bodies.find(&object) == nullptr || !theirs.overlaps(mine)) return;
    throw InvalidSetting(
        what,
        coupling_detail::body_text(object) + ", already in another WaterCoupling of this world whose " + "water " +
            coupling_detail::region_text(theirs) + " overlaps this one's " + coupling_detail::region_text(mine),
        std::string("a ") + kind +
            " may be in several water couplings only if their surfaces do not overlap (else "
            "both would float it): remove_body it from the other first");
  });
  coupling_detail::WaterBody record;
  record.settings = body_settings;
  record.shape = water_detail::prepare_shape(*object.getCollisionShape());
  if (record.shape.sampled) {
    const EnvelopeGrid grid = coupling_detail::sub_grid(surface, settings.fluid.samples_per_cell);
    (void)check_rasterizable(*object.getCollisionShape(), grid.cell, coupling_detail::nominal_with_upper());
    record.rasterizer = std::make_unique<EnvelopeRasterizer>(grid, coupling_detail::nominal_with_upper());
  }
  Entry& added = bodies.add(std::move(coupled), std::move(record));
  if (added.record.settings.disturb) displace(added);  // tracking starts at this pose
}

void WaterCoupling::remove_body(const btCollisionObject* body) {
  for (const coupling_detail::WaterVehicle& v : parts_->vehicles)  // not a wheel's object: remove_vehicle
    if (std::find(v.wheels.begin(), v.wheels.end(), body) != v.wheels.end()) return;
  parts_->bodies.remove(body);
}

std::vector<const btCollisionObject*> WaterCoupling::bodies() const {
  std::vector<const btCollisionObject*> out;
  out.reserve(parts_->bodies.size());
  for (const Parts::Entry& e : parts_->bodies)
    if (&e.body->held() == &e.body->object()) out.push_back(&e.body->object());  // a wheel's is its chassis
  return out;
}

double WaterCoupling::submerged_volume(const btCollisionObject* body) const {
  const Parts::Entry* e = parts_->bodies.find(body);
  return e != nullptr ? e->record.last.submerged_volume : 0.0;
}

BodyWater WaterCoupling::water_force(const btCollisionObject* body) const {
  const Parts::Entry* e = parts_->bodies.find(body);
  return e != nullptr ? parts_->in_world(*e) : BodyWater{};
}

BodyWater WaterCoupling::Parts::in_world(const Entry& e) const {
  BodyWater b = e.record.last;  // in the water's coordinates
  if (!settings.frame.identity()) {
    const GroundFrame& f = settings.frame;
    b.centre_of_buoyancy = f.to_world()(b.centre_of_buoyancy);
    b.buoyancy = f.direction_to_world(b.buoyancy), b.drag = f.direction_to_world(b.drag);
    b.force = f.direction_to_world(b.force), b.torque = f.direction_to_world(b.torque);
  }
  return b;
}

int WaterCoupling::fix_shoreline(const terrain::Terrain& ground) {
  const double level = surface_.settings().rest_height;
  int fixed = 0;
  for (int j = 0; j < surface_.ny(); ++j)
    for (int i = 0; i < surface_.nx(); ++i) {
      const double x = surface_.node_x(i), y = surface_.node_y(j);
      if (ground.height(ground.column_i(x), ground.column_j(y)) > level) {
        surface_.set_fixed(i, j, true);
        ++fixed;
      }
    }
  return fixed;
}

void WaterCoupling::updateAction(btCollisionWorld*, btScalar substep) {
  ++stats_.substeps;
  // First: nothing below may read a body the world no longer holds.
  stats_.lost_bodies += parts_->bodies.forget_lost(world_);
  parts_->forget_lost_vehicles();
  const auto t0 = Clock::now();
  for (Parts::Entry& e : parts_->bodies) parts_->float_body(e, substep);
  stats_.coupling_seconds = seconds_since(t0);
  if (settings_.step_water) {
    const auto t1 = Clock::now();
    stats_.water_substeps = surface_.step(substep).substeps;
    stats_.water_seconds = seconds_since(t1);
  }
}

void WaterCoupling::Parts::float_body(Entry& e, double h) {
  coupling_detail::CoupledBody& body = *e.body;
  coupling_detail::WaterBody& b = e.record;
  const Frame f = envelope_detail::frame_of(body.pose());
  if (!coupling_detail::body_is_sane(body, settings.max_speed) ||
      !(envelope_detail::basis_deviation(f) <= kMaxBasisDeviation)) {  // never poison the water
    ++stats.skipped_bodies;
    return;
  }
  btVector3 lo, hi;
  body.shape()->getAabb(body.pose(), lo, hi);
  const GridRect inner = water_detail::window_under(surface, lo, hi, 0);
  const GridRect win = water_detail::window_under(surface, lo, hi, 2);
  coupling_detail::WaterWorkspace& w = work;
  surface.heights_above_rest(win.i0, win.j0, win.nx, win.ny, w.heights);
  surface.vertical_velocities(win.i0, win.j0, win.nx, win.ny, w.velocities);
  const water_detail::WaterPlane plane = water_detail::fit_plane(surface, win, inner, w.heights, w.velocities);
  water_detail::part_frames(b.shape, f, w.frames, w.planes);
  water_detail::submerge(b.shape, w.frames, plane, b.wet);
  double sampled_volume = 0.0;
  Vec3 sampled_moment{};
  if (b.shape.sampled)
    water_detail::submerge_sampled(b.shape, w.frames, plane, *b.rasterizer, sampled_volume, sampled_moment);
  const coupling_detail::Motion motion = body.motion();
  water_detail::Motion m;
  m.com = to_vec3(motion.centre);
  m.v = to_vec3(motion.linear);
  m.w = to_vec3(motion.angular);
  const double inv_mass = body.inverse_mass();
  m.mass = inv_mass > 0 ? 1.0 / inv_mass : 0.0;
  m.inv_inertia = body.inverse_inertia();
  // A link answers through its whole articulation (a rigid body held to some axes through
  // its mobility), even where its mass along up is infinite (an arm's blade hanging
  // straight down cannot move up).
  m.articulated = body.dynamic() && body.mobility(m.mobility);
  b.last = water_detail::water_forces(b.wet, sampled_volume, sampled_moment, plane, settings.fluid, m, h);
  const bool moves = m.articulated || m.mass > 0.0;  // kinematic and static bodies: reported, not applied
  if (moves && b.last.submerged_volume > 0.0) {
    body.apply_impulse(b.last.force * btScalar(h), b.last.torque * btScalar(h));
    body.wake();
  }
  surface.wake(lo.x(), lo.y(), hi.x(), hi.y());
  if (b.settings.disturb) displace(e);
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
