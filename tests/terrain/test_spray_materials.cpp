// Spray by material (docs/terrain.md, "Material map"): on a painted terrain each clinging
// piece and each particle carries its palette index, so soil sheds with its own half-life
// and flies with its own particle size and drag. Measured against the closed forms:
// exponential shedding 2^(-t / h), the ballistic flight with linear drag
// (dv/dt = g - k v) and without, Sumner's particle volume pi d^3 / 6. The state saves,
// loads and travels in exact soil deltas with its indices; a file whose index lies beyond
// its palette is refused by name.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <string>
#include <vector>

#include "shore/core/error.h"
#include "shore/core/hash.h"
#include "shore/terrain/soil_delta.h"
#include "shore/terrain/terrain.h"
#include "terrain_fixtures.h"

using namespace shore::terrain;
using namespace shore::terrain::testing;

namespace {

constexpr double kG = 9.81;

/// The 50 %-slip wheel of the spray tests: radius 0.3 m, 0.15 m wide, 3 cm deep, its rim
/// at 3 m/s, kinematic.
Imprint wheel_at(const Terrain& t, double time, shore::EnvelopeRaster& env) {
  const double radius = 0.3, rim = 3.0, speed = 1.5, x = speed * time, z = radius - 0.03;
  env = wheel_by_centre(t, x, z, radius, 0.15);
  Imprint im{&env};
  const double omega = rim / radius, turn = omega * time;
  im.velocity.x = speed;
  im.angular_velocity.y = omega;
  im.centre.x = x, im.centre.z = z;
  im.orientation.w = std::cos(turn / 2), im.orientation.y = std::sin(turn / 2);
  im.key = 7;
  return im;
}

TerrainSettings sand_settings() {
  TerrainSettings s;
  s.cell = 0.01;
  s.material = Material::sand();
  s.tile_columns = 32;
  s.threads = 1;
  return s;
}

/// Mud that flies without drag, in 6 mm clods (a piece of a 1 cm column holds 3.5 of them).
Material drag_free_mud() {
  Material m = Material::mud();
  m.name = "drag-free mud";
  m.spray.drag = 0.0;
  m.spray.particle_size = 0.006;
  return m;
}

/// Sand (entry 0) where y < 0, the drag-free mud (entry 1) where y >= 0: the wheel's two
/// halves run on one each.
Terrain half_sand_half_mud() {
  Terrain t(sand_settings());
  t.set_palette({Material::sand(), drag_free_mud()});
  t.paint_rect({-60, 0, 400, 60}, 1);
  return t;
}

void run_wheel(Terrain& t, int from, int to) {
  shore::EnvelopeRaster env;
  for (int k = from; k < to; ++k) {
    const Imprint im = wheel_at(t, k / 240.0, env);
    t.step({&im, 1}, 1.0 / 240);
  }
}

double particle_volume(const Material& m) {
  return std::numbers::pi * m.spray.particle_size * m.spray.particle_size * m.spray.particle_size / 6.0;
}

/// Where the closed form of dv/dt = g - k v (k = 0: the parabola) puts a particle after t.
shore::Vec3 flown(const SprayParticle& p, double k, double t) {
  if (k == 0.0)
    return {p.position.x + p.velocity.x * t, p.position.y + p.velocity.y * t,
            p.position.z + p.velocity.z * t - 0.5 * kG * t * t};
  const double a = (1.0 - std::exp(-k * t)) / k, fall = kG / k;
  return {p.position.x + p.velocity.x * a, p.position.y + p.velocity.y * a,
          p.position.z + (p.velocity.z + fall) * a - fall * t};
}

double distance(const shore::Vec3& a, const shore::Vec3& b) {
  return std::sqrt((a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) + (a.z - b.z) * (a.z - b.z));
}

}  // namespace

