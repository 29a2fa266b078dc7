#pragma once
// Triangle meshes of Bullet collision shapes, in the shape's local frame, for drawing:
// analytic for spheres, boxes, capsules, cylinders and cones (the nominal solids the
// envelopes describe, scaling applied); convex hulls and point clouds from their points
// (btConvexHullComputer); concave shapes (triangle meshes, GImpact meshes, heightfields)
// from their triangles; compounds as the union of their children; any other convex shape
// from its support function sampled in many directions.

#include <cstdint>
#include <vector>

#include <BulletCollision/CollisionShapes/btCollisionShape.h>

namespace shore::render {

struct ShapeMesh {
  std::vector<float> positions;  ///< xyz per vertex, local frame, m
  std::vector<float> normals;    ///< xyz per vertex, unit
  std::vector<std::uint32_t> indices;
  [[nodiscard]] std::size_t vertex_count() const { return positions.size() / 3; }
  [[nodiscard]] std::size_t triangle_count() const { return indices.size() / 3; }
};

/// The shape's mesh; `segments` sets the smoothness of round shapes (>= 8). A shape type
/// that has no solid to draw (a static plane is drawn as a 200 m square) gives the closest
/// stand-in; an empty concave shape gives an empty mesh.
ShapeMesh shape_mesh(const btCollisionShape& shape, int segments = 32);

}  // namespace shore::render
