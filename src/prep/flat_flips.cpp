#include <algorithm>
#include <cmath>
#include <numbers>
#include <unordered_map>

#include "prep/steps.hpp"

namespace isoquad::prep {

namespace {

const double kNeedle = 10 * std::numbers::pi / 180;  // a triangle with a smaller angle

// The angle at p of the triangle p, q, r.
double angle_at(const Vec3& p, const Vec3& q, const Vec3& r) { return angle_between(q - p, r - p); }

}  // namespace

// Lawson's flip algorithm restricted to flat quads. Halfedge 3t + i runs from corner i of
// triangle t to corner i + 1; `at` finds a halfedge by its two vertices. The edge
// (a, b) lies in t1 = (a, b, c) and t2 = (b, a, d); the quad a, d, b, c is cut along c-d instead,
// into (a, d, c) and (d, b, c), which keeps the orientation.
uint32_t flip_flat_edges(const std::vector<Vec3>& positions, std::vector<Tri>& tris,
                         double tolerance) {
  // Only edges of needles can flip, and a flip queues the edges around it: the edges of the
  // input's needles are all that need checking at first (none on most meshes). They are queued
  // in the order all edges would be, which the flips depend on.
  auto least_angle = [&](const Tri& t) {
    const Vec3 &p0 = positions[t[0]], &p1 = positions[t[1]], &p2 = positions[t[2]];
    return std::min({angle_at(p0, p1, p2), angle_at(p1, p2, p0), angle_at(p2, p0, p1)});
  };
  std::vector<char> needle(tris.size());
  for (uint32_t t = 0; t < tris.size(); ++t) needle[t] = least_angle(tris[t]) < kNeedle;
  if (std::find(needle.begin(), needle.end(), 1) == needle.end()) return 0;
  std::unordered_map<uint64_t, uint32_t> at;
  at.reserve(3 * tris.size());
  for (uint32_t t = 0; t < tris.size(); ++t)
    for (uint32_t i = 0; i < 3; ++i) at[edge_key(tris[t][i], tris[t][(i + 1) % 3])] = 3 * t + i;
  std::vector<std::pair<uint32_t, uint32_t>> stack;  // edges to check, as (low, high) vertex ids
  for (uint32_t t = uint32_t(tris.size()); t-- > 0;)
    for (uint32_t i = 3; i-- > 0;) {
      const uint32_t a = tris[t][i], b = tris[t][(i + 1) % 3];
      const auto twin = at.find(edge_key(b, a));
      if (a < b && (needle[t] || (twin != at.end() && needle[twin->second / 3])))
        stack.push_back({a, b});
    }
  // Lawson's flips end in the plane; the cap only guards against rounding on near-flat quads.
  const std::size_t max_flips = 20 * tris.size() + 100;
  uint32_t flips = 0;
  while (!stack.empty() && flips < max_flips) {
    const auto [a, b] = stack.back();
    stack.pop_back();
    const auto i1 = at.find(edge_key(a, b)), i2 = at.find(edge_key(b, a));
    if (i1 == at.end() || i2 == at.end()) continue;  // a boundary edge, or flipped away
    const uint32_t t1 = i1->second / 3, t2 = i2->second / 3;
    const uint32_t c = tris[t1][(i1->second + 2) % 3], d = tris[t2][(i2->second + 2) % 3];
    if (c == d || at.count(edge_key(c, d)) || at.count(edge_key(d, c))) continue;
    const Vec3 &pa = positions[a], &pb = positions[b], &pc = positions[c], &pd = positions[d];
    // Delaunay: the angles opposite a-b sum to more than pi (with a margin, so that cocircular
    // points do not flip back and forth).
    if (angle_at(pc, pa, pb) + angle_at(pd, pb, pa) <= std::numbers::pi + 1e-9) continue;
    // Only where a needle is: a triangulation of well-shaped triangles stays as it came.
    if (std::min(least_angle(tris[t1]), least_angle(tris[t2])) >= kNeedle) continue;
    // Flat: the diagonals a-b and c-d pass within `tolerance` of each other, which bounds how
    // far the flip moves the surface.
    const Vec3 across = cross(pb - pa, pd - pc);
    const double l = norm(across);
    if (!(l > 0) || std::fabs(dot(across, pc - pa)) > tolerance * l) continue;
    // Convex: both new triangles face the way the two old ones do.
    const Vec3 n = cross(pb - pa, pc - pa) + cross(pa - pb, pd - pb);
    if (!(dot(cross(pd - pa, pc - pa), n) > 0) || !(dot(cross(pb - pd, pc - pd), n) > 0)) continue;
    for (const auto& [from, to] : {std::pair{a, b}, {b, c}, {c, a}, {b, a}, {a, d}, {d, b}})
      at.erase(edge_key(from, to));
    tris[t1] = {a, d, c};
    tris[t2] = {d, b, c};
    for (const uint32_t t : {t1, t2})
      for (uint32_t i = 0; i < 3; ++i) at[edge_key(tris[t][i], tris[t][(i + 1) % 3])] = 3 * t + i;
    for (const auto& [p, q] : {std::pair{a, d}, {d, b}, {b, c}, {c, a}})
      stack.push_back({std::min(p, q), std::max(p, q)});
    ++flips;
  }
  return flips;
}

}  // namespace isoquad::prep
