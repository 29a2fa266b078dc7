// A body's terrain contact in a checkpoint, field by field (docs/checkpoints.md).
#include <cmath>
#include <string>

#include "checkpoint_bytes.h"
#include "terrain_contact.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace contact_detail {
namespace {

using coupling_detail::get_vec3;
using coupling_detail::put_vec3;

constexpr std::size_t kElementBytes = 11 * sizeof(double) + 2 * sizeof(std::int64_t) + sizeof(std::int32_t) + 1;
constexpr std::size_t kBlockBytes = 29 * sizeof(double) + sizeof(std::uint64_t) + 1;

void put_element(ByteWriter& w, const terrain::ContactElement& e) {
  put_vec3(w, e.point), put_vec3(w, e.normal);
  w.put(e.area), w.put(e.pressure);
  w.put(static_cast<std::int64_t>(e.i)), w.put(static_cast<std::int64_t>(e.j));
  w.put(static_cast<std::int32_t>(e.raster_index)), w.put(static_cast<std::uint8_t>(e.wall));
  w.put(e.stiffness), w.put(e.preload), w.put(e.pressure_rate);
}

terrain::ContactElement get_element(ByteReader& r) {
  const char* what = "contact patch";
  terrain::ContactElement e;
  e.point = get_vec3(r, what), e.normal = get_vec3(r, what);
  e.area = r.get<double>(what), e.pressure = r.get<double>(what);
  e.i = r.get<std::int64_t>(what), e.j = r.get<std::int64_t>(what);
  e.raster_index = r.get<std::int32_t>(what), e.wall = r.get<std::uint8_t>(what) != 0;
  e.stiffness = r.get<double>(what), e.preload = r.get<double>(what), e.pressure_rate = r.get<double>(what);
  return e;
}

void put_block(ByteWriter& w, const Block& b) {
  w.put(static_cast<std::uint64_t>(b.key));
  put_vec3(w, b.point), put_vec3(w, b.normal);
  w.put(b.capacity), w.put(b.cohesion), w.put(b.friction), w.put(static_cast<std::uint8_t>(b.wall));
  put_vec3(w, b.t1), put_vec3(w, b.t2);
  for (const double v : {b.normal_impulse, b.t1_impulse, b.t2_impulse, b.mass_n, b.mass_t1, b.mass_t2, b.start_n,
                         b.start_t1, b.start_t2, b.stiffness, b.preload, b.capacity_rate, b.approach, b.deepest})
    w.put(v);
}

Block get_block(ByteReader& r) {
  const char* what = "contact blocks";
  Block b;
  b.key = r.get<std::uint64_t>(what);
  b.point = get_vec3(r, what), b.normal = get_vec3(r, what);
  b.capacity = r.get<double>(what), b.cohesion = r.get<double>(what), b.friction = r.get<double>(what);
  b.wall = r.get<std::uint8_t>(what) != 0;
  b.t1 = get_vec3(r, what), b.t2 = get_vec3(r, what);
  for (double* v : {&b.normal_impulse, &b.t1_impulse, &b.t2_impulse, &b.mass_n, &b.mass_t1, &b.mass_t2, &b.start_n,
                    &b.start_t1, &b.start_t2, &b.stiffness, &b.preload, &b.capacity_rate, &b.approach, &b.deepest})
    *v = r.get<double>(what);
  return b;
}

bool sound(const terrain::ContactElement& e, std::size_t columns) {
  return e.raster_index < static_cast<std::int64_t>(columns) && finite(e.point) && finite(e.normal) &&
         std::isfinite(e.area) && !std::isnan(e.pressure) && e.stiffness >= 0.0 && e.preload >= 0.0 &&
         std::isfinite(e.preload) && e.pressure_rate >= 0.0 && std::isfinite(e.pressure_rate);
}

bool sound(const Block& b) {
  return finite(b.point) && finite(b.normal) && !std::isnan(b.capacity) && b.stiffness >= 0.0 && b.preload >= 0.0 &&
         std::isfinite(b.preload) &&
         std::isfinite(b.cohesion + b.friction + b.normal_impulse + b.t1_impulse + b.t2_impulse + b.mass_n + b.mass_t1 +
                       b.mass_t2) &&
         finite(b.t1) && finite(b.t2) && std::isfinite(b.start_n + b.start_t1 + b.start_t2) && b.capacity_rate >= 0.0 &&
         std::isfinite(b.capacity_rate + b.approach + b.deepest);
}

void put_force(ByteWriter& w, const TerrainForce& f) {
  coupling_detail::put_vector(w, f.force), coupling_detail::put_vector(w, f.torque);
  coupling_detail::put_vector(w, f.normal_force);
  w.put(static_cast<std::int32_t>(f.contact_columns)), w.put(static_cast<std::uint8_t>(f.yielded));
}

TerrainForce get_force(ByteReader& r) {
  const char* what = "terrain force";
  TerrainForce f;
  f.force = coupling_detail::get_vector(r, what), f.torque = coupling_detail::get_vector(r, what);
  f.normal_force = coupling_detail::get_vector(r, what);
  f.contact_columns = r.get<std::int32_t>(what), f.yielded = r.get<std::uint8_t>(what) != 0;
  return f;
}

}  // namespace

