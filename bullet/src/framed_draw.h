#pragma once
// Internal: a btIDebugDraw that takes lines drawn in the ground's coordinates into the
// world's (shore/bullet/ground_frame.h), so the couplings' debugDraw code draws in one frame.

#include <LinearMath/btIDebugDraw.h>
#include <LinearMath/btTransform.h>

#include "shore/bullet/config.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

class FramedDraw final : public btIDebugDraw {
 public:
  FramedDraw(btIDebugDraw& drawer, const btTransform& to_world) : drawer_(drawer), to_world_(to_world) {}

  void drawLine(const btVector3& from, const btVector3& to, const btVector3& colour) override {
    drawer_.drawLine(to_world_(from), to_world_(to), colour);
  }
  void drawContactPoint(const btVector3& at, const btVector3& normal, btScalar distance, int lifetime,
                        const btVector3& colour) override {
    drawer_.drawContactPoint(to_world_(at), to_world_.getBasis() * normal, distance, lifetime, colour);
  }
  void reportErrorWarning(const char* text) override { drawer_.reportErrorWarning(text); }
  void draw3dText(const btVector3& at, const char* text) override { drawer_.draw3dText(to_world_(at), text); }
  void setDebugMode(int mode) override { drawer_.setDebugMode(mode); }
  [[nodiscard]] int getDebugMode() const override { return drawer_.getDebugMode(); }

 private:
  btIDebugDraw& drawer_;
  btTransform to_world_;
};

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet
