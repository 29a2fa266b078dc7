#include "validation.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

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
  // Each OpenMP thread costs memory for good: an absurd count (a corrupt file's) could
  // exhaust it.
  c.in_closed("threads", threads, 0, 1024);
  c.at_least("parallel_min_columns", parallel_min_columns, 0);
  c.at_least("idle_tile_steps", idle_tile_steps, 0);
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
bool imprint_ok(const Imprint& im) {
  if (im.envelope == nullptr || im.envelope->nx < 0 || im.envelope->ny < 0) return false;
  const EnvelopeRaster& env = *im.envelope;
  if (env.lower.size() != static_cast<std::size_t>(env.nx) * static_cast<std::size_t>(env.ny)) return false;
  bool bad = !(im.offset >= 0.0 && std::isfinite(im.offset)) || !std::isfinite(im.vx) || !std::isfinite(im.vy) ||
             !std::isfinite(im.vz);
  for (const double v : env.lower) bad |= !(v > -std::numeric_limits<double>::infinity());
  return !bad;
}
}  // namespace

void check_imprints(std::span<const Imprint> imprints) {
  for (std::size_t b = 0; b < imprints.size(); ++b) {
    if (imprint_ok(imprints[b])) continue;  // the common case builds no names
    const std::string name = "terrain.Imprint[" + std::to_string(b) + "]";
    check_envelope(imprints[b].envelope, name + ".envelope");
    const Check c{name};
    c.non_negative("offset", imprints[b].offset);
    c.finite("vx", imprints[b].vx);
    c.finite("vy", imprints[b].vy);
    c.finite("vz", imprints[b].vz);
  }
}

void check_relax_region(const ColumnRect& region) {
  const Check c{"terrain.Terrain.relax.region"};
  c.at_least("nx", region.nx, 0);
  c.at_least("ny", region.ny, 0);
  if (static_cast<std::int64_t>(region.nx + 2) * (region.ny + 2) > kMaxRegionColumns)
    throw InvalidSetting(c.name("nx * ny"), detail::to_text(static_cast<std::int64_t>(region.nx) * region.ny),
                         "must be at most " + detail::to_text(kMaxRegionColumns));
}

}  // namespace shore::terrain
