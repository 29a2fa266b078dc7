// TerrainCoupling's own state in a checkpoint (docs/checkpoints.md), field by field: the
// totals of its statistics, the terrain's clock, per body its envelope and contact, the
// tiles.
#include <string>
#include <utility>
#include <vector>

#include "checkpoint_bytes.h"
#include "shore/bullet/terrain_coupling.h"
#include "shore/core/det_math.h"
#include "shore/core/error.h"
#include "terrain_coupling_parts.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace {

constexpr char kMagic[8] = {'S', 'H', 'T', 'E', 'R', 'R', 'C', 'P'};
// 2: the ground frame (1: Z up). 3: a block's friction is its columns' tan(phi) times their
// mobilisation (before, the mobilisation alone, times entry 0's tan(phi) when solved).
// 4: each column's remould displacement (the shear it took while it last yielded).
// 5: where each body was when the terrain last stepped (its imprint's sweep starts there).
constexpr std::uint32_t kVersion = 5;

/// The totals of the statistics (not the last substep's timings: a checkpoint of the same
/// state is the same bytes).
void put_totals(ByteWriter& w, const TerrainCouplingStats& s) {
  for (const std::int64_t v :
       {s.substeps, s.skipped_bodies, s.yields, s.rescues, s.vertices_pushed, s.terrain_steps, s.contacts_followed})
    w.put(v);
  w.put(s.plastic_work), w.put(s.shear_work);
}
TerrainCouplingStats get_totals(ByteReader& r) {
  TerrainCouplingStats s;
  for (std::int64_t* v : {&s.substeps, &s.skipped_bodies, &s.yields, &s.rescues, &s.vertices_pushed, &s.terrain_steps,
                          &s.contacts_followed})
    *v = r.get<std::int64_t>("statistics");
  s.plastic_work = r.get<double>("statistics"), s.shear_work = r.get<double>("statistics");
  return s;
}

EnvelopeRaster get_envelope(ByteReader& r) {
  EnvelopeRaster e;
  coupling_detail::get_window(r, e);
  if (e.lower.size() != e.size() && !e.lower.empty())  // empty: the body left the terrain's region
    r.fail("envelope holds " + std::to_string(e.lower.size()) + " columns, its window " + std::to_string(e.size()));
  if (!e.upper.empty() && e.upper.size() != e.lower.size()) r.fail("envelope's upper and lower differ in size");
  return e;
}

/// What a body's entry holds of a checkpoint, read whole before anything changes.
struct SavedBody {
  EnvelopeRaster envelope;
  btTransform pose;
  bool imprint_pending = false;
  contact_detail::TerrainContact contact;
  btTransform stepped_pose = btTransform::getIdentity();
  bool stepped_pose_known = false;
};

}  // namespace

std::vector<unsigned char> TerrainCoupling::save_state() const {
  ByteWriter w;
  coupling_detail::put_header(w, kMagic, kVersion);
  coupling_detail::put_frame(w, settings_.frame);
  put_totals(w, stats_);
  parts_->clock.save(w);
  w.put(static_cast<std::uint32_t>(parts_->bodies.size()));
  for (const Parts::Entry& e : parts_->bodies) {
    w.put(static_cast<std::int32_t>(coupling_detail::shape_type(e.body->object())));
    w.put(static_cast<std::uint8_t>(e.record.settings.deform));
    coupling_detail::put_window(w, e.record.envelope);
    coupling_detail::put_transform(w, e.record.envelope_pose);
    w.put(static_cast<std::uint8_t>(e.record.imprint_pending));
    e.record.contact.save(w);
    w.put(static_cast<std::uint8_t>(e.record.stepped_pose_known));
    coupling_detail::put_transform(w, e.record.stepped_pose);
  }
  parts_->tiles.save_state(w);
  return std::move(w.bytes);
}

void TerrainCoupling::restore_state(std::span<const unsigned char> bytes, const std::string& source) {
  ByteReader r(bytes, source);
  const std::uint32_t version = coupling_detail::check_header(r, kMagic, 1, kVersion, "a terrain coupling's state");
  coupling_detail::check_frame(r, version, 2, settings_.frame);
  const TerrainCouplingStats totals = get_totals(r);
  coupling_detail::StepClock clock;
  clock.restore(r);
  const auto count = r.get<std::uint32_t>("body count");
  if (count != parts_->bodies.size())
    r.fail("holds " + std::to_string(count) + " bodies, the coupling has " + std::to_string(parts_->bodies.size()) +
           " (add the same bodies in the same order)");
  std::vector<SavedBody> saved(count);
  for (std::uint32_t k = 0; k < count; ++k) {
    const Parts::Entry& e = parts_->bodies[k];
    const auto type = r.get<std::int32_t>("body shape type");
    const bool deform = r.get<std::uint8_t>("body settings") != 0;
    const int own_type = coupling_detail::shape_type(e.body->object());
    if (type != own_type || deform != e.record.settings.deform)
      r.fail("body " + std::to_string(k) + " was saved with shape type " + std::to_string(type) +
             (deform ? "" : " not") + " deforming; the coupling's has " + std::to_string(own_type) +
             (e.record.settings.deform ? "" : " not") + " deforming");
    SavedBody& s = saved[k];
    s.envelope = get_envelope(r);
    s.pose = coupling_detail::get_transform(r, "envelope pose");
    if (!coupling_detail::finite(s.pose)) r.fail("body " + std::to_string(k) + "'s envelope pose is not finite");
    s.imprint_pending = r.get<std::uint8_t>("body's imprint") != 0;
    s.contact.restore(r, s.envelope.size(), version >= 4);
    if (version < 3) s.contact.scale_friction(det::tan(terrain_.settings().material.friction_angle));
    if (s.envelope.lower.empty() != (s.contact.state == contact_detail::ContactState::none))
      r.fail("body " + std::to_string(k) + "'s contact state does not match its envelope");
    if (version >= 5) {  // before: unknown, so the first step after the restore sweeps nothing
      s.stepped_pose_known = r.get<std::uint8_t>("body's stepped pose") != 0;
      s.stepped_pose = coupling_detail::get_transform(r, "stepped pose");
      if (!coupling_detail::finite(s.stepped_pose))
        r.fail("body " + std::to_string(k) + "'s stepped pose is not finite");
    }
  }
  parts_->tiles.restore_state(r);  // last in the bytes; changes the tiles only once all is read
  // Loading the terrain marked every column changed. The run that was saved had taken its
  // changes at the end of its last substep, and the tiles are now exactly as saved: taking
  // these keeps them from waking the bodies at rest (which would change the continuation).
  (void)terrain_.take_changed();
  stats_ = totals;  // the totals; the last substep's timings start again
  parts_->clock = clock;
  for (std::uint32_t k = 0; k < count; ++k) {
    coupling_detail::TerrainBody& b = parts_->bodies[k].record;
    b.envelope = std::move(saved[k].envelope);
    b.envelope_pose = saved[k].pose;
    b.imprint_pending = saved[k].imprint_pending;
    b.contact = std::move(saved[k].contact);
    b.stepped_pose = saved[k].stepped_pose;
    b.stepped_pose_known = saved[k].stepped_pose_known;
  }
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
