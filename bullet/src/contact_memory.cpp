#include "contact_memory.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>

#include "checkpoint_bytes.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace contact_detail {
namespace {

/// Elements whose stiffness lies below this unload elastically (ContactElement::stiffness).
constexpr double kRigid = std::numeric_limits<double>::infinity();

/// A body presses further into a column when it approaches it faster than this share of its
/// slip over it (tan 2.9 deg). A box gliding on soil at its yield pressure rocks and pitches
/// by a few hundredths of its slip as it goes (its underside slides along itself, the
/// rocking dips the front and back edges in and out); counting every such dip as flow
/// remoulded the whole shear displacement of the columns under it, where a wheel's front
/// arc meets its columns at tens of degrees (docs/terrain.md, "Validation matrix", "the
/// gliding box's rocking").
constexpr double kPressingDip = 0.05;

/// Values kept per envelope column, moved from the old window to the new one (`fresh` where
/// new). The same window keeps them as they are; otherwise each row's overlap is copied at once.
template <class T>
void remap_values(std::vector<T>& values, const GridRect& from, const GridRect& to, T fresh = T{}) {
  if (from == to && values.size() == to.size()) return;
  std::vector<T> moved(to.size(), fresh);
  if (!values.empty()) {
    // Columns x of the new window whose old column i = to.i0 + x - from.i0 lies in [0, from.nx).
    const std::int64_t x0 = std::max<std::int64_t>(0, from.i0 - to.i0);
    const std::int64_t x1 = std::min<std::int64_t>(to.nx, from.i0 + from.nx - to.i0);
    for (int y = 0; y < to.ny && x0 < x1; ++y) {
      const std::int64_t j = to.j0 + y - from.j0;
      if (j < 0 || j >= from.ny) continue;
      const auto src = values.begin() + static_cast<std::ptrdiff_t>(j * from.nx + (to.i0 + x0 - from.i0));
      std::copy(src, src + (x1 - x0), moved.begin() + static_cast<std::ptrdiff_t>(std::int64_t{y} * to.nx + x0));
    }
  }
  values.swap(moved);
}

/// Raster indices of the old window moved to the new one (those that left it dropped), as
/// remap_values moves the values they point at.
void remap_indices(std::vector<std::uint32_t>& indices, const GridRect& from, const GridRect& to) {
  if (from == to) return;
  std::size_t kept = 0;
  for (const std::uint32_t k : indices) {
    const std::int64_t i = from.i0 + k % static_cast<std::uint32_t>(from.nx);
    const std::int64_t j = from.j0 + k / static_cast<std::uint32_t>(from.nx);
    if (to.contains(i, j)) indices[kept++] = static_cast<std::uint32_t>(to.index(i, j));
  }
  indices.resize(kept);
}

/// The raster index of an element's own column (-1 for walls and for fringe elements, which
/// lie on the uncovered neighbour of the column whose index they carry).
std::int64_t own_column(const EnvelopeRaster& env, const terrain::ContactElement& e) {
  if (e.wall || e.raster_index < 0 || !env.contains(e.i, e.j)) return -1;
  const auto k = static_cast<std::int64_t>(env.index(e.i, e.j));
  return k == e.raster_index ? k : -1;
}

}  // namespace

void ContactMemory::remap(const GridRect& from, const GridRect& to) {
  remap_values(shear_, from, to);
  remap_values(shear_length_, from, to);
  remap_values(remould_, from, to);
  remap_values(unloading_, from, to, kNone);
  remap_indices(touched_, from, to);
}

void ContactMemory::limit_unloading(std::span<terrain::ContactElement> elements, const EnvelopeRaster& envelope) const {
  if (unloading_.size() != envelope.lower.size()) return;
  for (terrain::ContactElement& e : elements) {
    if (!(e.stiffness < kRigid)) continue;
    const std::int64_t k = own_column(envelope, e);
    if (k >= 0) e.preload = std::min(e.preload, unloading_[static_cast<std::size_t>(k)]);
  }
}

