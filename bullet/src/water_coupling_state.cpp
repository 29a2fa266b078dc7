// WaterCoupling's own state in a checkpoint (docs/checkpoints.md), field by field: the
// totals of its statistics, per body the envelopes and pose its displacement was last
// taken from and its last forces.
#include <string>
#include <utility>
#include <vector>

#include "checkpoint_bytes.h"
#include "shore/bullet/water_coupling.h"
#include "shore/core/error.h"
#include "water_coupling_parts.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

namespace {
constexpr char kWaterMagic[8] = {'S', 'H', 'W', 'A', 'T', 'R', 'C', 'P'};
constexpr std::uint32_t kWaterVersion = 2;  // 2: the ground frame (1: Z up)
using coupling_detail::shape_type;

void put_body_water(ByteWriter& w, const BodyWater& b) {
  w.put(b.submerged_volume);
  for (const btVector3* v : {&b.centre_of_buoyancy, &b.buoyancy, &b.drag, &b.force, &b.torque})
    coupling_detail::put_vector(w, *v);
  w.put(b.projected_area), w.put(b.water_level);
}

BodyWater get_body_water(ByteReader& r) {
  BodyWater b;
  b.submerged_volume = r.get<double>("water force");
  for (btVector3* v : {&b.centre_of_buoyancy, &b.buoyancy, &b.drag, &b.force, &b.torque})
    *v = coupling_detail::get_vector(r, "water force");
  b.projected_area = r.get<double>("water force"), b.water_level = r.get<double>("water force");
  return b;
}

void put_sub_envelope(ByteWriter& w, const EnvelopeRaster& e) { coupling_detail::put_window(w, e); }

EnvelopeRaster get_sub_envelope(ByteReader& r) {
  EnvelopeRaster e;
  coupling_detail::get_window(r, e);
  const std::size_t n = std::size_t(e.nx) * std::size_t(e.ny);
  if (e.lower.size() != n || e.upper.size() != n)
    r.fail("envelope holds " + std::to_string(e.lower.size()) + " samples, its window " + std::to_string(n));
  return e;
}

}  // namespace

std::vector<unsigned char> WaterCoupling::save_state() const {
  ByteWriter w;
  coupling_detail::put_header(w, kWaterMagic, kWaterVersion);
  coupling_detail::put_frame(w, settings_.frame);
  w.put(stats_.substeps), w.put(stats_.skipped_bodies), w.put(stats_.displaced_volume);  // totals, not timings
  w.put(static_cast<std::uint32_t>(parts_->bodies.size()));
  for (const Parts::Entry& e : parts_->bodies) {
    const coupling_detail::WaterBody& b = e.record;
    w.put(static_cast<std::int32_t>(shape_type(e.body->object()))),
        w.put(static_cast<std::uint8_t>(b.settings.disturb));
    put_sub_envelope(w, b.reference);
    coupling_detail::put_transform(w, b.reference_pose);
    w.put(static_cast<std::uint8_t>(b.have_reference));
    put_body_water(w, b.last);
  }
  return std::move(w.bytes);
}

void WaterCoupling::restore_state(std::span<const unsigned char> bytes, const std::string& source) {
  ByteReader r(bytes, source);
  const std::uint32_t version =
      coupling_detail::check_header(r, kWaterMagic, 1, kWaterVersion, "a water coupling's state");
  coupling_detail::check_frame(r, version, 2, settings_.frame);
  WaterCouplingStats stats;
  stats.substeps = r.get<std::int64_t>("statistics"), stats.skipped_bodies = r.get<std::int64_t>("statistics");
  stats.displaced_volume = r.get<double>("statistics");
  const auto count = r.get<std::uint32_t>("body count");
  if (count != parts_->bodies.size())
    r.fail("holds " + std::to_string(count) + " bodies, the coupling has " + std::to_string(parts_->bodies.size()) +
           " (add the same bodies in the same order)");
  struct Saved {
    EnvelopeRaster reference;
    btTransform pose;
    bool have_reference = false;
    BodyWater last;
  };
  std::vector<Saved> saved(count);  // read whole before anything changes
  for (std::uint32_t k = 0; k < count; ++k) {
    const auto type = r.get<std::int32_t>("body shape type");
    const bool disturb = r.get<std::uint8_t>("body settings") != 0;
    const Parts::Entry& entry = parts_->bodies[k];
    const int own_type = shape_type(entry.body->object());
    const bool own_disturb = entry.record.settings.disturb;
    if (type != own_type || disturb != own_disturb)
      r.fail("body " + std::to_string(k) + " was saved with shape type " + std::to_string(type) +
             (disturb ? "" : " not") + " disturbing; the coupling's has " + std::to_string(own_type) +
             (own_disturb ? "" : " not") + " disturbing");
    saved[k].reference = get_sub_envelope(r);
    const EnvelopeRaster& e = saved[k].reference;
    const int per = settings_.fluid.samples_per_cell;
    if (!e.lower.empty() && (e.i0 < 0 || e.j0 < 0 || e.i0 + e.nx > std::int64_t(surface_.nx()) * per ||
                             e.j0 + e.ny > std::int64_t(surface_.ny()) * per))
      r.fail("body " + std::to_string(k) + "'s envelope lies outside the water grid");
    saved[k].pose = coupling_detail::get_transform(r, "envelope pose");
    if (!coupling_detail::finite(saved[k].pose)) r.fail("body " + std::to_string(k) + "'s envelope pose is not finite");
    saved[k].have_reference = r.get<std::uint8_t>("envelope flag") != 0;
    saved[k].last = get_body_water(r);
  }
  if (r.remaining() != 0) r.fail("bytes after the last body (corrupt)");
  stats_ = stats;
  for (std::uint32_t k = 0; k < count; ++k) {
    coupling_detail::WaterBody& b = parts_->bodies[k].record;
    b.reference = std::move(saved[k].reference);
    b.reference_pose = saved[k].pose;
    b.have_reference = saved[k].have_reference;
    b.last = saved[k].last;
  }
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
