#include "shore/demo/rigid_world.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace shore::demo {
namespace {

void hash_vector(StateHash& h, const btVector3& v) {
  for (int k = 0; k < 3; ++k) h.add(v[k]);
}

long non_finite(const btVector3& v) {
  long n = 0;
  for (int k = 0; k < 3; ++k) n += std::isfinite(static_cast<double>(v[k])) ? 0 : 1;
  return n;
}

}  // namespace

RigidWorld::RigidWorld(const bullet::HeightfieldTileSettings& tile, const std::function<double(double, double)>& ground,
                       double gravity)
    : config_(std::make_unique<btDefaultCollisionConfiguration>()),
      dispatcher_(std::make_unique<btCollisionDispatcher>(config_.get())),
      broadphase_(std::make_unique<btDbvtBroadphase>()),
      solver_(std::make_unique<btSequentialImpulseConstraintSolver>()),
      world_(std::make_unique<btDiscreteDynamicsWorld>(dispatcher_.get(), broadphase_.get(), solver_.get(),
                                                       config_.get())),
      tile_(std::make_unique<bullet::HeightfieldTile>(tile)) {
  world_->setGravity(btVector3(0, 0, static_cast<btScalar>(-gravity)));
  const auto& s = tile_->settings();
  for (int j = 0; j < s.columns; ++j)
    for (int i = 0; i < s.columns; ++i)
      tile_->set_height(i, j, ground(s.origin_x + i * s.cell, s.origin_y + j * s.cell));
  world_->addCollisionObject(tile_->object());
}

RigidWorld::~RigidWorld() {
  for (auto& b : bodies_) world_->removeRigidBody(b.get());
  world_->removeCollisionObject(tile_->object());
}

btRigidBody& RigidWorld::add_body(std::unique_ptr<btCollisionShape> shape, double mass, const btTransform& pose) {
  btVector3 inertia(0, 0, 0);
  shape->calculateLocalInertia(static_cast<btScalar>(mass), inertia);
  auto motion = std::make_unique<btDefaultMotionState>(pose);
  auto body = std::make_unique<btRigidBody>(
      btRigidBody::btRigidBodyConstructionInfo(static_cast<btScalar>(mass), motion.get(), shape.get(), inertia));
  world_->addRigidBody(body.get());
  shapes_.push_back(std::move(shape));
  motions_.push_back(std::move(motion));
  body_list_.push_back(body.get());
  bodies_.push_back(std::move(body));
  return *bodies_.back();
}

btRigidBody& RigidWorld::add_box(const btVector3& half_extents, double mass, const btTransform& pose) {
  return add_body(std::make_unique<btBoxShape>(half_extents), mass, pose);
}

btRigidBody& RigidWorld::add_cylinder(double radius, double half_width, double mass, const btTransform& pose) {
  const btVector3 half(static_cast<btScalar>(radius), static_cast<btScalar>(half_width), static_cast<btScalar>(radius));
  return add_body(std::make_unique<btCylinderShape>(half), mass, pose);
}

void RigidWorld::step(double h) { world_->stepSimulation(static_cast<btScalar>(h), 1, static_cast<btScalar>(h)); }

std::uint64_t RigidWorld::state_hash() const {
  StateHash h;
  for (const btRigidBody* b : body_list_) {
    const btTransform& t = b->getWorldTransform();
    hash_vector(h, t.getOrigin());
    for (int r = 0; r < 3; ++r) hash_vector(h, t.getBasis()[r]);
    hash_vector(h, b->getLinearVelocity());
    hash_vector(h, b->getAngularVelocity());
  }
  const int n = tile_->columns();
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) h.add(static_cast<float>(tile_->height(i, j)));
  return h.value();
}

long RigidWorld::nan_count() const {
  long count = 0;
  for (const btRigidBody* b : body_list_) {
    const btTransform& t = b->getWorldTransform();
    count += non_finite(t.getOrigin()) + non_finite(b->getLinearVelocity()) + non_finite(b->getAngularVelocity());
    for (int r = 0; r < 3; ++r) count += non_finite(t.getBasis()[r]);
  }
  const int n = tile_->columns();
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) count += std::isfinite(tile_->height(i, j)) ? 0 : 1;
  return count;
}

HeightGrid RigidWorld::ground_grid() const {
  const auto& s = tile_->settings();
  HeightGrid g(s.columns, s.columns, s.cell, s.origin_x, s.origin_y);
  for (int j = 0; j < s.columns; ++j)
    for (int i = 0; i < s.columns; ++i) g.at(i, j) = tile_->height(i, j);
  return g;
}