// The wheel runs half on sand, half on drag-free mud: the particles of each half are that
// material's, in its size (Sumner's pi d^3 / 6, the last of a piece's soil smaller), and fly
// by its law: after a further 0.05 s every particle still in flight is where the closed form
// with its own material's drag puts it, and not where the other material's would.
TEST(SprayMaterials, EachHalfOfAWheelThrowsItsOwnMaterialsParticlesAndTheyFlyByItsDrag) {
  Terrain t = half_sand_half_mud();
  run_wheel(t, 0, 240);
  const std::vector<SprayParticle> before = t.spray_particles();
  const Material materials[2] = {Material::sand(), drag_free_mud()};
  int count[2] = {0, 0}, whole[2] = {0, 0};
  double largest[2] = {0.0, 0.0};
  for (const SprayParticle& p : before) {
    ASSERT_TRUE(p.material == 0 || p.material == 1) << p.material;
    const double vp = particle_volume(materials[p.material]);
    ++count[p.material];
    largest[p.material] = std::max(largest[p.material], p.volume);
    whole[p.material] += std::abs(p.volume - vp) <= 1e-12 * vp ? 1 : 0;
  }
  std::printf("[ halves ] in flight: sand %d (%d whole, %.3g m^3), mud %d (%d whole, %.3g m^3)\n", count[0], whole[0],
              particle_volume(materials[0]), count[1], whole[1], particle_volume(materials[1]));
  ASSERT_GT(count[0], 50) << "the sand half throws sand";
  ASSERT_GT(count[1], 20) << "the mud half throws mud";
  // Whole particles of the material's size; the last of a piece's soil goes smaller.
  for (const int m : {0, 1}) {
    const double vp = particle_volume(materials[m]);
    EXPECT_NEAR(largest[m], vp, 1e-12 * vp) << "material " << m;
    EXPECT_GT(whole[m], count[m] / 4) << "material " << m;
  }

  const double dt = 0.05;
  t.step({}, dt);  // the wheel gone: no new particle, what clung is set down
  const std::vector<SprayParticle> after = t.spray_particles();
  ASSERT_GT(after.size(), before.size() / 2);
  // Oldest first, in flight or landed: `after` is `before` less the landed ones, in order.
  std::size_t k = 0;
  double worst_own = 0.0, least_other = 1e9;
  for (const SprayParticle& q : after) {
    const auto predicted = [&](std::size_t n, int m) { return flown(before[n], materials[m].spray.drag, dt); };
    while (k < before.size() && distance(predicted(k, before[k].material), q.position) > 1e-9) ++k;
    ASSERT_LT(k, before.size()) << "a particle in flight is not where its own material's drag puts it";
    EXPECT_EQ(q.material, before[k].material);
    worst_own = std::max(worst_own, distance(predicted(k, q.material), q.position));
    least_other = std::min(least_other, distance(predicted(k, 1 - q.material), q.position));
    const double k_drag = materials[q.material].spray.drag;
    EXPECT_NEAR(q.velocity.x, before[k].velocity.x * std::exp(-k_drag * dt), 1e-12);
    ++k;
  }
  std::printf("[ flight ] %zu of %zu still flying: own law within %.2g m, the other material's off by >= %.2g m\n",
              after.size(), before.size(), worst_own, least_other);
  EXPECT_GT(least_other, 1e-5) << "the two laws must differ for this to test anything";
}

namespace {

/// A 10 x 10 column plate moving at 1 m/s along x, touching the soil for 10 steps, then
/// lifted 10 cm: what clings to it (m^3) each step after it left, and the step's time.
std::vector<double> shed_after_lift(Terrain& t, int steps_off, double dt) {
  std::vector<double> clinging;
  for (int k = 0; k < 10 + steps_off; ++k) {
    const double x = 1.0 * k * dt, lift = k < 10 ? -0.001 : 0.1;
    const std::int64_t i0 = t.column_i(x) - 5;
    const shore::EnvelopeRaster env = box_envelope(i0, -5, 10, 10, lift);
    Imprint im{&env};
    im.velocity.x = 1.0;
    im.centre.x = t.column_x(i0 + 5), im.centre.z = lift + 0.05;
    im.key = 3;
    t.step({&im, 1}, dt);
    if (k >= 10) clinging.push_back(t.volume().clinging);
  }
  return clinging;
}

/// Half-life (s) from the least-squares slope of ln V over the steps given.
double fitted_half_life(const std::vector<double>& v, double dt) {
  double st = 0, sy = 0, stt = 0, sty = 0;
  int n = 0;
  for (std::size_t k = 1; k < v.size() && v[k] > v[0] / 8; ++k, ++n) {  // three half-lives at most
    const double time = static_cast<double>(k) * dt, y = std::log(v[k]);
    st += time, sy += y, stt += time * time, sty += time * y;
  }
  const double slope = (n * sty - st * sy) / (n * stt - st * st);
  return -std::numbers::ln2 / slope;
}

Material shedding(const char* name, double half_life) {
  Material m = Material::sand();
  m.name = name;
  m.spray.adhesion = 0.002;
  m.spray.half_life = half_life;
  m.spray.particle_size = 0.002;  // 48 particles to a piece: shedding in near-continuous steps
  m.spray.speed_scale = 100.0;    // nearly all drop as clumps: the decay is what is measured
  return m;
}

}  // namespace