void TerrainContact::scale_friction(double tan_phi) {
  for (Block& b : blocks) b.friction *= tan_phi;
  for (Block& b : previous) b.friction *= tan_phi;
}

void TerrainContact::save(ByteWriter& w) const {
  w.put(static_cast<std::uint8_t>(state));
  coupling_detail::put_fields(w, patch.elements, put_element);
  w.put(patch.patch_width), w.put(patch.area), w.put(static_cast<std::int32_t>(patch.touching_columns));
  coupling_detail::put_fields(w, blocks, put_block);
  coupling_detail::put_fields(w, previous, put_block);
  memory.save(w);
  put_force(w, last);
  w.put(drift);
  w.put(static_cast<std::uint8_t>(end.has_value()));
  if (end) coupling_detail::put_vector(w, end->linear), coupling_detail::put_vector(w, end->angular);
}

void TerrainContact::restore(ByteReader& r, std::size_t columns, bool with_remould) {
  const auto kind = r.get<std::uint8_t>("contact state");
  if (kind > static_cast<std::uint8_t>(ContactState::resting)) r.fail("contact state " + std::to_string(kind));
  state = static_cast<ContactState>(kind);
  coupling_detail::get_fields(r, patch.elements, kElementBytes, "contact patch", get_element);
  patch.patch_width = r.get<double>("contact patch"), patch.area = r.get<double>("contact patch");
  patch.touching_columns = r.get<std::int32_t>("contact patch");
  coupling_detail::get_fields(r, blocks, kBlockBytes, "contact blocks", get_block);
  coupling_detail::get_fields(r, previous, kBlockBytes, "contact blocks", get_block);
  memory.restore(r, columns, with_remould);
  last = get_force(r);
  drift = r.get<double>("contact drift");
  end.reset();
  if (r.get<std::uint8_t>("contact end") != 0) {
    EndMotion m;
    m.linear = coupling_detail::get_vector(r, "contact end"), m.angular = coupling_detail::get_vector(r, "contact end");
    end = m;
  }
  // What the next substeps index or divide by must be sound: a corrupt state is refused,
  // never read out of bounds or turned into NaN.
  bool ok = coupling_detail::finite(last.force) && coupling_detail::finite(last.torque) && drift >= 0.0 &&
            std::isfinite(drift) &&
            (!end || (coupling_detail::finite(end->linear) && coupling_detail::finite(end->angular)));
  for (const terrain::ContactElement& e : patch.elements) ok = ok && sound(e, columns);
  for (const auto* list : {&blocks, &previous})
    for (const Block& b : *list) ok = ok && sound(b);
  if (!ok) r.fail("the terrain contact's state holds a non-finite value or an index beyond the envelope");
}

}  // namespace contact_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
