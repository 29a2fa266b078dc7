// TerrainCoupling's substep, stage by stage (docs/ARCHITECTURE.md, "One substep"), and each
// body's path through it.
#include "shore/bullet/terrain_coupling.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include "bedrock_rescue.h"
#include "bt_convert.h"
#include "contact_solver.h"
#include "coupled_multibody_link.h"
#include "coupling_util.h"
#include "rest_hold.h"
#include "terrain_coupling_parts.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

using contact_detail::ContactState;
using coupling_detail::Clock;
using coupling_detail::CoupledBody;
using coupling_detail::seconds_since;
using coupling_detail::TerrainBody;

void TerrainCoupling::updateAction(btCollisionWorld*, btScalar substep) {
  Parts& p = *parts_;
  const double h = substep;
  ++stats_.substeps;
  stats_.envelope_seconds = stats_.terrain_seconds = stats_.push_seconds = stats_.reaction_seconds = 0.0;
  stats_.resting_bodies = 0;
  // 0. Nothing below may read a body the world no longer holds; tiles around every body.
  stats_.lost_bodies += p.bodies.forget_lost(world_) + p.wheels.forget_lost(world_);
  const auto t0 = Clock::now();
  p.cover_bodies(h);
  stats_.push_seconds += seconds_since(t0);
  // 1.-3. Each body: sanity, its contact solved, its envelope and imprint; each raycast
  // wheel: its rut and resistance.
  p.imprints.clear();
  const bool deforms = p.clock.advance(h, settings_.step_interval);
  for (Parts::Entry& e : p.bodies) p.serve_push(e, h);
  if (!p.rigid) {
    const auto t1 = Clock::now();
    p.solve_links_together(h);
    stats_.reaction_seconds += seconds_since(t1);
    p.advance_memories(h);
  }
  for (Parts::Entry& e : p.bodies) p.serve_press(e, h, deforms);
  p.wheels.set_soil_step(p.clock.seconds());
  if (!p.rigid) p.wheels.serve(p.terrain, p.rasterizer, h, deforms, p.imprints);
  // 4. The terrain deforms with the imprints (once per step_interval).
  stats_.active_columns = stats_.erosion_passes = 0;
  if (deforms) {
    p.step_terrain();
    for (Parts::Entry& e : p.bodies) {  // where the next step's sweeps start
      e.record.stepped_pose = e.record.envelope_pose;
      e.record.stepped_pose_known = !e.record.envelope.lower.empty();
    }
  }
  // 5. Its changes go into the tiles.
  p.push_changes();
  for (Parts::Entry& e : p.bodies) {  // the start of the next substep, for the terrain's work
    const coupling_detail::Motion m = e.body->motion();
    e.record.contact.end = contact_detail::EndMotion{m.linear, m.angular};
  }
}

void TerrainCoupling::Parts::cover_bodies(double h) {
  const double margin = settings.cover_margin;
  const std::uint64_t pass = ++cover_pass;
  // Any object that moves gets ground under it: rigid bodies (their reach grows with their
  // speed), and ghost objects, character capsules and other collision objects a game moves
  // itself, whose reach grows with how far they moved since the last substep (Bullet knows
  // no velocity of theirs: with the margin alone, a character moving 2 m a step walked off
  // its ground and fell through the world).
  auto cover = [&](btCollisionObject& object) {
    if (object.isStaticObject() || object.getCollisionShape() == nullptr) return;
    const btRigidBody* body = btRigidBody::upcast(&object);
    // A multibody's links, like rigid bodies, meet soft tiles through their own masks.
    const btMultiBodyLinkCollider* link = btMultiBodyLinkCollider::upcast(&object);
    if (body == nullptr && link == nullptr) show_soft_tiles(object);
    const btVector3 zero(0, 0, 0);
    const coupling_detail::Motion link_motion =
        link != nullptr ? coupling_detail::link_motion(world, *link) : coupling_detail::Motion{};
    const btVector3& v = body != nullptr ? body->getLinearVelocity() : link != nullptr ? link_motion.linear : zero;
    const btVector3& w = body != nullptr ? body->getAngularVelocity() : link != nullptr ? link_motion.angular : zero;
    if (!coupling_detail::motion_is_sane(object.getWorldTransform(), v, w, settings.max_speed)) return;
    btVector3 lo, hi;
    object.getCollisionShape()->getAabb(in_ground(object.getWorldTransform()), lo, hi);
    const btVector3 centre = (lo + hi) * btScalar(0.5);
    const auto [last, fresh] = covered_at.try_emplace(&object, CoveredAt{centre, pass});
    const double moved = fresh ? 0.0 : double((centre - last->second.centre).length());
    last->second = {centre, pass};
    const double reach = margin + 2.0 * std::max(h * v.length(), moved);
    tiles.ensure_cover(lo.x() - reach, lo.y() - reach, hi.x() + reach, hi.y() + reach);
  };
  if (settings.cover_all_bodies) {
    const btCollisionObjectArray& objects = world.getCollisionObjectArray();
    for (int k = 0; k < objects.size(); ++k) cover(*objects[k]);
  } else {
    for (const Entry& e : bodies) cover(e.body->object());
  }
  // Objects not covered in this pass (gone from the world, or skipped) are forgotten.
  std::erase_if(covered_at, [&](const auto& e) { return e.second.pass != pass; });
}