// A plate picks soil up and lifts off: what clings to it decays as 2^(-t / h) with the
// half-life of the material it picked up, the painted entry's, not entry 0's.
TEST(SprayMaterials, ShedSoilDecaysWithTheHalfLifeOfTheMaterialPickedUp) {
  const double dt = 1.0 / 240;
  const Material quick = shedding("quick", 0.05), slow = shedding("slow", 0.2);
  struct Case {
    const char* what;
    bool palette, paint;
    double expected;
  };
  for (const Case& c : {Case{"one material", false, false, 0.05}, Case{"a palette, unpainted", true, false, 0.05},
                        Case{"painted slow", true, true, 0.2}}) {
    TerrainSettings s = sand_settings();
    s.material = quick;
    Terrain t(s);
    if (c.palette) t.set_palette({quick, slow});
    if (c.paint) t.paint_rect({-20, -20, 80, 40}, 1);
    const std::vector<double> v = shed_after_lift(t, static_cast<int>(3.2 * c.expected / dt), dt);
    ASSERT_GT(v[0], 0.9 * 100 * 0.002 * 1e-4) << c.what << ": the plate's 100 pieces picked up adhesion x area";
    const double h = fitted_half_life(v, dt);
    std::printf("[ shed ] %s: half-life %.4f s (material's %.3f s), from %.3g m^3\n", c.what, h, c.expected, v[0]);
    EXPECT_NEAR(h, c.expected, 0.03 * c.expected) << c.what;
  }
}

// Saved mid-spray and loaded, the terrain is the same state (hash, particles and their
// indices), and both go on the same, bit for bit.
TEST(SprayMaterials, SaveLoadRoundTripKeepsEveryIndexBitForBit) {
  Terrain a = half_sand_half_mud();
  run_wheel(a, 0, 120);
  const std::vector<unsigned char> bytes = a.save_bytes();
  EXPECT_EQ(bytes[8], 8) << "a terrain with a map is written as version 8";
  Terrain b = Terrain::load_bytes(bytes, "halves");
  EXPECT_EQ(b.state_hash(), a.state_hash());
  EXPECT_EQ(b.save_bytes(), bytes);
  run_wheel(a, 120, 180);
  run_wheel(b, 120, 180);
  EXPECT_EQ(b.state_hash(), a.state_hash());
  const std::vector<SprayParticle> pa = a.spray_particles(), pb = b.spray_particles();
  ASSERT_EQ(pa.size(), pb.size());
  int mud = 0;
  for (std::size_t k = 0; k < pa.size(); ++k) {
    ASSERT_EQ(pa[k].material, pb[k].material);
    ASSERT_EQ(std::memcmp(&pa[k].position, &pb[k].position, sizeof pa[k].position), 0);
    ASSERT_EQ(std::memcmp(&pa[k].velocity, &pb[k].velocity, sizeof pa[k].velocity), 0);
    mud += pa[k].material;
  }
  EXPECT_GT(mud, 0) << "mud particles were in flight: the indices were tested";
}

// A particle's index beyond the file's palette is refused naming the file, the particle and
// the palette's range.
TEST(SprayMaterials, AFileWithASprayIndexBeyondItsPaletteIsRefusedByName) {
  Terrain a = half_sand_half_mud();
  run_wheel(a, 0, 120);
  const std::vector<SprayParticle> flying = a.spray_particles();
  const auto first_mud = std::find_if(flying.begin(), flying.end(), [](const SprayParticle& p) { return p.material; });
  ASSERT_NE(first_mud, flying.end());
  std::vector<unsigned char> bytes = a.save_bytes();
  // Layout (terrain_io.cpp): a particle is f64 x, y, z, vx, vy, vz, volume, age, then its u8 index.
  unsigned char xy[16];
  std::memcpy(xy, &first_mud->position.x, 8), std::memcpy(xy + 8, &first_mud->position.y, 8);
  const auto at = std::search(bytes.begin(), bytes.end(), xy, xy + 16);
  ASSERT_NE(at, bytes.end());
  const std::size_t index_at = static_cast<std::size_t>(at - bytes.begin()) + 64;
  ASSERT_EQ(bytes[index_at], 1);
  bytes[index_at] = 9;
  reseal(bytes);
  const std::string m = message_of<shore::FileError>([&] { (void)Terrain::load_bytes(bytes, "sprayed.state"); });
  EXPECT_NE(m.find("sprayed.state"), std::string::npos) << m;
  const std::string particle = "spray particle " + std::to_string(first_mud - flying.begin());
  EXPECT_NE(m.find(particle + " holds palette index 9, beyond the palette (0 to 1)"), std::string::npos) << m;
}

