#include "spray_io.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace shore::terrain {

namespace {
constexpr std::size_t kParticleBytes = 8 * sizeof(double);
constexpr std::size_t kCellBytes = 4 * sizeof(std::uint64_t) + 6 * sizeof(double);
constexpr std::int64_t kMaxElapsedSteps = std::int64_t{1} << 20;

void need_finite(Reader& r, double v, const char* what) {
  if (!std::isfinite(v)) r.fail(std::string(what) + " holds a non-finite value");
}
}  // namespace

void write_spray_material(Writer& w, const SprayMaterial& m) {
  for (double v : {m.adhesion, m.half_life, m.speed_scale, m.exponent, m.particle_size, m.min_speed, m.jitter, m.drag})
    w.put(v);
}

void write_spray_settings(Writer& w, const TerrainSettings& s) {
  write_spray_material(w, s.material.spray);
  const SpraySettings& p = s.spray;
  w.put(static_cast<std::uint8_t>(p.enabled ? 1 : 0));
  w.put(static_cast<std::int32_t>(p.max_particles));
  w.put(p.seed);
  for (double v : {p.gravity, p.x_min, p.x_max, p.y_min, p.y_max, p.max_flight}) w.put(v);
}

void read_spray_settings(Reader& r, TerrainSettings& s) {
  SprayMaterial& m = s.material.spray;
  for (double* v :
       {&m.adhesion, &m.half_life, &m.speed_scale, &m.exponent, &m.particle_size, &m.min_speed, &m.jitter, &m.drag})
    *v = r.get<double>("spray settings");
  SpraySettings& p = s.spray;
  p.enabled = r.get<std::uint8_t>("spray settings") != 0;
  p.max_particles = r.get<std::int32_t>("spray settings");
  p.seed = r.get<std::uint64_t>("spray settings");
  for (double* v : {&p.gravity, &p.x_min, &p.x_max, &p.y_min, &p.y_max, &p.max_flight})
    *v = r.get<double>("spray settings");
}

void write_spray_state(Writer& w, const SprayState& st, SprayLayout layout) {
  const bool materials = layout.materials;
  w.put(st.step);
  w.put(st.lost);
  const SprayCounts& c = st.counts;
  for (std::int64_t v : {c.created, c.landed, c.lost, c.clumps, c.limited, c.set_down}) w.put(v);
  w.put(c.picked_volume);
  w.put(static_cast<std::uint64_t>(st.particles.size()));
  for (std::size_t k = 0; k < st.particles.size(); ++k) {
    const Particle& p = st.particles[k];
    for (double v :
         {p.position.x, p.position.y, p.position.z, p.velocity.x, p.velocity.y, p.velocity.z, p.volume, p.age})
      w.put(v);
    if (materials) w.put(st.particle_materials.empty() ? std::uint8_t{0} : st.particle_materials[k]);
  }
  w.put(static_cast<std::uint64_t>(st.bodies.size()));
  for (const ClingingBody& b : st.bodies) {
    w.put(b.key);
    for (double v : {b.centre.x, b.centre.y, b.centre.z}) w.put(v);
    for (double v : {b.orientation.w, b.orientation.x, b.orientation.y, b.orientation.z}) w.put(v);
    if (layout.steps) w.put(b.stepped);
    w.put(static_cast<std::uint64_t>(b.cells.size()));
    for (const ClingCell& cell : b.cells) {
      w.put(cell.key);
      for (double v : {cell.local.x, cell.local.y, cell.local.z, cell.volume, cell.owed, cell.pending}) w.put(v);
      for (std::int64_t v : {cell.i, cell.j, cell.touched}) w.put(v);
      if (materials) w.put(cell.material);
    }
  }
}

