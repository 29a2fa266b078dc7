#pragma once
// The plain, paper-style form of the surface step, kept to test and benchmark the fast
// kernel against: an array of node structures, forces accumulated one spring at a time
// (each spring computed once and applied with both signs), then one update loop. No
// guard and no threads: step(dt) is exactly one semi-implicit Euler step of length dt.
// Same settings, constraints, disturbances and state layout (displacement from rest) as
// Surface.

#include <vector>

#include "shore/water/disturbance.h"
#include "shore/water/surface_settings.h"

namespace shore::water {

class ReferenceSurface {
 public:
  struct Node {
    float u[3] = {0.f, 0.f, 0.f};  ///< displacement from the rest position (m)
    float v[3] = {0.f, 0.f, 0.f};  ///< velocity (m/s)
    float f[3] = {0.f, 0.f, 0.f};  ///< spring force of the current step (N)
    NodeConstraint constraint = NodeConstraint::free;
  };

  explicit ReferenceSurface(const SurfaceSettings& settings);

  /// One semi-implicit Euler step of length dt (finite, > 0), no substeps.
  void step(double dt);
  void set_constraint(int i, int j, NodeConstraint c);
  /// Validated like Surface::disturb, including the amplitude cap.
  void disturb(const Disturbance& d);

  [[nodiscard]] const Node& node(int i, int j) const {
    return nodes_[static_cast<std::size_t>(j) * static_cast<std::size_t>(settings_.nx) + static_cast<std::size_t>(i)];
  }
  [[nodiscard]] const std::vector<Node>& nodes() const { return nodes_; }
  [[nodiscard]] const SurfaceSettings& settings() const { return settings_; }

 private:
  void accumulate_3d_springs();
  void accumulate_vertical_springs();
  void add_spring(Node& a, Node& b, double rest_dx, double rest_dy, double rest_length);
  void update(double dt);

  SurfaceSettings settings_;
  std::vector<Node> nodes_;
};

}  // namespace shore::water