// The palette cannot shrink below an index soil in the air or on a body still holds.
TEST(SprayMaterials, APaletteTooShortForTheSprayIsRefused) {
  Terrain t = half_sand_half_mud();
  run_wheel(t, 0, 120);
  // Nothing painted 1 is left (the mud laid over sand by erosion cleared too), but mud still flies.
  t.paint_rect({-60, -60, 400, 120}, 0);
  t.clear_layers({-60, -60, 400, 120});
  const std::string m = message_of<shore::InvalidSetting>([&] { t.set_palette({Material::sand()}); });
  EXPECT_NE(m.find("largest index of soil in spray (1)"), std::string::npos) << m;
  EXPECT_EQ(t.palette().size(), 2u);
}

// Exact soil deltas carry the indices: a replica driven by them alone has the server's
// spray, particle for particle, and its hash.
TEST(SprayMaterials, ExactDeltasCarryTheSpraysIndices) {
  Terrain server(sand_settings()), replica(sand_settings());
  std::uint64_t sent = server.generation(), mirrored = replica.generation();
  server.set_palette({Material::sand(), drag_free_mud()});
  server.paint_rect({-60, 0, 400, 60}, 1);
  DeltaSettings exact;
  exact.quantum = 0.0;
  shore::EnvelopeRaster env;
  for (int k = 0; k < 120; ++k) {
    const Imprint im = wheel_at(server, k / 240.0, env);
    server.step({&im, 1}, 1.0 / 240);
    if (k % 10 != 9) continue;
    const std::vector<unsigned char> delta = SoilDelta::encode(server, sent, exact);
    sent = server.generation();
    mirrored = SoilDelta::apply(replica, delta, mirrored);
    ASSERT_EQ(replica.state_hash(), server.state_hash()) << "step " << k;
  }
  const std::vector<SprayParticle> ps = server.spray_particles(), pr = replica.spray_particles();
  ASSERT_EQ(pr.size(), ps.size());
  int mud = 0;
  for (std::size_t k = 0; k < ps.size(); ++k) {
    EXPECT_EQ(pr[k].material, ps[k].material);
    mud += ps[k].material;
  }
  EXPECT_GT(mud, 0);
}

// A piece holds one material: a plate that carried sand away and then skims mud lays its
// sand there (counted as set down) and leaves with mud, adhesion x area of it per piece.
TEST(SprayMaterials, APieceThatLoadsAnotherMaterialLaysWhatItHeldFirst) {
  const double dt = 1.0 / 240;
  Material sand = shedding("sand-like", 10.0), mud = shedding("mud-like", 10.0);  // hardly sheds in this test
  mud.spray.adhesion = 0.005;
  TerrainSettings s = sand_settings();
  s.material = sand;
  Terrain t(s);
  t.set_palette({sand, mud});
  t.paint_rect({40, -20, 60, 40}, 1);  // mud from x = 0.4 m
  // 100 pieces at 1 m/s: on sand (x ~ 0 to 0.04), lifted (x ~ 0.04 to 0.4), down on mud, lifted.
  double after_sand = 0.0;
  std::int64_t set_down_before = 0;
  for (int k = 0; k < 180; ++k) {
    const double x = 1.0 * k * dt;
    const bool down = k < 10 || (x > 0.5 && x < 0.55);
    const double bottom = down ? -0.001 : 0.1;
    const std::int64_t i0 = t.column_i(x) - 5;
    const shore::EnvelopeRaster env = box_envelope(i0, -5, 10, 10, bottom);
    Imprint im{&env};
    im.velocity.x = 1.0;
    im.centre.x = t.column_x(i0 + 5), im.centre.z = bottom + 0.05;
    im.key = 3;
    if (down && x > 0.5 && after_sand == 0.0) {
      after_sand = t.volume().clinging;
      set_down_before = t.spray_counts().set_down;
    }
    t.step({&im, 1}, dt);
  }
  const double area = 1e-4, sand_load = 100 * 0.002 * area, mud_load = 100 * 0.005 * area;
  const std::int64_t laid = t.spray_counts().set_down - set_down_before;
  std::printf(
      "[ swap ] clinging %.3g m^3 after sand (100 pieces x adhesion: %.3g), %.3g after mud (%.3g); %lld pieces "
      "laid their sand\n",
      after_sand, sand_load, t.volume().clinging, mud_load, static_cast<long long>(laid));
  EXPECT_NEAR(after_sand, sand_load, 0.05 * sand_load);
  EXPECT_GE(laid, 80) << "the pieces that touched mud laid their sand first";  // 90: a tenth miss by a sub-cell shift
  EXPECT_NEAR(t.volume().clinging, mud_load, 0.05 * mud_load) << "what clings is mud alone, not sand + mud";
}