bool TerrainCoupling::Parts::on_terrain(const btVector3& world_point) const {
  const btVector3 at = in_ground(world_point);
  const double x = at.x(), y = at.y();
  if (!settings.region.contains(x, y)) return false;
  // Within two cells' height of the surface there: the tile's triangles, not something
  // lying on the terrain (a rock, a plank) that a ray met first.
  const double surface = terrain.height(terrain.column_i(x), terrain.column_j(y));
  return std::abs(double(at.z()) - surface) <= 2.0 * terrain.settings().cell;
}

void TerrainCoupling::Parts::show_soft_tiles(btCollisionObject& object) {
  btBroadphaseProxy* proxy = object.getBroadphaseHandle();
  const int bit = settings.terrain_filter_bit;
  if (rigid || proxy == nullptr || (proxy->m_collisionFilterMask & btBroadphaseProxy::StaticFilter) == 0 ||
      (proxy->m_collisionFilterMask & bit) != 0)
    return;
  proxy->m_collisionFilterMask |= bit;
  world.refreshBroadphaseProxy(&object);  // pairs with the tiles that exist already
}

namespace {

/// A moving body's imprint: its envelope, and for spray its motion (after the terrain's
/// push), pose and key.
terrain::Imprint moving_imprint(const EnvelopeRaster& envelope, const CoupledBody& body, bool spray) {
  terrain::Imprint im{&envelope};
  const coupling_detail::Motion m = body.motion();
  const btQuaternion q = body.pose().getRotation();
  im.velocity = to_vec3(m.linear), im.angular_velocity = to_vec3(m.angular);
  im.centre = to_vec3(m.centre);
  im.orientation = {q.w(), q.x(), q.y(), q.z()};
  im.key = body.key();
  im.spray = spray && body.proxy() != nullptr;  // a body outside the world has no stable key: it does not spray
  return im;
}

/// A body at rest holds the terrain it touches without pressing it again.
terrain::Imprint holding_imprint(const EnvelopeRaster& envelope) {
  terrain::Imprint hold{&envelope};
  hold.hold = true;
  return hold;
}

}  // namespace

void TerrainCoupling::Parts::serve_push(Entry& e, double h) {
  CoupledBody& body = *e.body;
  TerrainBody& b = e.record;
  b.to_press = b.pushed = b.solved = false;
  // 1. Sanity: a broken pose or an absurd speed never reaches the grid.
  if (!sane(body) || (b.settings.deform && !shape_still_fits(body, b, rasterizer.grid().cell, rasterizer.options()))) {
    ++stats.skipped_bodies;
    return;
  }
  if (!b.settings.deform) return;
  own_terrain_contact(body);
  if (!overlaps_region(body)) {  // nothing to do here (another terrain's region, say)
    b.envelope.lower.clear();
    b.contact.state = ContactState::none;
    return;
  }
  // 2. The terrain's push, on bodies that move under forces.
  if (body.dynamic() && body.awake() && !rigid) {
    const auto t0 = Clock::now();
    solve_contact(e, h);  // reads the envelope of the previous substep
    stats.reaction_seconds += seconds_since(t0);
    b.pushed = true;
  }
  b.to_press = true;
}

