// Probe: a ball dropped vertically onto soil; spin and drift over time.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include <btBulletDynamicsCommon.h>

#include "shore/bullet/terrain_coupling.h"
#include "shore/scenes/world.h"
#include "shore/terrain/terrain.h"

using namespace shore;

namespace {
struct Probe {
  double max_spin = 0, max_drift = 0, end_spin = 0, end_drift = 0;
};

Probe drop(const terrain::Material& m, double cell, double offset, double speed, double seconds, bool print,
           bullet::TerrainCouplingSettings cs = {}) {
  terrain::TerrainSettings s;
  s.cell = cell;
  s.material = m;
  s.threads = 1;
  terrain::Terrain soil(s);
  scenes::World world;
  bullet::TerrainCoupling ground(world.world(), soil, cs);
  const double R = 0.1, h = 1.0 / 240;
  const double x0 = offset * cell, y0 = (offset == -0.5 ? 1.0 : 0.3) * offset * cell;
  btRigidBody* ball = world.add_body(std::make_unique<btSphereShape>(btScalar(R)), 10.0,
                                     btVector3(btScalar(x0), btScalar(y0), btScalar(R + 0.001)));
  ball->setActivationState(DISABLE_DEACTIVATION);
  ball->setLinearVelocity(btVector3(0, 0, btScalar(-speed)));
  ground.add_body(ball);
  Probe p;
  const int n = int(std::lround(seconds / h));
  for (int k = 0; k < n; ++k) {
    world.step(h);
    const btVector3 w = ball->getAngularVelocity(), x = ball->getCenterOfMassPosition(), v = ball->getLinearVelocity();
    const double spin = double(w.length()), drift = std::hypot(double(x.x()) - x0, double(x.y()) - y0);
    p.max_spin = std::max(p.max_spin, spin);
    p.max_drift = std::max(p.max_drift, drift);
    p.end_spin = spin, p.end_drift = drift;
    if (print && (k < 16 || k % 24 == 0))
      std::printf("  k %3d z %.5f vz %8.4f vx %8.5f w (%8.4f %8.4f %8.4f) drift %.5f\n", k, double(x.z()), double(v.z()),
                  double(v.x()), double(w.x()), double(w.y()), double(w.z()), drift);
  }
  return p;
}

terrain::Material stiffest() {
  terrain::Material m = terrain::Material::sand();
  m.bekker_kc = 0.0, m.bekker_kphi = 1e12;
  return m;
}
}  // namespace

TEST(ImpactSpinProbe, Table) {
  const bool print = std::getenv("SPIN_PRINT") != nullptr;
  struct Soil {
    const char* name;
    terrain::Material m;
  } soils[] = {{"sand", terrain::Material::sand()}, {"mud", terrain::Material::mud()}, {"stiffest", stiffest()}};
  for (const Soil& s : soils)
    for (double offset : {0.0, -0.5, 0.37})
      for (double speed : {4.43, 8.0})
        for (int it : {6, 50})
          for (int bc : {4, 1}) {
            bullet::TerrainCouplingSettings cs;
            cs.contact.iterations = it;
            cs.contact.block_columns = bc;
            char label[64];
            std::snprintf(label, sizeof label, "%s/%.2f/%.2f/%d/%d", s.name, offset, speed, it, bc);
            const bool here = print && std::string(std::getenv("SPIN_PRINT")) == label;
            const Probe p = drop(s.m, 0.02, offset, speed, 1.0, here, cs);
            std::printf("%-9s offset %5.2f speed %.2f it %2d bc %d: max spin %7.4f end spin %7.4f rad/s, max drift %.5f end %.5f m\n",
                        s.name, offset, speed, it, bc, p.max_spin, p.end_spin, p.max_drift, p.end_drift);
          }
}
