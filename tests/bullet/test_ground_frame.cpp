// The ground in any frame (shore/bullet/ground_frame.h): a Y-up world, whose ground is the
// Z-up one turned by -90 degrees about x, gives the same motion in the ground's coordinates,
// the same soil and the same references (Bekker's plate and rolling wheel, Archimedes'
// draft); bad frames and a checkpoint of another frame are refused by name.
#include <gtest/gtest.h>

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "shore/bullet/ground_frame.h"
#include "shore/bullet/terrain_coupling.h"
#include "shore/bullet/water_coupling.h"
#include "shore/core/error.h"
#include "shore/scenes/raycast_car.h"
#include "shore/scenes/soil_cases.h"
#include "shore/scenes/state.h"
#include "shore/scenes/world.h"
#include "shore/terrain/bekker.h"
#include "shore/terrain/terrain.h"
#include "shore/water/surface.h"

using namespace shore;
using bullet::GroundFrame;

namespace {
double rel(double value, double reference) { return std::abs(value - reference) / std::abs(reference); }

/// m (position) or basis entries, whichever differs more.
double pose_difference(const btTransform& a, const btTransform& b) {
  double d = (a.getOrigin() - b.getOrigin()).length();
  for (int r = 0; r < 3; ++r) d = std::max(d, double((a.getBasis()[r] - b.getBasis()[r]).length()));
  return d;
}

/// Three bodies thrown into sand, in a world whose ground lies in `frame`: a sphere, a box
/// and a lying cylinder, released `height` m up (m, ground coordinates) moving down at 1 m/s
/// and sideways at `thrown` (m/s, ground coordinates).
struct Drop {
  explicit Drop(const GroundFrame& frame, double height = 0.4, btVector3 thrown = gentle())
      : soil(sand()), world(9.81, frame), ground(world.world(), soil, on(frame)), sideways(thrown) {
    const auto z = btScalar(height);
    add(std::make_unique<btSphereShape>(btScalar(0.1)), btVector3(0, 0, z));
    add(std::make_unique<btBoxShape>(btVector3(0.1f, 0.08f, 0.06f)), btVector3(0.5f, 0, z));
    add(std::make_unique<btCylinderShapeX>(btVector3(0.12f, 0.07f, 0.07f)), btVector3(0, 0.5f, z));
  }
  /// m/s: the throw's sideways speed unless told (ground coordinates).
  static btVector3 gentle() { return {0.3f, -0.2f, 0}; }
  static terrain::TerrainSettings sand() {
    terrain::TerrainSettings s = scenes::one_thread_terrain();
    s.cell = 0.02;
    return s;
  }
  static bullet::TerrainCouplingSettings on(const GroundFrame& frame) {
    bullet::TerrainCouplingSettings s;
    s.frame = frame;
    return s;
  }
  /// Position and push given in the ground's coordinates.
  void add(std::unique_ptr<btCollisionShape> shape, const btVector3& at) {
    btRigidBody* b =
        world.add_body(std::move(shape), 5.0, world.to_world(btTransform(btQuaternion::getIdentity(), at)));
    b->setActivationState(DISABLE_DEACTIVATION);
    b->setLinearVelocity(world.ground().direction_to_world(sideways + btVector3(0, 0, -1.0f)));
    ground.add_body(b);
  }
  /// The largest difference of each body's ground-frame pose from another drop's over 2 s.
  std::vector<double> differences_from(Drop& other) {
    std::vector<double> worst(3, 0.0);
    for (int k = 0; k < 480; ++k) {
      world.step(1.0 / 240);
      other.world.step(1.0 / 240);
      for (std::size_t b = 0; b < 3; ++b) worst[b] = std::max(worst[b], pose_difference(pose(b), other.pose(b)));
    }
    return worst;
  }
  /// Body k's pose in the ground's coordinates.
  [[nodiscard]] btTransform pose(std::size_t k) const {
    return world.ground().to_ground() * world.bodies()[k]->getWorldTransform();
  }