void TerrainCoupling::Parts::serve_press(Entry& e, double h, bool deforms) {
  CoupledBody& body = *e.body;
  TerrainBody& b = e.record;
  if (!b.to_press) return;
  // A body the terrain holds at rest presses nothing new: imprinting it again would only
  // re-press soil that erosion slid back under its sides, inflating sinkage forever. One
  // that creeps away from where it was imprinted is imprinted again.
  bool moved = true;
  if (b.pushed) {
    const coupling_detail::Motion m = body.motion();
    moved = b.envelope.lower.empty() || m.linear.length() > settings.rest_speed ||
            m.angular.length() > settings.rest_spin || drifted(e);
  }
  // 3. Its envelope and imprint.
  if (!body.awake() || !moved) {
    // At rest its last envelope holds the terrain it touches: slopes still eroding next to
    // it cannot slide under it. It presses nothing and keeps its contact.
    if (b.envelope.lower.empty()) return;
    b.contact.state = ContactState::resting;
    imprints.push_back(b.imprint_pending ? moving_imprint(b.envelope, body, b.settings.spray)  // pressed once
                                         : holding_imprint(b.envelope));
    return;
  }
  // Between terrain steps a body whose contact can follow it needs no new envelope.
  if (!deforms && !needs_envelope(e, h)) return;
  if (!can_rasterize(e)) {  // a pose the envelope cannot take (not a rotation, say): skip, never poison the grid
    ++stats.skipped_bodies;
    b.envelope.lower.clear();
    b.contact.state = ContactState::none;
    return;
  }
  const auto t0 = Clock::now();
  rasterize(e);  // at the (corrected) pose: this substep's imprint, next substep's contact
  stats.envelope_seconds += seconds_since(t0);
  if (body.dynamic() && !rigid && coupling_detail::keep_above_bedrock(body, b.envelope, terrain, base_scratch))
    ++stats.rescues;
  imprints.push_back(moving_imprint(deforms ? pressed(e) : b.envelope, body, b.settings.spray));
}

namespace {

/// Solves of a multibody's links in a substep (solve_links_together): the first, one after
/// another, then this many less one again. The rover at 1/60 s (its wheels' deepest rut
/// and slip, with its links added in either order): 1 pass 101 / 246 mm; 4 passes 38 /
/// 79 mm; 6 passes 37 / 37 mm, 13 % slip (12 passes: 38 / 38 mm, 11 %).
constexpr int kLinkPasses = 6;

contact_detail::SolverBody solver_body(const CoupledBody& body) {
  const coupling_detail::Motion m = body.motion();
  contact_detail::SolverBody rb;
  rb.v = to_vec3(m.linear);
  rb.w = to_vec3(m.angular);
  rb.com = to_vec3(m.centre);
  rb.inv_mass = body.inverse_mass();
  const btMatrix3x3 inv = body.inverse_inertia();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) rb.inv_inertia[r][c] = inv[r][c];
  rb.articulated = body.mobility(rb.mobility);
  return rb;
}

/// How the blocks being solved came to be: built or followed this substep, kept at rest,
/// or solved already this substep and solved again (solve_links_together).
enum class Blocks { built, followed, kept_at_rest, again };

