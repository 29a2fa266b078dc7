#include "validation.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "region.h"
#include "shore/core/error.h"

namespace shore::terrain {

void TerrainSettings::validate() const {
  const Check c{"terrain.TerrainSettings"};
  // Beyond these a corrupt or mistaken value makes areas (cell^2 times a tile's sum)
  // underflow to 0 or overflow to infinity, and a denormal cell slows every step badly.
  c.in_closed("cell", cell, 1e-4, 1e3);
  c.in_closed("origin_x", origin_x, -1e12, 1e12);
  c.in_closed("origin_y", origin_y, -1e12, 1e12);
  if (!(tile_columns >= 4 && tile_columns <= 1024))
    throw InvalidSetting(c.name("tile_columns"), detail::to_text(tile_columns), "must be in [4, 1024]");
  material.validate();
  c.finite("base_height", base_height);
  // A rate limit: more passes than this per step would stall the step (slopes that barely
  // move, sigma near 0, keep every pass busy up to the cap).
  c.in_closed("max_erosion_passes", max_erosion_passes, 0, 1000);
  // A wider margin makes one small imprint gather over 250,000 columns every step (a fuzzed
  // file with 1025 took seconds per step).
  if (!(active_margin >= 1 && active_margin <= 256))
    throw InvalidSetting(c.name("active_margin"), detail::to_text(active_margin), "must be in [1, 256]");
  if (!(active_reach > 0.0))  // +infinity allowed: every covered column widens the region
    throw InvalidSetting(c.name("active_reach"), detail::to_text(active_reach), "must be > 0 (+infinity allowed)");
  c.non_negative("contact_tolerance", contact_tolerance);
  // Each team thread costs memory for good: an absurd count (a corrupt file's) could
  // exhaust it.
  c.in_closed("threads", threads, 0, 1024);
  c.at_least("parallel_min_columns", parallel_min_columns, 0);
  c.at_least("idle_tile_steps", idle_tile_steps, 0);
  spray.validate(Check{c.name("spray")});
}

void check_envelope(const EnvelopeRaster* env, const std::string& name) {
  if (env == nullptr) throw InvalidSetting(name, "null", "must point to an EnvelopeRaster");
  if (env->nx < 0 || env->ny < 0)
    throw InvalidSetting(name + ".nx/ny", detail::to_text(env->nx) + " x " + detail::to_text(env->ny), "must be >= 0");
  const std::size_t expected = static_cast<std::size_t>(env->nx) * static_cast<std::size_t>(env->ny);
  if (env->lower.size() != expected)
    throw InvalidSetting(name + ".lower.size()", detail::to_text(env->lower.size()),
                         "must equal nx * ny = " + detail::to_text(expected));
  // A NaN fails v > -inf, and so does -inf: one comparison per value, no branch taken.
  bool bad = false;
  const double* lower = env->lower.data();
  for (std::size_t k = 0; k < expected; ++k) bad |= !(lower[k] > -std::numeric_limits<double>::infinity());
  if (!bad) return;
  for (std::size_t k = 0; k < expected; ++k) {
    const double v = lower[k];
    if (std::isnan(v) || v == -std::numeric_limits<double>::infinity())
      throw InvalidSetting(name + ".lower[" + std::to_string(k) + "]", detail::to_text(v),
                           "must be finite, or +inf where the body does not cover the column");
  }
}

namespace {
/// Within 1e-3 of a unit quaternion.
bool unit(const Imprint& im) {
  const Quat& q = im.orientation;
  const double n2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
  return n2 > 0.998 && n2 < 1.002;
}

bool imprint_ok(const Imprint& im) {
  if (im.envelope == nullptr || im.envelope->nx < 0 || im.envelope->ny < 0) return false;
  const EnvelopeRaster& env = *im.envelope;
  if (env.lower.size() != static_cast<std::size_t>(env.nx) * static_cast<std::size_t>(env.ny)) return false;
  bool bad = !(im.offset >= 0.0 && std::isfinite(im.offset)) || !unit(im) || im.margin < 0 || im.margin > 256;
  bad |= im.cling_every < 1 || im.cling_every > 16;
  bad |= !finite(im.velocity) || !finite(im.angular_velocity) || !finite(im.centre);
  for (const double v : env.lower) bad |= !(v > -std::numeric_limits<double>::infinity());
  return !bad;
}

void check_one(const Imprint& im, const std::string& name) {
  check_envelope(im.envelope, name + ".envelope");
  const Check c{name};
  c.non_negative("offset", im.offset);
  if (im.margin < 0 || im.margin > 256)
    throw InvalidSetting(c.name("margin"), detail::to_text(im.margin), "must be in [0, 256] (0: the terrain's)");
  if (im.cling_every < 1 || im.cling_every > 16)
    throw InvalidSetting(c.name("cling_every"), detail::to_text(im.cling_every), "must be in [1, 16]");
  c.finite("velocity.x", im.velocity.x), c.finite("velocity.y", im.velocity.y), c.finite("velocity.z", im.velocity.z);
  c.finite("angular_velocity.x", im.angular_velocity.x), c.finite("angular_velocity.y", im.angular_velocity.y);
  c.finite("angular_velocity.z", im.angular_velocity.z);
  c.finite("centre.x", im.centre.x), c.finite("centre.y", im.centre.y), c.finite("centre.z", im.centre.z);
  const Quat& q = im.orientation;
  if (!unit(im))
    throw InvalidSetting(
        c.name("orientation"),
        detail::to_text(q.w) + ", " + detail::to_text(q.x) + ", " + detail::to_text(q.y) + ", " + detail::to_text(q.z),
        "must be a unit quaternion (w, x, y, z) (|q| within 1e-3 of 1)");
}

/// Spraying imprints name their bodies: one key, one body.
void check_body_keys(std::span<const Imprint> imprints) {
  std::vector<std::pair<std::uint64_t, std::size_t>> keys;
  for (std::size_t b = 0; b < imprints.size(); ++b)
    if (imprints[b].spray && !imprints[b].hold) keys.emplace_back(imprints[b].key, b);
  std::sort(keys.begin(), keys.end());
  for (std::size_t k = 1; k < keys.size(); ++k)
    if (keys[k].first == keys[k - 1].first)
      throw InvalidSetting("terrain.Imprint[" + std::to_string(std::max(keys[k].second, keys[k - 1].second)) + "].key",
                           detail::to_text(keys[k].first),
                           "must differ from the key of every other spraying imprint of the step (Imprint[" +
                               std::to_string(std::min(keys[k].second, keys[k - 1].second)) +
                               "] has it); or set spray = false");
}
}  // namespace

void check_imprints(std::span<const Imprint> imprints, double dt) {
  if (!(dt >= 0.0 && std::isfinite(dt)))
    throw InvalidSetting("terrain.Terrain.step.dt", detail::to_text(dt), "must be finite and >= 0 (s)");
  for (std::size_t b = 0; b < imprints.size(); ++b)
    if (!imprint_ok(imprints[b])) check_one(imprints[b], "terrain.Imprint[" + std::to_string(b) + "]");
  if (dt > 0.0 && imprints.size() > 1) check_body_keys(imprints);
}

void check_relax_region(const GridRect& region) {
  const Check c{"terrain.Terrain.relax.region"};
  c.at_least("nx", region.nx, 0);
  c.at_least("ny", region.ny, 0);
  if (static_cast<std::int64_t>(region.nx + 2) * (region.ny + 2) > kMaxRegionColumns)
    throw InvalidSetting(c.name("nx * ny"), detail::to_text(static_cast<std::int64_t>(region.nx) * region.ny),
                         "must be at most " + detail::to_text(kMaxRegionColumns));
}

}  // namespace shore::terrain
