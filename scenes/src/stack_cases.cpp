#include "shore/scenes/stack_cases.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include <btBulletDynamicsCommon.h>

#include "shore/bullet/terrain_coupling.h"
#include "shore/core/error.h"
#include "shore/scenes/world.h"
#include "shore/terrain/bekker.h"
#include "shore/terrain/terrain.h"

namespace shore::scenes {

SoilRun StackCase::four_centimetre_run() {
  SoilRun run;
  run.terrain.cell = 0.04;
  return run;
}

StackResult run_stack(const StackCase& c) {
  if (!c.run.coupling.frame.identity())
    throw InvalidSetting("scenes.StackCase.run.coupling.frame", "not the identity",
                         "this case runs in a Z-up world only");
  if (c.boxes < 1) throw InvalidSetting("scenes.StackCase.boxes", detail::to_text(c.boxes), "must be at least 1");
  if (!(c.box_mass > 0.0))
    throw InvalidSetting("scenes.StackCase.box_mass", detail::to_text(c.box_mass), "must be positive");
  const double gravity = 9.81;
  World world(gravity, c.run.coupling.frame);
  terrain::Terrain soil(c.run.terrain);
  bullet::TerrainCoupling coupling(world.world(), soil, c.run.coupling);
  const btVector3 half = c.half_extents;
  const double height = 2.0 * double(half.z()), surface = c.run.terrain.base_height;
  std::vector<btRigidBody*> boxes;
  for (int k = 0; k < c.boxes; ++k) {
    const btVector3 at(0, 0, btScalar(surface + (k + 0.5) * height));
    btRigidBody* box = world.add_body(std::make_unique<btBoxShape>(half), c.box_mass, at);
    box->setActivationState(DISABLE_DEACTIVATION);
    coupling.add_body(box);
    boxes.push_back(box);
  }
  StackResult out;
  const double h = c.run.substep;
  const int steps = static_cast<int>(std::lround(c.seconds / h)), last_second = static_cast<int>(std::lround(1.0 / h));
  for (int k = 0; k < steps; ++k) {
    world.step(h);
    for (std::size_t b = 0; b < boxes.size(); ++b) {
      const btVector3 x = boxes[b]->getCenterOfMassPosition();
      out.finite =
          out.finite && std::isfinite(double(x.x())) && std::isfinite(double(x.y())) && std::isfinite(double(x.z()));
      if (b > 0) {
        const double gap = double(x.z() - boxes[b - 1]->getCenterOfMassPosition().z()) - height;
        out.overlap = std::max(out.overlap, -gap);
      }
      if (k >= steps - last_second)
        out.late_speed = std::max(out.late_speed, double(boxes[b]->getLinearVelocity().length()));
    }
  }
  out.sinkage = surface - (double(boxes.front()->getCenterOfMassPosition().z()) - 0.5 * height);
  const double width = 2.0 * double(std::min(half.x(), half.y()));
  const double area = 4.0 * double(half.x() * half.y());
  out.reference =
      terrain::bekker::plate_sinkage_released(c.run.terrain.material, width, c.boxes * c.box_mass * gravity / area);
  out.rescues = coupling.stats().rescues;
  return out;
}

}  // namespace shore::scenes
