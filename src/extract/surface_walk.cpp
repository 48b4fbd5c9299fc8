#include "extract/surface_walk.hpp"

#include <algorithm>
#include <cmath>

#include "metrics/aabb_tree.hpp"

namespace isoquad {

std::array<double, 3> barycentric(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 v0 = b - a, v1 = c - a, v2 = q - a;
  const double d00 = dot(v0, v0), d01 = dot(v0, v1), d11 = dot(v1, v1), d20 = dot(v2, v0),
               d21 = dot(v2, v1);
  const double den = d00 * d11 - d01 * d01;
  if (!(std::fabs(den) > 0)) return {1, 0, 0};
  const double v = (d11 * d20 - d01 * d21) / den, w = (d00 * d21 - d01 * d20) / den;
  return {std::max(0.0, 1 - v - w), std::max(0.0, v), std::max(0.0, w)};
}

SurfacePoint project_locally(const TriMesh& base, uint32_t start, const Vec3& p) {
  auto dist = [&](uint32_t f, Vec3& q) {
    const Tri& t = base.face(f);
    q = closest_point_on_triangle(p, base.position(t[0]), base.position(t[1]), base.position(t[2]));
    return squared_norm(q - p);
  };
  Vec3 best_q;
  uint32_t best = start;
  double best_d = dist(start, best_q);
  for (int step = 0; step < 10000; ++step) {
    uint32_t next = best;
    for (const uint32_t v : base.face(best))
      base.for_each_outgoing(v, [&](uint32_t h) {
        const uint32_t f = TriMesh::face_of(h);
        Vec3 q;
        const double d = dist(f, q);
        if (d < best_d || (d == best_d && f < next && next != best)) {
          best_d = d;
          best_q = q;
          next = f;
        }
      });
    if (next == best) break;
    best = next;
  }
  const Tri& t = base.face(best);
  return {best, barycentric(best_q, base.position(t[0]), base.position(t[1]), base.position(t[2]))};
}

Vec3 position_of(const TriMesh& base, const SurfacePoint& s) {
  const Tri& t = base.face(s.face);
  return s.bary[0] * base.position(t[0]) + s.bary[1] * base.position(t[1]) +
         s.bary[2] * base.position(t[2]);
}

Vec3 face_normal(const TriMesh& base, uint32_t f) {
  const Tri& t = base.face(f);
  return normalized(
      cross(base.position(t[1]) - base.position(t[0]), base.position(t[2]) - base.position(t[0])));
}

}  // namespace isoquad
