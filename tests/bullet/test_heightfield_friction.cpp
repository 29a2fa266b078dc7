// Bullet's own heightfield contact follows the material map: a box the coupling does not
// serve (Bullet collides it with the tiles) slides over ground painted with two materials of
// different Material::friction and decelerates by Coulomb's mu g on each; an application's
// own contact-added callback stays installed and, forwarding to Shore's, gives the same
// motion; a palette that paints nothing leaves the motion bit for bit as on one material.

#include <gtest/gtest.h>

#include <btBulletDynamicsCommon.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "shore/bullet/heightfield_tile.h"
#include "shore/bullet/terrain_coupling.h"
#include "shore/scenes/world.h"
#include "shore/terrain/terrain.h"

using namespace shore;

namespace {

constexpr double kG = 9.81, kH = 1.0 / 240;
/// m: half the side of the slab that slides (0.2 m thick: a taller box pitches onto its
/// front edge under its friction torque, and Bullet's box contact then brakes it harder
/// than Coulomb, on one material as on a map: 6.38 m/s^2 at mu 0.6 for a 0.4 m cube).
constexpr btScalar kHalf = 0.4f;

terrain::Material ground(const char* name, double friction) {
  terrain::Material m = terrain::Material::rigid_ground();
  m.name = name;
  m.friction = friction;
  return m;
}

enum class Paint { none, palette_only, halves };

/// x and vx of the box every substep.
struct Slide {
  std::vector<double> x, vx;
  std::vector<unsigned char> bits;  ///< the box's pose and velocity bytes at the end
};

/// A 0.8 x 0.8 x 0.2 m slab of friction 1 (so the contact's is the ground's), launched at 8 m/s along
/// +x from x = -4 m over rigid ground whose columns at x >= 0.8 m are painted `ice` (friction
/// 0.2; the rest friction 0.6), not added to the coupling. The border runs through the middle
/// of a tile (1.6 m): near it the tiles' friction is per vertex, farther off per tile.
Slide slide(Paint paint) {
  terrain::TerrainSettings s;
  s.cell = 0.05;
  s.tile_columns = 32;
  s.threads = 1;
  s.material = ground("asphalt", 0.6);
  terrain::Terrain soil(s);
  if (paint != Paint::none) soil.set_palette({s.material, ground("ice", 0.2)});
  if (paint == Paint::halves) soil.paint_rect({16, -40, 400, 80}, 1);  // from x = 0.8 m, mid-tile
  scenes::World world(kG);
  bullet::TerrainCoupling coupling(world.world(), soil);
  btRigidBody* box = world.add_body(std::make_unique<btBoxShape>(btVector3(kHalf, kHalf, 0.1f)), 10.0,
                                    btVector3(btScalar(-4.0), btScalar(0.0), btScalar(0.1)));
  box->setFriction(1.0f);
  box->setActivationState(DISABLE_DEACTIVATION);
  box->setLinearVelocity(btVector3(8.0f, 0.0f, 0.0f));
  Slide out;
  for (int k = 0; k < 3 * 240; ++k) {
    world.step(kH);
    out.x.push_back(double(box->getCenterOfMassPosition().x()));
    out.vx.push_back(double(box->getLinearVelocity().x()));
  }
  const btTransform& t = box->getWorldTransform();
  const btVector3 v = box->getLinearVelocity();
  for (const btVector3& w : {t.getOrigin(), v}) {
    const auto* p = reinterpret_cast<const unsigned char*>(&w);
    out.bits.insert(out.bits.end(), p, p + sizeof w);
  }
  return out;
}

/// The deceleration (m/s^2) over the substeps whose box lies wholly in [x0, x1] and still
/// slides (least squares of vx over time).
double deceleration(const Slide& s, double x0, double x1) {
  double st = 0, sv = 0, stt = 0, stv = 0;
  int n = 0;
  for (std::size_t k = 0; k < s.x.size(); ++k) {
    if (s.x[k] - kHalf < x0 || s.x[k] + kHalf > x1 || s.vx[k] < 0.3) continue;
    const double t = static_cast<double>(k) * kH;
    st += t, sv += s.vx[k], stt += t * t, stv += t * s.vx[k], ++n;
  }
  if (n < 20) return std::nan("");
  return -(n * stv - st * sv) / (n * stt - st * st);
}

bool forwarded = false;
bool user_callback(btManifoldPoint& cp, const btCollisionObjectWrapper* a, int pa, int ia,
                   const btCollisionObjectWrapper* b, int pb, int ib) {
  forwarded = true;
  return bullet::terrain_contact_added(cp, a, pa, ia, b, pb, ib);
}

}  // namespace

