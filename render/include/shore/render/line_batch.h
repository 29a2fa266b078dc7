#pragma once
// A btIDebugDraw that keeps the lines it is given (world positions, RGB colours) for the
// renderer to draw in one batch: the couplings' debugDraw and Bullet's own debug drawing
// go through it.

#include <vector>

#include <LinearMath/btIDebugDraw.h>

namespace shore::render {

class LineBatch : public btIDebugDraw {
 public:
  /// xyz rgb per line end, two ends per line.
  struct End {
    float x, y, z, r, g, b;
  };

  void drawLine(const btVector3& from, const btVector3& to, const btVector3& colour) override;
  void drawContactPoint(const btVector3& point, const btVector3& normal, btScalar distance, int lifetime,
                        const btVector3& colour) override;
  void reportErrorWarning(const char*) override {}
  void draw3dText(const btVector3&, const char*) override {}
  void setDebugMode(int mode) override { mode_ = mode; }
  [[nodiscard]] int getDebugMode() const override { return mode_; }

  void clear() { ends_.clear(); }
  [[nodiscard]] const std::vector<End>& ends() const noexcept { return ends_; }
  [[nodiscard]] std::size_t line_count() const noexcept { return ends_.size() / 2; }

 private:
  std::vector<End> ends_;
  int mode_ = 0;
};

}  // namespace shore::render
