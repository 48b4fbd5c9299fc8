#include "metrics/aabb_tree.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace isoquad {

namespace {

Box3 box_of(const std::array<Vec3, 3>& t) {
  Box3 b;
  for (const Vec3& p : t) b.add(p);
  return b;
}

// The largest of lo - p, 0 and p - hi per axis, as compares the compiler turns into maxsd
// (std::max of an initializer list was a loop over it: 5% of a fandisk remesh).
double box_distance2(const Box3& b, const Vec3& p) {
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double below = b.lo[k] - p[k], above = p[k] - b.hi[k];
    double d = below > 0.0 ? below : 0.0;
    d = above > d ? above : d;
    d2 += d * d;
  }
  return d2;
}

}  // namespace

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Voronoi regions of the vertices, then of the edges, else the face.
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = va + vb + vc;
  if (!(std::fabs(denom) > 0)) return a;  // degenerate triangle
  const double v = vb / denom, w = vc / denom;
  return a + v * ab + w * ac;
}

AabbTree::AabbTree(std::vector<std::array<Vec3, 3>> triangles) : tris_(std::move(triangles)) {
  order_.resize(tris_.size());
  std::iota(order_.begin(), order_.end(), 0u);
  nodes_.reserve(2 * tris_.size() / 4 + 2);
  if (!tris_.empty()) build(0, uint32_t(tris_.size()));
}

uint32_t AabbTree::build(uint32_t begin, uint32_t end) {
  const uint32_t id = uint32_t(nodes_.size());
  nodes_.push_back({});
  Box3 box, centers;
  for (uint32_t i = begin; i < end; ++i) {
    const auto& t = tris_[order_[i]];
    box.add(box_of(t).lo);
    box.add(box_of(t).hi);
    centers.add((t[0] + t[1] + t[2]) / 3.0);
  }
  nodes_[id].box = box;
  if (end - begin <= 4) {
    nodes_[id].leaf = true;
    nodes_[id].left = begin;
    nodes_[id].right = end;
    return id;
  }
  const Vec3 ext = centers.hi - centers.lo;
  const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
  const uint32_t mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](uint32_t a, uint32_t b) {
                     const double ca = tris_[a][0][axis] + tris_[a][1][axis] + tris_[a][2][axis];
                     const double cb = tris_[b][0][axis] + tris_[b][1][axis] + tris_[b][2][axis];
                     return ca < cb || (ca == cb && a < b);
                   });
  const uint32_t l = build(begin, mid);
  const uint32_t r = build(mid, end);
  nodes_[id].left = l;
  nodes_[id].right = r;
  return id;
}

template <class Triangle>
void AabbTree::search(const Vec3& p, const double& best2, Triangle&& triangle) const {
  // Depth-first, nearer child first; the tree is balanced (median splits), so its depth is
  // about log2(n / 4) and a fixed stack of 128 holds any search.
  std::array<uint32_t, 128> stack;
  std::size_t top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (box_distance2(node.box, p) >= best2) continue;
    if (node.leaf) {
      for (uint32_t i = node.left; i < node.right; ++i) {
        const auto& t = tris_[order_[i]];
        triangle(i, squared_norm(closest_point_on_triangle(p, t[0], t[1], t[2]) - p));
      }
      continue;
    }
    const double dl = box_distance2(nodes_[node.left].box, p);
    const double dr = box_distance2(nodes_[node.right].box, p);
    // Push the farther child first so the nearer one is searched first.
    if (dl <= dr) {
      stack[top++] = node.right;
      stack[top++] = node.left;
    } else {
      stack[top++] = node.left;
      stack[top++] = node.right;
    }
  }
}

AabbTree::Hit AabbTree::closest(const Vec3& p) const {
  Hit best{INFINITY, 0, {}};
  double best2 = INFINITY;
  search(p, best2, [&](uint32_t i, double d2) {
    if (d2 < best2 || (d2 == best2 && order_[i] < best.triangle)) {
      best2 = d2;
      best.triangle = order_[i];
    }
  });
  if (best2 < INFINITY) {
    const auto& t = tris_[best.triangle];
    best.point = closest_point_on_triangle(p, t[0], t[1], t[2]);
  }
  best.distance = std::sqrt(best2);
  return best;
}

double AabbTree::distance(const Vec3& p, uint32_t hint) const {
  double best2 = INFINITY;
  if (hint < tris_.size()) {
    const auto& t = tris_[hint];
    best2 = squared_norm(closest_point_on_triangle(p, t[0], t[1], t[2]) - p);
  }
  search(p, best2, [&](uint32_t, double d2) { best2 = std::min(best2, d2); });
  return std::sqrt(best2);
}

Vec3 AabbTree::normal_at_closest(const Vec3& p, uint32_t hint) const {
  // One search for the closest distance d and every triangle within d + tol of p: the bound
  // shrinks as closer triangles are found, candidates beyond it are dropped at the end.
  const double tol = 1e-9 * nodes_[0].box.diagonal();
  double best = INFINITY;
  if (hint < tris_.size()) {
    const auto& t = tris_[hint];
    best = norm(closest_point_on_triangle(p, t[0], t[1], t[2]) - p);
  }
  thread_local std::vector<std::pair<double, uint32_t>> near;
  near.clear();
  std::array<uint32_t, 128> stack;
  std::size_t top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    const double bound = best + tol;
    if (box_distance2(node.box, p) > bound * bound) continue;
    if (!node.leaf) {
      // Nearer child first, so that the bound shrinks early. The triangles kept are those within
      // the final bound, whatever the order of the search.
      if (box_distance2(nodes_[node.left].box, p) <= box_distance2(nodes_[node.right].box, p)) {
        stack[top++] = node.right;
        stack[top++] = node.left;
      } else {
        stack[top++] = node.left;
        stack[top++] = node.right;
      }
      continue;
    }
    for (uint32_t i = node.left; i < node.right; ++i) {
      const auto& t = tris_[order_[i]];
      const double d = norm(closest_point_on_triangle(p, t[0], t[1], t[2]) - p);
      if (d > best + tol) continue;
      best = std::min(best, d);
      near.push_back({d, order_[i]});
    }
  }
  // In triangle order, so that the sum does not depend on the tree's layout.
  std::sort(near.begin(), near.end(),
            [](const auto& a, const auto& b) { return a.second < b.second; });
  Vec3 sum{0, 0, 0};
  uint32_t first = kNoTriangle;
  for (const auto& [d, i] : near) {
    if (d > best + tol) continue;
    if (first == kNoTriangle) first = i;
    const auto& t = tris_[i];
    const Vec3 n = cross(t[1] - t[0], t[2] - t[0]);
    const double l = norm(n);
    if (l > 0) sum = sum + n / l;
  }
  const double l = norm(sum);
  if (l > 0) return sum / l;
  const auto& t = tris_[first == kNoTriangle ? closest(p).triangle : first];
  return normalized(cross(t[1] - t[0], t[2] - t[0]));
}

}  // namespace isoquad
