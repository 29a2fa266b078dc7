// A ball dropped straight down onto soil: nothing in a vertical impact turns it, throws it
// sideways or gives back more than the soil's damped unloading spring can.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include <btBulletDynamicsCommon.h>

#include "shore/bullet/terrain_coupling.h"
#include "shore/scenes/world.h"
#include "shore/terrain/terrain.h"

using namespace shore;

namespace {

constexpr double kCell = 0.02, kRadius = 0.1, kMass = 10.0, kH = 1.0 / 240;

struct Drop {
  double rebound = 0.0;    ///< m/s, the fastest it moved up after touching
  double peak_spin = 0.0;  ///< rad/s
  double end_spin = 0.0;   ///< rad/s
  double drift = 0.0;      ///< m, horizontally from where it was dropped, at the end
};

/// The 10 kg, 0.2 m ball released just above the surface moving down at `speed`, its
/// centre `offset` cells past a column centre along x (and 0.3 of that along y).
Drop drop(const terrain::Material& m, double offset, double speed, double seconds) {
  terrain::TerrainSettings s;
  s.cell = kCell;
  s.material = m;
  s.threads = 1;
  terrain::Terrain soil(s);
  scenes::World world;
  bullet::TerrainCoupling ground(world.world(), soil);
  const double x0 = offset * kCell, y0 = 0.3 * offset * kCell;
  btRigidBody* ball = world.add_body(std::make_unique<btSphereShape>(btScalar(kRadius)), kMass,
                                     btVector3(btScalar(x0), btScalar(y0), btScalar(kRadius + 0.001)));
  ball->setActivationState(DISABLE_DEACTIVATION);
  ball->setLinearVelocity(btVector3(0, 0, btScalar(-speed)));
  ground.add_body(ball);
  Drop d;
  const auto steps = static_cast<int>(std::lround(seconds / kH));
  for (int k = 0; k < steps; ++k) {
    world.step(kH);
    d.rebound = std::max(d.rebound, double(ball->getLinearVelocity().z()));
    d.peak_spin = std::max(d.peak_spin, double(ball->getAngularVelocity().length()));
  }
  const btVector3 x = ball->getCenterOfMassPosition();
  d.end_spin = double(ball->getAngularVelocity().length());
  d.drift = std::hypot(double(x.x()) - x0, double(x.y()) - y0);
  return d;
}

terrain::Material stiffest() {  // the extreme smoke's stiffest soil (scenes/src/extreme_cases.cpp)
  terrain::Material m = terrain::Material::sand();
  m.name = "stiffest";
  m.bekker_kc = 0.0, m.bekker_kphi = 1e12;
  return m;
}

}  // namespace

// The bars. Rebound: the soil gives back only through its unloading springs, damped at 0.3
// of critical (contact_solver.cpp), whose restitution is exp(-pi 0.3 / sqrt(1 - 0.3^2)) =
// 0.37 of the approach speed at most (rigid-plastic soil, mud, gives none). Drift: the grid's
// asymmetry (the ball's centre off a column centre, the 4 x 4 blocks split around it) can
// move where the push acts by at most half a cell, so the ball may settle off its drop point
// by less than that, never roll off its pit (it did, 0.5 to 1 m on the stiffest soil: the
// impact set it rolling at 0.5 to 0.8 m/s and up to 10 rad/s). Spin: at rest at the end.
TEST(SoilImpact, AVerticalDropNeitherSpinsNorThrowsTheBall) {
  const double restitution = std::exp(-3.141592653589793 * 0.3 / std::sqrt(1.0 - 0.3 * 0.3));
  const terrain::Material soils[] = {terrain::Material::sand(), terrain::Material::mud(), stiffest()};
  for (const terrain::Material& m : soils)
    for (const double offset : {0.0, 0.37})
      for (const double speed : {5.0, 10.0}) {
        const Drop d = drop(m, offset, speed, 0.6);
        std::printf("%-9s offset %.2f cell, %4.1f m/s: rebound %.3f m/s, spin peak %.3f end %.4f rad/s, drift %.5f m\n",
                    m.name.c_str(), offset, speed, d.rebound, d.peak_spin, d.end_spin, d.drift);
        const std::string what = m.name + " at " + std::to_string(speed) + " m/s, offset " + std::to_string(offset);
        EXPECT_LT(d.rebound, restitution * speed) << what;
        EXPECT_LT(d.drift, 0.5 * kCell) << what;
        EXPECT_LT(d.end_spin * kRadius, 1e-3) << what << ": still turning, " << d.end_spin << " rad/s";
      }
}
