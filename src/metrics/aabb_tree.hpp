// Closest-point queries on a triangle set (for distances between surfaces): a bounding-volume
// hierarchy split at the median of the longest axis, searched nearest-box first.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/vec.hpp"

namespace isoquad {

class AabbTree {
 public:
  explicit AabbTree(std::vector<std::array<Vec3, 3>> triangles);

  struct Hit {
    double distance = 0;
    uint32_t triangle = 0;
    Vec3 point;
  };
  // \pre at least one triangle.
  Hit closest(const Vec3& p) const;
  // The surface normal at the point closest to p: the mean of the unit normals of every
  // triangle that point is on (within 1e-9 of the tree's bounding-box diagonal). Where the
  // closest point is on an edge or a vertex, several triangles are equally close up to
  // rounding, and taking the first one found made the normal depend on the tree's layout (the
  // untangler and `isoquad quality` disagreed on quads at ridges).
  // `hint`, a triangle near p if known, speeds the search up; the result does not depend on it.
  // \pre at least one triangle.
  static constexpr uint32_t kNoTriangle = 0xffffffffu;
  Vec3 normal_at_closest(const Vec3& p, uint32_t hint = kNoTriangle) const;
  // The distance from p to the closest triangle, as closest(p).distance; `hint` as above.
  double distance(const Vec3& p, uint32_t hint) const;
  const std::vector<std::array<Vec3, 3>>& triangles() const { return tris_; }

 private:
  struct Node {
    Box3 box;
    uint32_t left = 0, right = 0;  // children (inner node) or [begin, end) of order_ (leaf)
    bool leaf = false;
  };
  uint32_t build(uint32_t begin, uint32_t end);
  // The closest-point search: every leaf whose box is nearer than best2 (which `triangle`,
  // called with a triangle's index in order_ and its squared distance, lowers), nearer first.
  template <class Triangle>
  void search(const Vec3& p, const double& best2, Triangle&& triangle) const;
  std::vector<std::array<Vec3, 3>> tris_;
  std::vector<uint32_t> order_;
  std::vector<Node> nodes_;
};

// Closest point to p on triangle (a, b, c) (Ericson, Real-Time Collision Detection, 5.1.5).
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace isoquad
