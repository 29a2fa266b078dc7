// The soak: see shore/scenes/soak.h.
#include "shore/scenes/soak.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <set>

#include <time.h>
#include <unistd.h>

#include <btBulletDynamicsCommon.h>

#include "shore/bullet/terrain_coupling.h"
#include "shore/bullet/water_coupling.h"
#include "shore/scenes/world.h"
#include "shore/terrain/terrain.h"
#include "shore/water/surface.h"

namespace shore::scenes {

std::unique_ptr<btCollisionShape> random_body_shape(std::mt19937& rng,
                                                    std::vector<std::unique_ptr<btCollisionShape>>& children) {
  std::uniform_real_distribution<double> size(0.05, 0.25);
  auto s = [&] { return btScalar(size(rng)); };
  switch (rng() % 7) {
    case 0:
      return std::make_unique<btSphereShape>(s());
    case 1:
      return std::make_unique<btBoxShape>(btVector3(s(), s(), s()));
    case 2:
      return std::make_unique<btCapsuleShapeZ>(s(), s());
    case 3:
      return std::make_unique<btCylinderShapeZ>(btVector3(s(), s(), s()));
    case 4:
      return std::make_unique<btConeShapeZ>(s(), 2 * s());
    case 5: {
      auto hull = std::make_unique<btConvexHullShape>();
      for (int k = 0; k < 12; ++k) hull->addPoint(btVector3(s() - 0.15f, s() - 0.15f, s() - 0.15f));
      return hull;
    }
    default: {
      auto compound = std::make_unique<btCompoundShape>();
      children.push_back(std::make_unique<btBoxShape>(btVector3(s(), s(), s())));
      compound->addChildShape(btTransform(btQuaternion::getIdentity(), btVector3(0.1f, 0, 0)), children.back().get());
      children.push_back(std::make_unique<btSphereShape>(s()));
      compound->addChildShape(btTransform(btQuaternion::getIdentity(), btVector3(-0.1f, 0, 0)), children.back().get());
      return compound;
    }
  }
}

std::size_t resident_bytes() {
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  if (f == nullptr) return 0;
  unsigned long size = 0, resident = 0;
  const int read = std::fscanf(f, "%lu %lu", &size, &resident);
  std::fclose(f);
  const long page = sysconf(_SC_PAGESIZE);
  return read == 2 && page > 0 ? static_cast<std::size_t>(resident) * static_cast<std::size_t>(page) : 0;
}

namespace {

constexpr double kPoolX0 = 8.5, kPoolX1 = 12.0, kPoolY0 = -0.5, kPoolY1 = 4.0;  // m, the pool beside the sand
constexpr double kPoolDepth = 0.3;                                              // m of water over the sand
constexpr double kPoolSpacing = 0.05;                                           // m between water nodes

water::SurfaceSettings pool_settings() {
  water::PhysicalParameters phys;
  phys.cell = kPoolSpacing;
  phys.depth = kPoolDepth;
  phys.density = 1000.0;
  phys.damping_time = 2.0;
  const int nx = static_cast<int>(std::lround((kPoolX1 - kPoolX0) / kPoolSpacing)) + 1;
  const int ny = static_cast<int>(std::lround((kPoolY1 - kPoolY0) / kPoolSpacing)) + 1;
  water::SurfaceSettings s = water::SurfaceSettings::physical(phys, nx, ny);
  s.origin_x = kPoolX0;
  s.origin_y = kPoolY0;
  s.rest_height = kPoolDepth;
  s.mode = water::SurfaceMode::vertical_only;
  s.boundary = water::Boundary::vertical_only;  // walls: no open edge, no fixed node
  s.threads = 1;
  return s;
}

terrain::TerrainSettings sand_settings(double cell) {
  terrain::TerrainSettings s;
  s.cell = cell;
  s.material = terrain::Material::preset("sand");
  s.threads = 1;
  return s;
}

bool finite3(const btVector3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

/// What one check finds wrong: non-finite values, and the bodies below bedrock.
struct CheckCounts {
  std::int64_t nan = 0;
  std::set<std::size_t> fallen;
};

void check_bodies(const std::vector<btRigidBody*>& bodies, const terrain::Terrain& soil, CheckCounts& out) {
  for (std::size_t k = 0; k < bodies.size(); ++k) {
    const btRigidBody* b = bodies[k];
    const btVector3 c = b->getCenterOfMassPosition();
    if (!finite3(c) || !finite3(b->getLinearVelocity()) || !finite3(b->getAngularVelocity())) {
      ++out.nan;
      continue;
    }
    btVector3 lo, hi;
    b->getCollisionShape()->getAabb(b->getWorldTransform(), lo, hi);
    if (lo.z() < soil.bedrock(soil.column_i(c.x()), soil.column_j(c.y())) - 0.02) out.fallen.insert(k);
  }
}

double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// CPU time per substep in blocks of kBlock substeps, kept for the blocks inside the first
/// and the last window.
struct BlockClock {
  static constexpr std::int64_t kBlock = 100;
  std::int64_t first_begin = 0, first_end = 0, last_begin = 0, last_end = 0;  // substeps (begin, end]
  double block_start = thread_cpu_seconds();
  std::vector<double> first, last;
  void tick(std::int64_t s) {
    if (s % kBlock != 0) return;
    const double now = thread_cpu_seconds(), per_substep = (now - block_start) / kBlock;
    block_start = now;
    const std::int64_t b0 = s - kBlock;  // the block is (b0, s]
    if (b0 >= first_begin && s <= first_end) first.push_back(per_substep);
    if (b0 >= last_begin && s <= last_end) last.push_back(per_substep);
  }
};

/// The kick of substep s (see SoakCase::kick_every): one body in turn, thrown up and across.
void kick(const std::vector<btRigidBody*>& bodies, std::int64_t s, int every) {
  const std::int64_t n = s / every, k = n % static_cast<std::int64_t>(bodies.size());
  const btScalar side = (n / static_cast<std::int64_t>(bodies.size())) % 2 == 0 ? 1.0f : -1.0f;
  btRigidBody* b = bodies[static_cast<std::size_t>(k)];
  b->activate(true);
  b->setLinearVelocity(btVector3(0.3f * side, 0.2f * side, 2.0f));
}

/// Warm-up and window lengths: the case's, or a tenth of the run (windows at most 10,000).
void resolve_lengths(const SoakCase& c, SoakResult& r) {
  r.warm_up_substeps = c.warm_up_substeps > 0 ? c.warm_up_substeps : std::max<std::int64_t>(1, c.substeps / 10);
  r.window_substeps = c.window_substeps > 0 ? c.window_substeps : std::clamp<std::int64_t>(c.substeps / 10, 1, 10000);
  r.window_substeps = std::min(r.window_substeps, std::max<std::int64_t>(1, (c.substeps - r.warm_up_substeps) / 2));
}

}  // namespace

SoakResult run_soak(const SoakCase& c) {
  SoakResult r;
  resolve_lengths(c, r);
  std::vector<std::unique_ptr<btCollisionShape>> children;  // outlive the world's compounds
  std::mt19937 rng(c.seed);
  terrain::Terrain soil(sand_settings(c.cell));
  std::unique_ptr<water::Surface> pool = c.water ? std::make_unique<water::Surface>(pool_settings()) : nullptr;
  World world;
  bullet::TerrainCoupling ground(world.world(), soil);
  std::unique_ptr<bullet::WaterCoupling> water =
      pool ? std::make_unique<bullet::WaterCoupling>(world.world(), *pool) : nullptr;
  std::vector<btRigidBody*> bodies;
  const int on_sand = c.bodies - (water ? c.floating_bodies : 0);
  for (int k = 0; k < c.bodies; ++k) {
    const bool afloat = k >= on_sand;
    const int slot = afloat ? k - on_sand : k;
    const btVector3 at = afloat
                             ? btVector3(btScalar(kPoolX0 + 0.6 + 0.8 * (slot % 4)), btScalar(0.8 * (slot / 4)), 0.8f)
                             : btVector3(btScalar(0.8 * (slot % 10)), btScalar(0.8 * (slot / 10)), 0.4f);
    btRigidBody* b = world.add_body(random_body_shape(rng, children), 1.0 + 20.0 * (rng() % 100) / 100.0, at,
                                    btQuaternion(btScalar(0.1 * k), btScalar(0.2), btScalar(0.05 * k)));
    ground.add_body(b);
    if (afloat) water->add_body(b);
    bodies.push_back(b);
  }
  const double water_start = pool ? pool->volume() : 0.0;
  CheckCounts counts;
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const std::int64_t last_window_start = c.substeps - r.window_substeps;
  BlockClock cpu;
  cpu.first_begin = r.warm_up_substeps, cpu.first_end = r.warm_up_substeps + r.window_substeps;
  cpu.last_begin = last_window_start, cpu.last_end = c.substeps;
  for (std::int64_t s = 1; s <= c.substeps; ++s) {
    if (c.kick_every > 0 && s > c.settled_substeps && s % c.kick_every == 0) kick(bodies, s, c.kick_every);
    const auto t0 = Clock::now();
    world.step(c.substep);
    const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
    cpu.tick(s);
    if (s > r.warm_up_substeps && s <= r.warm_up_substeps + r.window_substeps) r.first_window_seconds += dt;
    if (s > last_window_start) r.last_window_seconds += dt;
    if (s == c.settled_substeps) r.rescues_after_settling = -ground.stats().rescues;
    const bool warm_end = s == r.warm_up_substeps;
    if (s % c.check_every != 0 && !warm_end && s != c.substeps) continue;
    check_bodies(bodies, soil, counts);
    const terrain::VolumeTotals vol = soil.volume();
    if (!std::isfinite(vol.total()) || (pool && !std::isfinite(pool->volume()))) ++counts.nan;
    const std::size_t soil_mem = soil.memory_bytes(), water_mem = pool ? pool->tile_stats().memory_bytes : 0;
    const std::size_t rss = resident_bytes();
    const std::size_t tiles = soil.tile_count();
    if (warm_end) r.soil_memory_warm = soil_mem, r.water_memory_warm = water_mem, r.rss_warm = rss;
    if (warm_end) r.soil_tiles_warm = tiles;
    if (s >= r.warm_up_substeps) {
      r.soil_memory_max = std::max(r.soil_memory_max, soil_mem);
      r.soil_tiles_max = std::max(r.soil_tiles_max, tiles);
      r.water_memory_max = std::max(r.water_memory_max, water_mem);
      r.rss_max = std::max(r.rss_max, rss);
    }
    if (c.progress) c.progress(s);
  }
  r.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  r.substeps = c.substeps;
  r.first_window_cpu = median(cpu.first);
  r.last_window_cpu = median(cpu.last);
  r.nan_count = counts.nan;
  r.fall_throughs = static_cast<int>(counts.fallen.size());
  r.rescues = ground.stats().rescues;
  r.rescues_after_settling += c.substeps >= c.settled_substeps ? ground.stats().rescues : 0;
  r.lost_bodies = ground.stats().lost_bodies + (water ? water->stats().lost_bodies : 0);
  const terrain::VolumeTotals vol = soil.volume();
  r.soil_moved_volume = std::abs(vol.compacted);
  r.soil_volume_drift = std::abs(vol.total() - vol.edited);
  if (water) {
    r.water_displaced_volume = water->stats().displaced_volume;
    r.water_volume_drift = std::abs(pool->volume() - water_start - r.water_displaced_volume);
  }
  return r;
}

}  // namespace shore::scenes