  terrain::Terrain soil;
  scenes::World world;
  bullet::TerrainCoupling ground;
  btVector3 sideways;
};

/// Per body, the largest difference a nudge of a tenth of a micrometre in the release height
/// makes to a Z-up drop thrown sideways at `thrown` (a few nudges): how chaotic it is.
std::vector<double> nudged_differences(const btVector3& thrown) {
  std::vector<double> nudged(3, 0.0);
  for (const double nudge : {1e-7, -1e-7, 2e-7}) {
    Drop a(GroundFrame::z_up(), 0.4, thrown), b(GroundFrame::z_up(), 0.4 + nudge, thrown);
    const std::vector<double> d = a.differences_from(b);
    for (std::size_t k = 0; k < 3; ++k) nudged[k] = std::max(nudged[k], d[k]);
  }
  return nudged;
}

}  // namespace

TEST(GroundFrame, YUpIsTheZUpWorldTurnedAboutXExactly) {
  const GroundFrame f = GroundFrame::y_up();
  EXPECT_NO_THROW(f.validate("frame"));
  EXPECT_EQ(f.up(), btVector3(0, 1, 0));
  EXPECT_EQ(f.direction_to_world(btVector3(0, 1, 0)), btVector3(0, 0, -1));  // the ground's y is the world's -z
  EXPECT_EQ(f.direction_to_ground(btVector3(0.25f, -3.5f, 7.0f)), btVector3(0.25f, -7.0f, -3.5f));
  EXPECT_TRUE(GroundFrame::z_up().identity());
  EXPECT_FALSE(f.identity());
}

// The same throw in a Z-up and a Y-up world. Bullet keeps orientations as quaternions,
// and a Y-up body's (a quarter turn about x) has irrational components, so the two worlds
// differ from the first substep by float rounding, which landings then amplify as they
// amplify any difference: a box landing flat tips one way or the other. So each body's
// ground-frame pose in the Y-up world must stay within what nudging the Z-up release by a
// tenth of a micrometre does to it (a few nudges, the largest), and the rolling sphere, which
// amplifies nothing, within 20 micrometres.
TEST(GroundFrame, AThrowInAYUpWorldMovesAsInAZUpOne) {
  Drop z_up(GroundFrame::z_up()), y_up(GroundFrame::y_up());
  const std::vector<double> framed = z_up.differences_from(y_up);
  const std::vector<double> nudged = nudged_differences(Drop::gentle());
  const char* names[] = {"sphere", "box", "cylinder"};
  for (std::size_t k = 0; k < 3; ++k) {
    std::printf("%-8s  Y-up %.3g   nudged Z-up %.3g\n", names[k], framed[k], nudged[k]);
    EXPECT_LE(framed[k], 3.0 * nudged[k] + 2e-5) << names[k];
  }
  EXPECT_LT(framed[0], 2e-5) << "the rolling sphere";
  const double sunk = -(z_up.pose(0).getOrigin().z() - 0.1);
  EXPECT_GT(sunk, 0.01) << "the sphere should sink into the sand";
  EXPECT_EQ(y_up.ground.stats().rescues, 0);
  EXPECT_EQ(y_up.ground.stats().skipped_bodies, 0);
  // Readouts are in world coordinates: the soil carries the sphere along the world's y.
  for (int k = 0; k < 240; ++k) y_up.world.step(1.0 / 240);
  const btVector3 push = y_up.ground.terrain_force(y_up.world.bodies()[0]).force;
  EXPECT_NEAR(double(push.y()), 5.0 * 9.81, 0.2 * 5.0 * 9.81) << "the soil's push on the sphere at rest";
  EXPECT_LT(std::abs(double(push.z())), 0.1 * double(push.y()));
}

// Thrown at 8 m/s, the bodies move farther than a quarter of their footprint between two
// soil steps and are pressed along their path (swept), in the ground's coordinates: the
// rolling sphere moves in a Y-up world as in the Z-up one, within what a 0.1 um nudge of its
// start makes. (The box and the cylinder tumble: chaos, printed, not compared.)
TEST(GroundFrame, AFastThrowInAYUpWorldMovesAsInAZUpOne) {
  const btVector3 fast(8.0f, -3.0f, 0);
  Drop z_up(GroundFrame::z_up(), 0.4, fast), y_up(GroundFrame::y_up(), 0.4, fast);
  const std::vector<double> framed = z_up.differences_from(y_up);
  const double nudged = nudged_differences(fast)[0];
  std::printf("fast sphere: Y-up %.3g, nudged Z-up %.3g; box %.3g, cylinder %.3g (Y-up)\n", framed[0], nudged,
              framed[1], framed[2]);
  EXPECT_LE(framed[0], 3.0 * nudged + 2e-5);
  EXPECT_EQ(y_up.ground.stats().skipped_bodies, 0);
}