void ContactMemory::advance(std::span<terrain::ContactElement> elements, const EnvelopeRaster& envelope,
                            const SolverBody& body, std::span<const Block> blocks, int block_columns, double h) {
  const std::size_t size = envelope.lower.size();
  // The share of its yield pressure a column being pressed carried: its block's (the solve
  // shares a block's push among its elements in proportion to their capacity).
  auto carried_share = [&](const terrain::ContactElement& e) {
    const std::uint64_t key = block_key(e, block_columns);
    const auto b = std::lower_bound(blocks.begin(), blocks.end(), key,
                                    [](const Block& block, std::uint64_t k) { return block.key < k; });
    return b != blocks.end() && b->key == key ? utilisation(*b, h) : 1.0;
  };
  const bool had = shear_.size() == size;
  // The new values first, from the old ones (nothing is reset before all are read).
  new_shear_.clear(), new_unloading_.clear();
  for (terrain::ContactElement& e : elements) {
    if (e.wall || e.raster_index < 0 || !envelope.contains(e.i, e.j)) continue;
    const Vec3 n = e.normal;
    const Vec3 u = body.point_velocity(e.point);
    const auto k = static_cast<std::uint32_t>(e.raster_index);
    const Vec3 slip = u - n * dot(u, n);
    const Vec3 j = (had ? shear_[k] : Vec3{}) + slip * h;
    const double length = std::sqrt(dot(j, j));
    const bool elastic = e.stiffness < kRigid;
    // The spring at the end of the substep: what the column carries on, and where a patch
    // kept for the next substep (follow_drift) starts from. It yields where that reaches
    // the yield pressure. A column on its loading branch flows only while the body presses
    // further into it with its block at its whole capacity: one whose block held below it
    // carried that share of its yield pressure, and a body sliding along the column's top
    // (not approaching it, or by less than kPressingDip of its slip) does not compress it
    // further, so neither remoulds its strength
    // (a box sliding level keeps the soil under it intact; a wheel's front arc, which the
    // rim approaches, yields). A link's solve is not what its columns carry (the links
    // solved after it load it through their joints): its pressed columns yield.
    const double spring = elastic ? e.preload + e.stiffness * h * -dot(u, n) : 0.0;
    const bool own = envelope.index(e.i, e.j) == k;  // a fringe element's column is its covered neighbour's
    const double share = !elastic && !body.articulated && e.pressure < kRigid ? carried_share(e) : 1.0;
    const bool held = share < 1.0 - 1e-9;
    const bool presses =
        body.articulated || !(e.pressure < kRigid) || -dot(u, n) > kPressingDip * std::sqrt(dot(slip, slip));
    const bool yields = elastic ? spring >= e.pressure : !held && presses;
    new_shear_.push_back({k, j, length, yields ? length : std::min(length, had ? remould_[k] : 0.0)});
    if (!elastic) {
      // Pressed below its yield pressure, it unloads from what it carried (a yielding one
      // carried its yield pressure, which bounds its push anyway).
      if (held && own) new_unloading_.emplace_back(k, e.pressure * share);
      continue;
    }
    e.preload = std::clamp(spring, 0.0, e.pressure);
    if (own) new_unloading_.emplace_back(k, e.preload);
  }
  // Back to fresh: only the entries touched last substep, when the arrays fit; else all.
  if (had) {
    for (const std::uint32_t k : touched_) shear_[k] = {}, shear_length_[k] = 0.0, remould_[k] = 0.0;
  } else {
    shear_.assign(size, {});
    shear_length_.assign(size, 0.0);
    remould_.assign(size, 0.0);
  }
  if (new_unloading_.empty()) {
    unloading_.clear();
  } else if (had && unloading_.size() == size) {
    for (const std::uint32_t k : touched_) unloading_[k] = kNone;
  } else {
    unloading_.assign(size, kNone);
  }
  touched_.clear();
  for (const NewShear& s : new_shear_) {
    shear_[s.k] = s.j;
    shear_length_[s.k] = s.length;
    remould_[s.k] = s.remould;
    touched_.push_back(s.k);
  }
  for (const auto& [k, p] : new_unloading_) unloading_[k] = p;  // k is among the shear's
}