/// Solves the body's blocks for this substep and applies the result: velocities corrected,
/// pose re-integrated, the terrain's force recorded; the solve kept for the per-column
/// memory (advance_memories). Solved again, the body's own last push is taken out of its
/// motion first and its blocks start from the impulses they ended with: the statistics
/// then count the last solve only.
void solve_blocks(CoupledBody& body, TerrainBody& b, Blocks blocks, const TerrainCouplingSettings& settings,
                  TerrainCouplingStats& stats, double h) {
  contact_detail::TerrainContact& c = b.contact;
  if (c.blocks.empty()) return;
  contact_detail::SolverBody rb = solver_body(body);
  const bool again = blocks == Blocks::again;
  if (again) rb.v = rb.v - to_vec3(b.own_dv), rb.w = rb.w - to_vec3(b.own_dw);
  const Vec3 free_v = rb.v, free_w = rb.w;
  // The blocks' points are the body's surface where the contact was built (the envelope's
  // pose: before Bullet moved the body on by a substep, more while the contact follows it),
  // so their arms are taken from the centre of mass there too. Taken from where it is now,
  // every push would act a substep's travel behind the body and turn it: a driven wheel's
  // load a few mm behind its axle resists its drive. Any kind maps the same way (a link's
  // centre is its frame's origin, a rigid body's its pose's), as the pose and the centre
  // move together.
  rb.com = to_vec3(b.envelope_pose * (body.pose().inverse() * to_bt(rb.com)));
  contact_detail::SolverBody start = rb;
  if (c.end) start.v = to_vec3(c.end->linear), start.w = to_vec3(c.end->angular);
  if (blocks == Blocks::followed) {
    c.follow(start, h);
    ++stats.contacts_followed;
  }
  const bool resting = blocks == Blocks::kept_at_rest;
  const contact_detail::SolverSettings solver{
      settings.contact.block_columns, resting ? settings.contact.resting_iterations : settings.contact.iterations,
      resting};
  contact_detail::SolveResult r = contact_detail::solve(rb, start, c.blocks, h, solver);
  // Solved again, its change is applied as an impulse (below), which the sway stop is not.
  if (r.stuck && !again) contact_detail::stop_sway(body, {settings.rest_speed, settings.rest_spin}, rb, r);
  if (again) {
    // Solved again: the change of its push itself, through the articulation (exact, where
    // a velocity change would be matched through the inverse of the link's mobility); the
    // joints move once, after the last solve (solve_links_together), so every solve of the
    // substep sees one configuration.
    body.apply_impulse(to_bt(r.impulse) - b.solved_impulse, to_bt(r.angular_impulse) - b.solved_angular_impulse);
  } else {
    body.correct_motion(to_bt(rb.v), to_bt(rb.w), h);
  }
  b.solved_impulse = to_bt(r.impulse), b.solved_angular_impulse = to_bt(r.angular_impulse);
  b.own_dv = to_bt(rb.v - free_v), b.own_dw = to_bt(rb.w - free_w);

  if (again) {
    stats.plastic_work -= b.solved_work;
    stats.shear_work -= b.solved_shear_work;
    if (b.solved_yielded) --stats.yields;
  }
  stats.plastic_work += r.work;
  stats.shear_work += r.shear_work;
  if (r.yielded) ++stats.yields;
  b.solved_work = r.work, b.solved_shear_work = r.shear_work, b.solved_yielded = r.yielded;
  c.last.force = to_bt(r.impulse * (1.0 / h));
  c.last.torque = to_bt(r.angular_impulse * (1.0 / h));
  c.last.normal_force = to_bt(r.normal_impulse * (1.0 / h));
  c.last.contact_columns = c.patch.touching_columns;
  c.last.yielded = r.yielded;
  b.solved = !resting;
  if (b.solved) b.solved_body = rb;
}

}  // namespace

void TerrainCoupling::Parts::solve_links_together(double h) {
  // The multibodies with more than one link solved this substep, each with its links'
  // entries in the order served (few multibodies: a linear search).
  thread_local std::vector<std::pair<btMultiBody*, std::vector<std::size_t>>> groups;
  thread_local btAlignedObjectArray<btQuaternion> scratch_q;
  thread_local btAlignedObjectArray<btVector3> scratch_o;
  groups.clear();
  for (std::size_t k = 0; k < bodies.size(); ++k) {
    if (!bodies[k].record.solved) continue;
    const auto* link = btMultiBodyLinkCollider::upcast(&bodies[k].body->object());
    if (link == nullptr) continue;
    auto group =
        std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return g.first == link->m_multiBody; });
    if (group == groups.end()) {
      groups.emplace_back(link->m_multiBody, std::vector<std::size_t>{});
      group = groups.end() - 1;
    }
    group->second.push_back(k);
  }
  for (const auto& [multibody, links] : groups) {
    if (links.size() < 2) continue;
    btMultiBody& mb = *multibody;
    const std::vector<btScalar> first = coupling_detail::generalized_velocity(mb);
    for (int pass = 1; pass < kLinkPasses; ++pass)
      for (std::size_t q = 0; q < links.size(); ++q) {
        const std::size_t k = links[pass % 2 == 1 ? links.size() - 1 - q : q];
        solve_blocks(*bodies[k].body, bodies[k].record, Blocks::again, settings, stats, h);
      }
    // The joints move by what the solves after the first changed, as Bullet's integration
    // would have moved them.
    std::vector<btScalar> change = coupling_detail::generalized_velocity(mb);
    for (std::size_t i = 0; i < change.size(); ++i) change[i] -= first[i];
    coupling_detail::step_positions(mb, change, h, scratch_q, scratch_o);
  }
}

