#include "shore/bullet/heightfield_tile.h"

#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletCollision/CollisionDispatch/btInternalEdgeUtility.h>
#include <BulletCollision/CollisionDispatch/btManifoldResult.h>
#include <BulletCollision/NarrowPhaseCollision/btManifoldPoint.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "shore/core/error.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {

namespace {

/// Bullet's heightfield, told the range its heights have reached and, optionally, to give
/// convex queries coarser triangles.
///
/// The range: Bullet finds the triangles under a box (a body's AABB in the narrow phase, a
/// sweep's) by visiting every cell under it and keeping those whose height range meets the
/// box's: a car body a metre above 1 cm ground visits some 50,000 cells per substep to keep
/// none. A box wholly above the highest height the tile has held, or below the lowest, meets
/// no triangle, so it is answered at once: the same triangles (none), the same contacts, bit
/// for bit.
///
/// The stride: a character's capsule on 1 cm to 2 cm ground meets thousands of triangles in
/// each of its sweeps and contacts, and Bullet runs GJK on every one (most of a walking
/// character's substep). With a stride k the triangles are those of the heightfield sampled
/// every k-th vertex. Rays do not come here (btCollisionWorld casts them through
/// performRaycast), so they keep every vertex.
class BoundedHeightfield final : public btHeightfieldTerrainShape {
 public:
  BoundedHeightfield(int n, const float* heights, btScalar min_height, btScalar max_height, float initial, int stride)
      : btHeightfieldTerrainShape(n, n, heights, min_height, max_height, 2, false),
        lowest_(initial),
        highest_(initial),
        stride_(stride) {}
  void widen(float lo, float hi) {
    lowest_ = std::min(lowest_, lo);
    highest_ = std::max(highest_, hi);
  }
  void processAllTriangles(btTriangleCallback* callback, const btVector3& aabbMin,
                           const btVector3& aabbMax) const override {
    // A vertex's height as Bullet's getVertex makes it: (raw - origin) times the scaling.
    const btScalar top = (btScalar(highest_) - m_localOrigin[m_upAxis]) * m_localScaling[m_upAxis];
    const btScalar bottom = (btScalar(lowest_) - m_localOrigin[m_upAxis]) * m_localScaling[m_upAxis];
    if (aabbMin[m_upAxis] > top || aabbMax[m_upAxis] < bottom) return;
    if (stride_ == 1)
      btHeightfieldTerrainShape::processAllTriangles(callback, aabbMin, aabbMax);
    else
      coarse_triangles(callback, aabbMin, aabbMax);
  }

 private:
  /// The cells of the stride's coarse grid under the box, as Bullet splits a cell (its
  /// default diagonal, the winding flipped as the tile sets it), each triangle passed on
  /// only if its height range meets the box's.
  void coarse_triangles(btTriangleCallback* callback, const btVector3& aabbMin, const btVector3& aabbMax) const {
    const btVector3 inverse(btScalar(1) / m_localScaling[0], btScalar(1) / m_localScaling[1],
                            btScalar(1) / m_localScaling[2]);
    int lo[3], hi[3];
    quantizeWithClamp(lo, aabbMin * inverse + m_localOrigin, 0);
    quantizeWithClamp(hi, aabbMax * inverse + m_localOrigin, 1);
    // Bullet widens by a vertex either way (a box between grid points); then out to the
    // coarse grid's lines.
    const int last = m_heightStickWidth - 1, k = stride_;
    const auto down = [&](int v) { return std::clamp(v - 1, 0, last) / k * k; };
    const auto up = [&](int v) { return std::min(last, (std::clamp(v + 1, 0, last) + k - 1) / k * k); };
    const int x0 = down(lo[0]), x1 = up(hi[0]), y0 = down(lo[1]), y1 = up(hi[1]);
    const btScalar box_lo = aabbMin[m_upAxis], box_hi = aabbMax[m_upAxis];
    const int a = m_flipTriangleWinding ? 2 : 0, c = 2 - a;  // the winding's first and last slots
    for (int y = y0; y < y1; y += k)
      for (int x = x0; x < x1; x += k) {
        btVector3 v[3];
        getVertex(x, y, v[a]);
        getVertex(x, y + k, v[1]);
        getVertex(x + k, y, v[c]);
        pass_if_meets(callback, v, box_lo, box_hi, 2 * x, y);
        v[a] = v[c];
        getVertex(x + k, y + k, v[c]);
        pass_if_meets(callback, v, box_lo, box_hi, 2 * x + 1, y);
      }
  }
  static void pass_if_meets(btTriangleCallback* callback, btVector3* v, btScalar box_lo, btScalar box_hi, int part,
                            int index) {
    const btScalar z_lo = std::min({v[0].z(), v[1].z(), v[2].z()});
    const btScalar z_hi = std::max({v[0].z(), v[1].z(), v[2].z()});
    if (z_hi >= box_lo && z_lo <= box_hi) callback->processTriangle(v, part, index);
  }