namespace {
/// A body's last clinging step: before the state's step (its next step covers at least
/// one), read or (an older layout) the step just done.
std::int64_t read_stepped(Reader& r, const SprayState& st, bool steps) {
  if (!steps) {
    if (st.step == std::numeric_limits<std::int64_t>::min())
      r.fail("spray bodies at step " + std::to_string(st.step) + " (corrupt)");
    return st.step - 1;
  }
  const auto stepped = r.get<std::int64_t>("spray bodies");
  // The steps its next clinging step covers: at least 1, and far fewer than 2^20 (cadences
  // of 1 to 16 skip at most 720,719 steps in a row: 720,720 is a multiple of each).
  std::int64_t elapsed = 0;
  if (__builtin_sub_overflow(st.step, stepped, &elapsed) || elapsed < 1 || elapsed > kMaxElapsedSteps)
    r.fail("a spray body last stepped on step " + std::to_string(stepped) +
           ", not 1 to 2^20 steps before the spray's step " + std::to_string(st.step) + " (corrupt)");
  return stepped;
}

void read_bodies(Reader& r, SprayState& st, SprayLayout layout) {
  const bool materials = layout.materials;
  const auto bodies = r.get<std::uint64_t>("spray bodies");
  if (bodies > r.remaining() / 64) r.fail("spray body count " + std::to_string(bodies) + " (corrupt)");
  for (std::uint64_t k = 0; k < bodies; ++k) {
    ClingingBody b;
    b.key = r.get<std::uint64_t>("spray bodies");
    if (!st.bodies.empty() && !(st.bodies.back().key < b.key)) r.fail("spray bodies out of order (corrupt)");
    for (double* v : {&b.centre.x, &b.centre.y, &b.centre.z, &b.orientation.w, &b.orientation.x, &b.orientation.y,
                      &b.orientation.z})
      need_finite(r, *v = r.get<double>("spray bodies"), "a spray body");
    b.stepped = read_stepped(r, st, layout.steps);
    const auto cells = r.get<std::uint64_t>("spray bodies");
    if (cells > r.remaining() / (kCellBytes + (materials ? 1 : 0)))
      r.fail("clinging cell count " + std::to_string(cells) + " (corrupt)");
    for (std::uint64_t n = 0; n < cells; ++n) {
      ClingCell c;
      c.key = r.get<std::uint64_t>("clinging cells");
      if (!b.cells.empty() && !(b.cells.back().key < c.key)) r.fail("clinging cells out of order (corrupt)");
      for (double* v : {&c.local.x, &c.local.y, &c.local.z, &c.volume, &c.owed, &c.pending})
        need_finite(r, *v = r.get<double>("clinging cells"), "a clinging cell");
      for (std::int64_t* v : {&c.i, &c.j, &c.touched}) *v = r.get<std::int64_t>("clinging cells");
      if (materials) c.material = r.get<std::uint8_t>("clinging cells");
      b.cells.push_back(c);
    }
    st.bodies.push_back(std::move(b));
  }
}
}  // namespace

void read_spray_state(Reader& r, SprayState& st, SprayLayout layout) {
  const bool materials = layout.materials;
  st.step = r.get<std::int64_t>("spray state");
  need_finite(r, st.lost = r.get<double>("spray state"), "the lost spray volume");
  SprayCounts& c = st.counts;
  for (std::int64_t* v : {&c.created, &c.landed, &c.lost, &c.clumps, &c.limited, &c.set_down})
    *v = r.get<std::int64_t>("spray counts");
  need_finite(r, c.picked_volume = r.get<double>("spray counts"), "the spray counts");
  const auto particles = r.get<std::uint64_t>("spray particles");
  if (particles > r.remaining() / (kParticleBytes + (materials ? 1 : 0)))
    r.fail("spray particle count " + std::to_string(particles) + " (corrupt)");
  st.particles.resize(particles);
  if (materials) st.particle_materials.resize(particles);
  for (std::size_t k = 0; k < st.particles.size(); ++k) {
    Particle& p = st.particles[k];
    for (double* v :
         {&p.position.x, &p.position.y, &p.position.z, &p.velocity.x, &p.velocity.y, &p.velocity.z, &p.volume, &p.age})
      need_finite(r, *v = r.get<double>("spray particles"), "a spray particle");
    if (materials) st.particle_materials[k] = r.get<std::uint8_t>("spray particles");
  }
  // Every index 0 (a map whose spray is all entry 0's) is kept as no indices, as a terrain
  // that never had a map keeps it.
  if (std::all_of(st.particle_materials.begin(), st.particle_materials.end(), [](std::uint8_t m) { return m == 0; }))
    std::vector<std::uint8_t>().swap(st.particle_materials);
  read_bodies(r, st, layout);
}

void check_spray_materials(const Reader& r, const SprayState& st, std::size_t palette_size) {
  const auto refuse = [&](const std::string& what, int index) {
    r.fail(what + " holds palette index " + std::to_string(index) + ", beyond the palette (0 to " +
           std::to_string(palette_size - 1) + ")");
  };
  for (std::size_t k = 0; k < st.particle_materials.size(); ++k)
    if (st.particle_materials[k] >= palette_size)
      refuse("spray particle " + std::to_string(k), st.particle_materials[k]);
  for (const ClingingBody& b : st.bodies)
    for (const ClingCell& c : b.cells)
      if (c.material >= palette_size)
        refuse("the clinging soil of spray body " + std::to_string(b.key) + " (piece " + std::to_string(c.key) + ")",
               c.material);
}

}  // namespace shore::terrain