void TerrainCoupling::Parts::advance_memories(double h) {
  for (Entry& e : bodies) {
    TerrainBody& b = e.record;
    if (!b.solved) continue;
    contact_detail::TerrainContact& c = b.contact;
    c.memory.advance(c.patch.elements, b.envelope, b.solved_body, c.blocks, settings.contact.block_columns, h);
  }
}

// The terrain's push on one dynamic body, by where its contact stands (ContactState). Its
// contact was made where the body stood at the start of this substep (the envelope kept
// from the end of the previous one): Bullet has since applied gravity and integrated freely,
// since it does not collide this body with soft tiles.
void TerrainCoupling::Parts::solve_contact(Entry& e, double h) {
  CoupledBody& body = *e.body;
  TerrainBody& b = e.record;
  contact_detail::TerrainContact& c = b.contact;
  if (body.inverse_mass() <= 0.0) {
    c.last = {};
    return;
  }
  switch (c.state) {
    case ContactState::none:  // no envelope over the terrain
      c.last = {};
      return;
    case ContactState::resting:
      // Last substep's impulse holds it: a few dozen operations. If not (something pushed
      // it), its kept contact is solved again, from last substep's impulses.
      ++stats.resting_bodies;
      if (contact_detail::hold_at_rest(body, c.last, {settings.rest_speed, settings.rest_spin}, h)) return;
      c.last = {};
      solve_blocks(body, b, Blocks::kept_at_rest, settings, stats, h);
      return;
    case ContactState::following:
      // No envelope since the last solve: the blocks move with the body (from its motion at
      // the end of the last substep) until they have drifted follow_drift.
      c.last = {};
      if (c.end) {
        solve_blocks(body, b, Blocks::followed, settings, stats, h);
        return;
      }
      [[fallthrough]];  // its motion then unknown: built afresh
    case ContactState::to_build: {
      c.last = {};
      const coupling_detail::ShapeProbe probe(rasterizer, *body.shape(), b.envelope_pose);
      c.build(terrain, b.envelope, settings.contact.sub_cell_coverage ? &probe : nullptr,
              settings.contact.block_columns);
      solve_blocks(body, b, Blocks::built, settings, stats, h);
      return;
    }
  }
}

void TerrainCoupling::Parts::step_terrain() {
  const auto t0 = Clock::now();
  const terrain::StepReport report = terrain.step(imprints, clock.seconds());
  clock.restart();
  ++stats.terrain_steps;
  for (Entry& e : bodies) e.record.imprint_pending = false;
  stats.active_columns = report.active_columns;
  stats.erosion_passes = report.erosion_passes;
  stats.terrain_seconds += seconds_since(t0);
}

void TerrainCoupling::Parts::push_changes() {
  const auto t0 = Clock::now();
  const std::vector<GridRect> changed = terrain.take_changed();
  stats.vertices_pushed += tiles.push(changed);
  // Soft-soil bodies have no Bullet contact with the tiles, so nothing else wakes them; a
  // body at rest over terrain that changed (the ring around its envelope too: walls) builds
  // its contact afresh.
  for (Entry& e : bodies) {
    TerrainBody& b = e.record;
    if (b.envelope.lower.empty()) continue;
    for (const GridRect& r : changed)
      if (overlap(r, b.envelope, /*touching=*/true)) {
        if (!e.body->awake()) e.body->wake();
        b.contact.state = ContactState::to_build;
        break;
      }
  }
  if (settings.rescue_fallthrough)
    for (Entry& e : bodies)
      if (e.body->dynamic() && sane(*e.body) && coupling_detail::rescue_fallen(*e.body, terrain, settings.region))
        ++stats.rescues;
  stats.push_seconds += seconds_since(t0);
}

// ---- envelopes ----

void TerrainCoupling::Parts::rasterize(Entry& e) {
  TerrainBody& b = e.record;
  const GridRect old = b.envelope;
  b.envelope_pose = e.body->pose();
  rasterizer.rasterize(*e.body->shape(), b.envelope_pose, b.envelope);
  b.imprint_pending = true;
  clip_to_region(b.envelope);
  b.contact.memory.remap(old, b.envelope);
  b.contact.state = ContactState::to_build;
}