// Bekker's references hold in a Y-up world as in the Z-up one (the same cases, run through
// the ground frame: scenes/src/soil_cases.cpp).
TEST(GroundFrame, PlateAndTowedWheelMeetBekkerInAYUpWorld) {
  scenes::PlateCase p;
  p.run.coupling.frame = GroundFrame::y_up();
  const scenes::PlateResult plate = scenes::run_plate(p);
  EXPECT_LT(rel(plate.sinkage, plate.reference), 0.05) << plate.sinkage << " m vs Bekker " << plate.reference;
  scenes::PlateCase pz;
  const double z_up = scenes::run_plate(pz).sinkage;
  EXPECT_LT(rel(plate.sinkage, z_up), 1e-3) << "the Z-up plate: " << z_up << " m";

  scenes::WheelCase w;
  w.towed = true;
  w.run.terrain.material.alpha = 0.0;  // compaction alone, as Bekker's rolling wheel
  w.run.coupling.frame = GroundFrame::y_up();
  const scenes::WheelResult wheel = scenes::run_wheel(w);
  EXPECT_LT(rel(wheel.sinkage, wheel.reference_sinkage), 0.10)
      << "rolling sinkage " << wheel.sinkage << " m vs Bekker " << wheel.reference_sinkage;
  EXPECT_GT(wheel.rut_depth, 0.5 * wheel.sinkage);
}

// A box of half the water's density floats at Archimedes' draft in a Y-up world, and the
// water's force on it, in world coordinates, carries its weight along +y.
TEST(GroundFrame, ABoxFloatsAtArchimedesDraftInAYUpWorld) {
  water::PhysicalParameters phys;
  water::SurfaceSettings ws = water::SurfaceSettings::physical(phys, 32, 32);
  ws.origin_x = ws.origin_y = -0.775;
  ws.mode = water::SurfaceMode::vertical_only;
  water::Surface surface(ws);
  const GroundFrame frame = GroundFrame::y_up();
  scenes::World world(9.81, frame);
  bullet::WaterCouplingSettings cs;
  cs.frame = frame;
  bullet::WaterCoupling coupling(world.world(), surface, cs);
  const double density = 0.5 * surface.density(), height = 0.2;
  const double mass = density * 0.3 * 0.3 * height;
  btRigidBody* box =
      world.add_body(std::make_unique<btBoxShape>(btVector3(0.15f, 0.15f, 0.1f)), mass,
                     world.to_world(btTransform(btQuaternion::getIdentity(), btVector3(0.01f, 0.02f, 0.03f))));
  box->setActivationState(DISABLE_DEACTIVATION);
  coupling.add_body(box);
  for (int k = 0; k < 960; ++k) world.step(1.0 / 240);
  const double bottom = double((world.ground().to_ground() * box->getWorldTransform()).getOrigin().z()) - 0.5 * height;
  const double draft = ws.rest_height - bottom, archimedes = height * density / surface.density();
  EXPECT_LT(rel(draft, archimedes), 0.005) << "draft " << draft << " m vs Archimedes " << archimedes;
  const bullet::BodyWater w = coupling.water_force(box);
  EXPECT_NEAR(double(w.force.y()), mass * 9.81, 0.01 * mass * 9.81);
  EXPECT_LT(std::abs(double(w.force.z())), 0.01 * mass * 9.81);
}