  float lowest_, highest_;  ///< m, every height the tile has held lies in [lowest_, highest_]
  int stride_;              ///< vertices per triangle edge for processAllTriangles
};

}  // namespace

void HeightfieldTileSettings::validate() const {
  const Check c{"bullet.HeightfieldTileSettings"};
  c.at_least("columns", columns, 2);
  c.positive("cell", cell);
  c.finite("origin_x", origin_x);
  c.finite("origin_y", origin_y);
  c.finite("min_height", min_height);
  c.finite("max_height", max_height);
  if (!(max_height > min_height))
    throw InvalidSetting(c.name("max_height"), detail::to_text(max_height),
                         "must be > min_height (" + detail::to_text(min_height) + ")");
  c.in_closed("initial_height", initial_height, min_height, max_height);
  c.non_negative("friction", friction);
  c.at_least("contact_stride", contact_stride, 1);
  if ((columns - 1) % contact_stride != 0)
    throw InvalidSetting(c.name("contact_stride"), std::to_string(contact_stride),
                         "must divide columns - 1 (" + std::to_string(columns - 1) + ")");
}

HeightfieldTile::HeightfieldTile(const HeightfieldTileSettings& settings) : settings_(settings) {
  settings_.validate();
  const int n = settings_.columns;
  heights_.assign(static_cast<std::size_t>(n) * static_cast<std::size_t>(n),
                  static_cast<float>(settings_.initial_height));
  shape_ = std::make_unique<BoundedHeightfield>(n, heights_.data(), static_cast<btScalar>(settings_.min_height),
                                                static_cast<btScalar>(settings_.max_height),
                                                static_cast<float>(settings_.initial_height), settings_.contact_stride);
  shape_->setFlipTriangleWinding(true);
  shape_->setLocalScaling(btVector3(btScalar(settings_.cell), btScalar(settings_.cell), btScalar(1)));
  object_ = std::make_unique<btRigidBody>(btScalar(0), nullptr, shape_.get());
  const double half_span = 0.5 * (n - 1) * settings_.cell;
  btTransform pose;
  pose.setIdentity();
  pose.setOrigin(btVector3(btScalar(settings_.origin_x + half_span), btScalar(settings_.origin_y + half_span),
                           btScalar(0.5 * (settings_.min_height + settings_.max_height))));
  object_->setWorldTransform(pose);
  object_->setFriction(btScalar(settings_.friction));
}

bool HeightfieldTile::set_height(int i, int j, double h) {
  const double clamped = std::clamp(h, settings_.min_height, settings_.max_height);
  const auto stored = static_cast<float>(clamped);
  heights_[static_cast<std::size_t>(j) * static_cast<std::size_t>(settings_.columns) + static_cast<std::size_t>(i)] =
      stored;
  static_cast<BoundedHeightfield*>(shape_.get())->widen(stored, stored);
  return clamped == h;
}

HeightfieldTile::RowWrite HeightfieldTile::set_row(int i0, int j, std::span<const double> h, double max_rise) {
  RowWrite out;
  float* row = heights_.data() + static_cast<std::size_t>(j) * static_cast<std::size_t>(settings_.columns) +
               static_cast<std::size_t>(i0);
  const double lo = settings_.min_height, hi = settings_.max_height;
  float lowest = std::numeric_limits<float>::max(), highest = std::numeric_limits<float>::lowest();
  for (std::size_t k = 0; k < h.size(); ++k) {
    double next = h[k];
    const double now = row[k];
    if (next > now + max_rise) {
      next = now + max_rise;
      if (out.first_held < 0) out.first_held = static_cast<int>(k);
      out.last_held = static_cast<int>(k);
    }
    const double clamped = std::clamp(next, lo, hi);
    out.clamped += clamped != next;
    row[k] = static_cast<float>(clamped);
    lowest = std::min(lowest, row[k]), highest = std::max(highest, row[k]);
  }
  if (!h.empty()) static_cast<BoundedHeightfield*>(shape_.get())->widen(lowest, highest);
  return out;
}

namespace {
/// Tags a tile's shape (its user index; its user pointer is the HeightfieldTile): the
/// callback finds the tile's vertex friction through it.
constexpr int kTileShapeTag = 0x5e0e72;

/// Shore's callback in Bullet's global slot, unless the application has its own there.
void install_callback() {
  if (gContactAddedCallback == nullptr || gContactAddedCallback == adjust_internal_edge_contact)
    gContactAddedCallback = terrain_contact_added;
}
}  // namespace

void HeightfieldTile::update_callback_flag() {
  const int flag = btCollisionObject::CF_CUSTOM_MATERIAL_CALLBACK;
  const bool wanted = edge_info_ != nullptr || !vertex_friction_.empty();
  object_->setCollisionFlags(wanted ? object_->getCollisionFlags() | flag : object_->getCollisionFlags() & ~flag);
}

