#include "spray_state.h"

#include <algorithm>

#include "capacity_bytes.h"

namespace shore::terrain {

double SprayState::in_flight() const {
  double sum = 0.0;
  for (const Particle& p : particles) sum += p.volume;
  return sum;
}

double SprayState::clinging() const {
  double sum = 0.0;
  for (const ClingingBody& b : bodies)
    for (const ClingCell& c : b.cells) sum += c.volume;
  return sum;
}

std::int64_t SprayState::cell_count() const {
  std::int64_t n = 0;
  for (const ClingingBody& b : bodies)
    for (const ClingCell& c : b.cells) n += c.volume > 0.0 ? 1 : 0;
  return n;
}

int SprayState::largest_material() const {
  int most = 0;
  for (const std::uint8_t m : particle_materials) most = std::max(most, int{m});
  for (const ClingingBody& b : bodies)
    for (const ClingCell& c : b.cells) most = std::max(most, int{c.material});
  return most;
}

bool SprayState::has_bodies_between_steps() const {
  return std::any_of(bodies.begin(), bodies.end(), [&](const ClingingBody& b) { return b.between_steps(step); });
}

void SprayState::hash_into(StateHash& h) const {
  h.add(step);
  h.add(lost);
  h.add(static_cast<std::uint64_t>(particles.size()));
  for (const Particle& p : particles)
    for (double v :
         {p.position.x, p.position.y, p.position.z, p.velocity.x, p.velocity.y, p.velocity.z, p.volume, p.age})
      h.add(v);
  // Palette indices only where not 0 (as the map's tiles only where painted), so a terrain
  // with one material keeps its hashes.
  for (std::size_t k = 0; k < particle_materials.size(); ++k)
    if (particle_materials[k] != 0) h.add(static_cast<std::uint64_t>(k)), h.add(std::uint64_t{particle_materials[k]});
  h.add(static_cast<std::uint64_t>(bodies.size()));
  for (const ClingingBody& b : bodies) {
    h.add(b.key);
    for (double v : {b.centre.x, b.centre.y, b.centre.z}) h.add(v);
    for (double v : {b.orientation.w, b.orientation.x, b.orientation.y, b.orientation.z}) h.add(v);
    if (b.between_steps(step)) h.add(b.stepped);  // else step - 1, hashed already
    h.add(static_cast<std::uint64_t>(b.cells.size()));
    for (const ClingCell& c : b.cells) {
      h.add(c.key);
      for (double v : {c.local.x, c.local.y, c.local.z, c.volume, c.owed, c.pending}) h.add(v);
      for (std::int64_t v : {c.i, c.j, c.touched}) h.add(v);
      if (c.material != 0) h.add(std::uint64_t{c.material});
    }
  }
}

std::size_t SprayState::bytes() const {
  std::size_t n = capacity_bytes(particles, particle_materials, bodies);
  for (const ClingingBody& b : bodies) n += capacity_bytes(b.cells);
  return n;
}

}  // namespace shore::terrain