const EnvelopeRaster& TerrainCoupling::Parts::pressed(Entry& e) {
  TerrainBody& b = e.record;
  if (!b.stepped_pose_known || b.envelope.lower.empty()) return b.envelope;
  const btTransform& from = b.stepped_pose;
  const btTransform to = e.body->pose();  // the envelope's pose, or above it if lifted off bedrock
  const btVector3 d = to.getOrigin() - from.getOrigin();
  const double travel = std::hypot(double(d.x()), double(d.y()));
  if (!(travel > rasterizer.grid().cell)) return b.envelope;
  // The footprint's length along the travel: the shape's box, seen along it.
  const btCollisionShape& shape = *e.body->shape();
  btVector3 lo, hi;
  shape.getAabb(to, lo, hi);
  const double length =
      (std::abs(double(d.x())) * double(hi.x() - lo.x()) + std::abs(double(d.y())) * double(hi.y() - lo.y())) / travel;
  const double spacing = std::max(rasterizer.grid().cell, 0.25 * length);
  if (!(travel > spacing)) return b.envelope;
  const int poses = std::min(16, static_cast<int>(std::ceil(travel / spacing)));
  try {
    const GridRect start = rasterizer.window_of(shape, from);
    const GridRect window = bounding(start, b.envelope);
    rasterizer.rasterize(shape, to, window, b.swept);
    const btQuaternion q0 = from.getRotation(), q1 = to.getRotation();
    for (int k = 1; k < poses; ++k) {
      const double t = double(k) / poses;
      const btTransform between(q0.slerp(q1, btScalar(t)), from.getOrigin().lerp(to.getOrigin(), btScalar(t)));
      rasterizer.accumulate(shape, between, b.swept);
    }
  } catch (const InvalidSetting&) {  // a path wider than the rasterizer takes: the envelope alone
    return b.envelope;
  }
  clip_to_region(b.swept);
  return b.swept;
}

bool TerrainCoupling::Parts::can_rasterize(const Entry& e) const {
  return pose_rasterizable(e.body->pose(), e.record.shape.reach, rasterizer.grid());
}

bool TerrainCoupling::Parts::needs_envelope(const Entry& e, double h) const {
  const contact_detail::TerrainContact& c = e.record.contact;
  const double tolerance = settings.contact.follow_drift * terrain.settings().cell;
  if (c.blocks.empty() || !(tolerance > 0.0)) return true;
  if (!(double(e.body->motion().linear.length()) >= settings.contact.follow_speed)) return true;
  // Where its contact will have moved by the next substep's solve.
  return c.drift + contact_detail::largest_point_speed(c.blocks, solver_body(*e.body)) * h > tolerance;
}

bool TerrainCoupling::Parts::drifted(const Entry& e) const {
  // A tenth of a millimetre, a milliradian: well below what a column of soil resolves.
  const btTransform& now = e.body->pose();
  const btTransform& then = e.record.envelope_pose;
  if ((now.getOrigin() - then.getOrigin()).length() > btScalar(1e-4)) return true;
  const btMatrix3x3 turn = now.getBasis() * then.getBasis().transpose();
  return std::abs(double(turn[0][1] - turn[1][0])) + std::abs(double(turn[0][2] - turn[2][0])) +
             std::abs(double(turn[1][2] - turn[2][1])) >
         2e-3;
}

bool TerrainCoupling::Parts::overlaps_region(const CoupledBody& body) const {
  const Region& r = settings.region;
  btVector3 lo, hi;
  body.shape()->getAabb(body.pose(), lo, hi);
  const double pad = terrain.settings().cell;
  return hi.x() + pad >= r.x0 && lo.x() - pad <= r.x1 && hi.y() + pad >= r.y0 && lo.y() - pad <= r.y1;
}

void TerrainCoupling::Parts::clip_to_region(EnvelopeRaster& envelope) const {
  const Region& r = settings.region;
  if (r.everywhere()) return;
  for (int b = 0; b < envelope.ny; ++b)
    for (int a = 0; a < envelope.nx; ++a)
      if (!r.contains(terrain.column_x(envelope.i0 + a), terrain.column_y(envelope.j0 + b)))
        envelope.lower[envelope.index(envelope.i0 + a, envelope.j0 + b)] = EnvelopeRaster::kNoLower;
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