TEST(HeightfieldFriction, ABoxBrakesByCoulombOnEachPaintedMaterial) {
  const Slide s = slide(Paint::halves);
  // The slab wholly on one material, a cell from the border.
  const double on_asphalt = deceleration(s, -3.9, 0.75), on_ice = deceleration(s, 0.85, 20.0);
  // Where it stops: v^2 = 8^2 - 2 mu_a g (distance on asphalt), then v^2 / (2 mu_i g) on ice.
  const double v2 = 64.0 - 2.0 * 0.6 * kG * 4.8, stop = 0.8 + v2 / (2.0 * 0.2 * kG);
  std::printf(
      "[ slide ] asphalt %.3f m/s^2 (mu g %.3f), ice %.3f m/s^2 (mu g %.3f); stopped at x %.2f m (Coulomb %.2f)\n",
      on_asphalt, 0.6 * kG, on_ice, 0.2 * kG, s.x.back(), stop);
  EXPECT_NEAR(on_asphalt, 0.6 * kG, 0.03 * 0.6 * kG);
  EXPECT_NEAR(on_ice, 0.2 * kG, 0.03 * 0.2 * kG);
  // The slab brakes a percent or two above Coulomb on the asphalt (its friction torque loads
  // its front edge): that takes about 0.2 m off its run on the ice.
  EXPECT_NEAR(s.x.back(), stop, 0.25) << "Coulomb's stopping point on the ice";
}

TEST(HeightfieldFriction, AnApplicationsOwnCallbackStaysAndForwardingGivesTheSameSlide) {
  const ContactAddedCallback before = gContactAddedCallback;
  const Slide shore_s = slide(Paint::halves);
  gContactAddedCallback = user_callback;
  forwarded = false;
  const Slide user_s = slide(Paint::halves);
  EXPECT_EQ(gContactAddedCallback, &user_callback) << "Shore replaced the application's callback";
  EXPECT_TRUE(forwarded);
  EXPECT_EQ(user_s.bits, shore_s.bits);
  gContactAddedCallback = before;
}

TEST(HeightfieldFriction, APaletteThatPaintsNothingSlidesBitForBitAsOneMaterial) {
  const Slide one = slide(Paint::none), unpainted = slide(Paint::palette_only);
  EXPECT_EQ(unpainted.bits, one.bits);
  EXPECT_NEAR(deceleration(one, -3.9, 20.0), 0.6 * kG, 0.03 * 0.6 * kG);
}

TEST(HeightfieldFriction, AVertexFrictionOfTheWrongSizeIsRefusedByName) {
  bullet::HeightfieldTileSettings hs;
  hs.columns = 5;
  bullet::HeightfieldTile tile(hs);
  try {
    tile.set_vertex_friction(std::vector<btScalar>(24, btScalar(0.5)));
    FAIL() << "no exception";
  } catch (const InvalidSetting& e) {
    EXPECT_NE(std::strstr(e.what(), "set_vertex_friction(friction).size()"), nullptr) << e.what();
    EXPECT_NE(std::strstr(e.what(), "columns^2 = 25"), nullptr) << e.what();
  }
  std::vector<btScalar> f(25, btScalar(0.5));
  f[7] = btScalar(-1);
  EXPECT_THROW(tile.set_vertex_friction(f), InvalidSetting);
  EXPECT_FALSE(tile.has_vertex_friction());
}