void ContactMemory::save(ByteWriter& w) const {
  coupling_detail::put_fields(w, shear_, [](ByteWriter& out, const Vec3& v) { coupling_detail::put_vec3(out, v); });
  coupling_detail::put_fields(w, shear_length_, [](ByteWriter& out, double v) { out.put(v); });
  coupling_detail::put_fields(w, unloading_, [](ByteWriter& out, double v) { out.put(v); });
  coupling_detail::put_fields(w, remould_, [](ByteWriter& out, double v) { out.put(v); });
}

void ContactMemory::restore(ByteReader& r, std::size_t columns, bool with_remould) {
  coupling_detail::get_fields(r, shear_, 3 * sizeof(double), "shear displacement",
                              [](ByteReader& in) { return coupling_detail::get_vec3(in, "shear displacement"); });
  coupling_detail::get_fields(r, shear_length_, sizeof(double), "shear displacement",
                              [](ByteReader& in) { return in.get<double>("shear displacement"); });
  coupling_detail::get_fields(r, unloading_, sizeof(double), "unloading pressure",
                              [](ByteReader& in) { return in.get<double>("unloading pressure"); });
  if (with_remould)
    coupling_detail::get_fields(r, remould_, sizeof(double), "remould displacement",
                                [](ByteReader& in) { return in.get<double>("remould displacement"); });
  else
    remould_ = shear_length_;
  // What the next substeps index or divide by must be sound: a corrupt state is refused,
  // never read out of bounds or turned into NaN.
  if (!shear_.empty() && shear_.size() != columns)
    r.fail("shear displacement of " + std::to_string(shear_.size()) + " columns, the envelope has " +
           std::to_string(columns));
  if (shear_length_.size() != shear_.size())
    r.fail("shear displacement lengths of " + std::to_string(shear_length_.size()) + " columns, displacements of " +
           std::to_string(shear_.size()));
  if (!unloading_.empty() && unloading_.size() != columns)
    r.fail("unloading pressure of " + std::to_string(unloading_.size()) + " columns, the envelope has " +
           std::to_string(columns));
  if (remould_.size() != shear_.size())
    r.fail("remould displacements of " + std::to_string(remould_.size()) + " columns, shear displacements of " +
           std::to_string(shear_.size()));
  for (std::size_t k = 0; k < shear_.size(); ++k)
    if (!finite(shear_[k]) || !std::isfinite(shear_length_[k])) r.fail("a shear displacement that is not finite");
  for (const double j : remould_)
    if (!(j >= 0.0 && std::isfinite(j)))
      r.fail("a remould displacement of " + detail::to_text(j) + " m (must be finite, >= 0)");
  for (const double p : unloading_)
    if (!(p >= 0.0)) r.fail("an unloading pressure of " + detail::to_text(p) + " Pa (must be >= 0 or +infinity)");
  // Every column whose bits differ from fresh counts as touched, so the next substep resets
  // it (without shear displacements the next substep refills every array anyway).
  const auto set = [](double v) { return std::bit_cast<std::uint64_t>(v) != 0; };
  touched_.clear();
  for (std::size_t k = 0; k < shear_.size(); ++k)
    if (set(shear_[k].x) || set(shear_[k].y) || set(shear_[k].z) || set(shear_length_[k]) || set(remould_[k]) ||
        (!unloading_.empty() && unloading_[k] != kNone))
      touched_.push_back(static_cast<std::uint32_t>(k));
}

}  // namespace contact_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