namespace {
/// z of the first hit of a vertical ray from z0 to z1 against one body, or NaN.
double cast(const btRigidBody& b, double x, double y, double z0, double z1) {
  const btVector3 from(static_cast<btScalar>(x), static_cast<btScalar>(y), static_cast<btScalar>(z0));
  const btVector3 to(from.x(), from.y(), static_cast<btScalar>(z1));
  btTransform ray_from, ray_to;
  ray_from.setIdentity();
  ray_from.setOrigin(from);
  ray_to.setIdentity();
  ray_to.setOrigin(to);
  btCollisionWorld::ClosestRayResultCallback hit(from, to);
  // rayTestSingle takes a non-const object but only reads it.
  btCollisionWorld::rayTestSingle(ray_from, ray_to, const_cast<btRigidBody*>(&b), b.getCollisionShape(),
                                  b.getWorldTransform(), hit);
  return hit.hasHit() ? static_cast<double>(hit.m_hitPointWorld.z()) : std::numeric_limits<double>::quiet_NaN();
}

/// Exact lower/upper z of a box on the vertical line through (x, y) (slab method);
/// false if the line misses it.
bool box_span(const btRigidBody& b, const btBoxShape& box, double x, double y, double& lower, double& upper) {
  const btTransform& t = b.getWorldTransform();
  const btVector3 half = box.getHalfExtentsWithMargin();
  const btMatrix3x3& r = t.getBasis();
  const btVector3& c = t.getOrigin();
  // Line p(s) = (x, y, s): in box coordinates o + s d with o = R^T ((x, y, 0) - c), d = R^T e_z.
  double lo = -1e300, hi = 1e300;
  for (int a = 0; a < 3; ++a) {
    const double d = r[2][a];
    const double o = r[0][a] * (x - c.x()) + r[1][a] * (y - c.y()) + r[2][a] * (0.0 - c.z());
    const double h = half[a];
    if (std::abs(d) < 1e-12) {
      if (std::abs(o) > h) return false;
      continue;
    }
    const double s0 = (-h - o) / d, s1 = (h - o) / d;
    lo = std::max(lo, std::min(s0, s1));
    hi = std::min(hi, std::max(s0, s1));
  }
  if (lo > hi) return false;
  lower = lo;
  upper = hi;
  return true;
}
}  // namespace

RigidWorld::Envelopes RigidWorld::body_envelopes() const {
  const auto& s = tile_->settings();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Envelopes e{HeightGrid(s.columns, s.columns, s.cell, s.origin_x, s.origin_y, nan),
              HeightGrid(s.columns, s.columns, s.cell, s.origin_x, s.origin_y, nan)};
  for (const btRigidBody* b : body_list_) {
    btVector3 lo, hi;
    b->getAabb(lo, hi);
    const int i0 = std::max(0, static_cast<int>(std::floor((lo.x() - s.origin_x) / s.cell)));
    const int i1 = std::min(s.columns - 1, static_cast<int>(std::ceil((hi.x() - s.origin_x) / s.cell)));
    const int j0 = std::max(0, static_cast<int>(std::floor((lo.y() - s.origin_y) / s.cell)));
    const int j1 = std::min(s.columns - 1, static_cast<int>(std::ceil((hi.y() - s.origin_y) / s.cell)));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const double x = e.top.x(i), y = e.top.y(j);
        double top = 0.0, bottom = 0.0;
        if (const auto* box = dynamic_cast<const btBoxShape*>(b->getCollisionShape())) {
          if (!box_span(*b, *box, x, y, bottom, top)) continue;
        } else {
          top = cast(*b, x, y, hi.z() + 1.0, lo.z() - 1.0);
          if (!std::isfinite(top)) continue;
          bottom = cast(*b, x, y, lo.z() - 1.0, hi.z() + 1.0);
          if (!std::isfinite(bottom)) bottom = top;  // grazing ray: keep the column thin
        }
        double& t = e.top.at(i, j);
        double& u = e.bottom.at(i, j);
        t = std::isfinite(t) ? std::max(t, top) : top;
        u = std::isfinite(u) ? std::min(u, bottom) : bottom;
      }
  }
  return e;
}

double RigidWorld::ground_height(double x, double y) const {
  const auto& s = tile_->settings();
  const double fi = std::clamp((x - s.origin_x) / s.cell, 0.0, s.columns - 1.0);
  const double fj = std::clamp((y - s.origin_y) / s.cell, 0.0, s.columns - 1.0);
  const int i = std::min(static_cast<int>(fi), s.columns - 2);
  const int j = std::min(static_cast<int>(fj), s.columns - 2);
  const double u = fi - i, v = fj - j;
  // Bullet 3.24 splits each cell along the (i+1, j)-(i, j+1) diagonal unless told otherwise.
  const double h00 = tile_->height(i, j), h10 = tile_->height(i + 1, j);
  const double h01 = tile_->height(i, j + 1), h11 = tile_->height(i + 1, j + 1);
  if (u + v <= 1.0) return h00 + u * (h10 - h00) + v * (h01 - h00);
  return h11 + (1.0 - u) * (h01 - h11) + (1.0 - v) * (h10 - h11);
}

double lowest_corner_z(const btRigidBody& box, const btVector3& half) {
  double lowest = std::numeric_limits<double>::infinity();
  const btTransform& t = box.getWorldTransform();
  for (int c = 0; c < 8; ++c) {
    const btVector3 local((c & 1) ? half.x() : -half.x(), (c & 2) ? half.y() : -half.y(),
                          (c & 4) ? half.z() : -half.z());
    lowest = std::min(lowest, static_cast<double>((t * local).z()));
  }
  return lowest;
}

}  // namespace shore::demo