void HeightfieldTile::smooth_internal_edges() {
  if (!edge_info_) edge_info_ = std::make_unique<btTriangleInfoMap>();
  *edge_info_ = btTriangleInfoMap();
  btGenerateInternalEdgeInfo(shape_.get(), edge_info_.get());
  update_callback_flag();
  install_callback();
}

void HeightfieldTile::set_vertex_friction(std::vector<btScalar> friction) {
  const std::size_t n = static_cast<std::size_t>(settings_.columns);
  if (!friction.empty() && friction.size() != n * n)
    throw InvalidSetting("bullet.HeightfieldTile.set_vertex_friction(friction).size()", std::to_string(friction.size()),
                         "must be 0 or columns^2 = " + std::to_string(n * n));
  for (std::size_t k = 0; k < friction.size(); ++k)
    if (!(friction[k] >= btScalar(0)) || !std::isfinite(double(friction[k])))
      throw InvalidSetting("bullet.HeightfieldTile.set_vertex_friction(friction)[" + std::to_string(k) + "]",
                           detail::to_text(double(friction[k])), "must be finite and >= 0");
  vertex_friction_ = std::move(friction);
  shape_->setUserIndex(vertex_friction_.empty() ? -1 : kTileShapeTag);
  shape_->setUserPointer(vertex_friction_.empty() ? nullptr : this);
  update_callback_flag();
  if (!vertex_friction_.empty()) install_callback();
}

btScalar HeightfieldTile::friction_near(const btVector3& local) const {
  if (vertex_friction_.empty()) return object_->getFriction();
  // Bullet's vertex (i, j) lies at ((i - (n - 1) / 2) cell, (j - (n - 1) / 2) cell) in the
  // object's frame (the shape's origin is the middle of its span).
  const int n = settings_.columns;
  const double half = 0.5 * (n - 1), inverse = 1.0 / settings_.cell;
  const auto nearest = [&](btScalar x) {
    return std::clamp(static_cast<int>(std::floor(double(x) * inverse + half + 0.5)), 0, n - 1);
  };
  return vertex_friction_[static_cast<std::size_t>(nearest(local.y())) * static_cast<std::size_t>(n) +
                          static_cast<std::size_t>(nearest(local.x()))];
}

namespace {
bool smoothed_terrain(const btCollisionObjectWrapper* w) {
  const btCollisionShape* shape = w->getCollisionObject()->getCollisionShape();
  return shape->getShapeType() == TERRAIN_SHAPE_PROXYTYPE &&
         static_cast<const btHeightfieldTerrainShape*>(shape)->getTriangleInfoMap() != nullptr;
}

/// The tile of a wrapper's object if it has a vertex friction, else null.
const HeightfieldTile* painted_tile(const btCollisionObjectWrapper* w) {
  const btCollisionShape* shape = w->getCollisionObject()->getCollisionShape();
  if (shape->getShapeType() != TERRAIN_SHAPE_PROXYTYPE || shape->getUserIndex() != kTileShapeTag) return nullptr;
  return static_cast<const HeightfieldTile*>(shape->getUserPointer());
}

/// Bullet's default combination (btManifoldResult::calculateCombinedFriction).
btScalar combined_friction(btScalar body, btScalar ground) {
  constexpr btScalar kMaxFriction = 10;
  return std::clamp(body * ground, -kMaxFriction, kMaxFriction);
}
}  // namespace

bool terrain_contact_added(btManifoldPoint& cp, const btCollisionObjectWrapper* a, int part_a, int index_a,
                           const btCollisionObjectWrapper* b, int part_b, int index_b) {
  adjust_internal_edge_contact(cp, a, part_a, index_a, b, part_b, index_b);
  if (const HeightfieldTile* tile = painted_tile(a); tile != nullptr)
    cp.m_combinedFriction =
        combined_friction(b->getCollisionObject()->getFriction(), tile->friction_near(cp.m_localPointA));
  else if (const HeightfieldTile* t = painted_tile(b); t != nullptr)
    cp.m_combinedFriction =
        combined_friction(a->getCollisionObject()->getFriction(), t->friction_near(cp.m_localPointB));
  return false;
}

bool adjust_internal_edge_contact(btManifoldPoint& cp, const btCollisionObjectWrapper* a, int part_a, int index_a,
                                  const btCollisionObjectWrapper* b, int part_b, int index_b) {
  if (smoothed_terrain(a))
    btAdjustInternalEdgeContacts(cp, a, b, part_a, index_a);
  else if (smoothed_terrain(b))
    btAdjustInternalEdgeContacts(cp, b, a, part_b, index_b);
  return false;
}

double HeightfieldTile::height(int i, int j) const {
  return heights_[static_cast<std::size_t>(j) * static_cast<std::size_t>(settings_.columns) +
                  static_cast<std::size_t>(i)];
}

}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