// A stock btRaycastVehicle in a Y-up world: its wheels find the tiles (placed through the
// frame) and sink into the sand as far as in a Z-up world, Bekker's static sinkage.
TEST(GroundFrame, ARaycastCarSinksAsInAZUpWorld) {
  auto sinkage = [](const GroundFrame& frame) {
    terrain::TerrainSettings ts = Drop::sand();
    terrain::Terrain soil(ts);
    scenes::World world(9.81, frame);
    bullet::TerrainCoupling coupling(world.world(), soil, Drop::on(frame));
    scenes::RaycastCarSettings s;
    s.mass = 4 * 4000.0 / 9.81;  // 4 kN on each wheel
    s.wheel_radius = 0.4;
    s.wheel_width = 0.3;
    scenes::RaycastCar car(world, s,
                           btVector3(0, 0, btScalar(s.suspension_rest + s.wheel_radius - s.connection_height)));
    const std::array<double, 4> widths{0.3, 0.3, 0.3, 0.3};
    coupling.add_vehicle(&car.vehicle(), widths);
    for (int k = 0; k < 3 * 240; ++k) {  // the weight eased in over 2 s, then 1 s at rest
      const double u = std::min(1.0, double(k) / 480), carried = 1.0 - u * u * (3.0 - 2.0 * u);
      car.chassis()->applyCentralForce(frame.direction_to_world(btVector3(0, 0, btScalar(carried * s.mass * 9.81))));
      world.step(1.0 / 240);
    }
    EXPECT_EQ(car.wheels_on_ground(), 4);
    double depth = 0.0;
    for (int k = 0; k < 4; ++k)
      depth -= double(frame.to_ground()(car.vehicle().getWheelInfo(k).m_raycastInfo.m_contactPointWS).z()) / 4;
    return depth;
  };
  const double y_up = sinkage(GroundFrame::y_up()), z_up = sinkage(GroundFrame::z_up());
  const double bekker = terrain::bekker::wheel_sinkage_static(terrain::Material::sand(), 4000.0, 0.8, 0.3);
  std::printf("raycast car, static sinkage: Y-up %.4f m, Z-up %.4f m, Bekker %.4f m\n", y_up, z_up, bekker);
  EXPECT_LT(rel(y_up, bekker), 0.10);
  // A standing raycast wheel's settling rounds differently with the frame (and with the
  // precision: float and double builds differ by 9 % here), so the two worlds agree to 6 %.
  EXPECT_LT(rel(y_up, z_up), 0.06);
}

// A frame that is not a proper rotation, or not finite, is refused naming the field.
TEST(GroundFrame, BadFramesAreRefusedNamingTheField) {
  terrain::Terrain soil(Drop::sand());
  scenes::World world;
  auto refused = [&](const GroundFrame& f, const std::string& field, const std::string& words) {
    bullet::TerrainCouplingSettings s;
    s.frame = f;
    try {
      bullet::TerrainCoupling coupling(world.world(), soil, s);
      ADD_FAILURE() << "accepted a frame that should be refused: " << field;
    } catch (const InvalidSetting& e) {
      EXPECT_EQ(e.field().rfind(field, 0), 0u) << e.what();
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  GroundFrame scaled;
  scaled.rotation = btMatrix3x3(2, 0, 0, 0, 2, 0, 0, 0, 2);
  refused(scaled, "bullet.TerrainCouplingSettings.frame.rotation", "no scale or shear");
  GroundFrame sheared;
  sheared.rotation = btMatrix3x3(1, 0.3f, 0, 0, 1, 0, 0, 0, 1);
  refused(sheared, "bullet.TerrainCouplingSettings.frame.rotation", "no scale or shear");
  GroundFrame mirrored;
  mirrored.rotation = btMatrix3x3(1, 0, 0, 0, 1, 0, 0, 0, -1);
  refused(mirrored, "bullet.TerrainCouplingSettings.frame.rotation", "determinant");
  GroundFrame nan;
  nan.rotation[1][2] = std::numeric_limits<btScalar>::quiet_NaN();
  refused(nan, "bullet.TerrainCouplingSettings.frame.rotation[1][2]", "finite");
  GroundFrame far;
  far.origin.setX(std::numeric_limits<btScalar>::infinity());
  refused(far, "bullet.TerrainCouplingSettings.frame.origin", "finite");
  bullet::WaterCouplingSettings ws;
  ws.frame = scaled;
  EXPECT_THROW(ws.validate(), InvalidSetting);
}

// A checkpoint knows its frame: a Y-up coupling's state restores into a Y-up coupling and
// is refused, naming the frame, by a Z-up one.
TEST(GroundFrame, ACheckpointRestoresOnlyIntoTheSameFrame) {
  Drop y_up(GroundFrame::y_up());
  for (int k = 0; k < 60; ++k) y_up.world.step(1.0 / 240);
  const std::vector<unsigned char> bytes = y_up.ground.save_state();
  Drop again(GroundFrame::y_up());
  EXPECT_NO_THROW(again.ground.restore_state(bytes, "y-up state"));
  Drop z_up(GroundFrame::z_up());
  try {
    z_up.ground.restore_state(bytes, "y-up state");
    ADD_FAILURE() << "a Z-up coupling took a Y-up state";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("ground frame"), std::string::npos) << e.what();
  }
}
