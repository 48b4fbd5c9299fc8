#include "metrics/quality.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>
#include <random>
#include <unordered_map>
#include <unordered_set>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "core/element_data.hpp"
#include "core/union_find.hpp"
#include "core/z_order.hpp"
#include "metrics/aabb_tree.hpp"
#include "metrics/feature_coverage.hpp"

namespace isoquad {

int64_t Topology::genus() const {
  return (2 * int64_t(components) - euler - int64_t(boundary_loops)) / 2;
}

std::string topology_change(const Topology& input, const Topology& output) {
  std::string out;
  const auto differs = [&](const char* what, int64_t before, int64_t after) {
    if (before != after)
      out += fmt::format("{}{} {} -> {}", out.empty() ? "" : ", ", what, before, after);
  };
  differs("genus", input.genus(), output.genus());
  differs("boundary loops", input.boundary_loops, output.boundary_loops);
  differs("connected pieces", input.components, output.components);
  if (out.empty()) differs("Euler characteristic", input.euler, output.euler);
  return out;
}

namespace {

struct EdgeUse {
  uint32_t count = 0, forward = 0;  // forward: used as (min -> max)
  uint32_t f0 = kInvalidFace, c0 = 0, f1 = kInvalidFace, c1 = 0;
  static constexpr uint32_t kInvalidFace = 0xFFFFFFFFu;
};

uint64_t edge_key(uint32_t a, uint32_t b) {
  return (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
}

struct FaceShape {
  double sj = INFINITY;          // against the face's Newell normal
  double sj_surface = INFINITY;  // against the reference's normal at each corner
  double angle_deviation_sum = 0, angle_deviation_max = 0;  // |corner angle - 90| in degrees
  double aspect = 0;  // of a 4-sided face (QualityReport::aspect_mean)
  double area = 0;    // the vector area: half the Newell vector's length
};

// The shape of the polygon whose i-th corner is at(i), of n corners. Its scaled Jacobian is the
// minimum over its corners of n . (e1 x e2)/(|e1||e2|), n the Newell normal: 0 at a corner of
// 180 degrees up to rounding, which kMinValidScaledJacobian counts as invalid with the folds.
// The Newell vector of the polygon whose i-th corner is at(i): twice its vector area.
template <class Corner>
Vec3 newell_vector(std::size_t count, Corner at) {
  Vec3 n;
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3& a = at(i);
    const Vec3& b = at((i + 1) % count);
    n += Vec3{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
  }
  return n;
}

template <class Corner>
FaceShape polygon_shape(std::size_t count, Corner at, const AabbTree* reference) {
  Vec3 n = newell_vector(count, at);
  FaceShape s;
  s.area = 0.5 * norm(n);
  n = normalized(n);
  if (count == 4) {
    double side[4];
    for (std::size_t i = 0; i < 4; ++i) side[i] = norm(at((i + 1) % 4) - at(i));
    const double a = 0.5 * (side[0] + side[2]), b = 0.5 * (side[1] + side[3]);
    s.aspect = std::min(a, b) > 0 ? std::max(a, b) / std::min(a, b) : INFINITY;
  }
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3& p = at(i);
    const Vec3 e1 = at((i + 1) % count) - p;
    const Vec3 e2 = at((i + count - 1) % count) - p;
    const double l = norm(e1) * norm(e2);
    const Vec3 c = cross(e1, e2);
    s.sj = std::min(s.sj, l > 0 ? dot(n, c) / l : 0.0);
    if (reference) {
      // The normal just inside the corner: at a vertex on a crease, the side the quad lies on.
      const Vec3 rn = reference->normal_at_closest(p + 0.05 * (e1 + e2));
      s.sj_surface = std::min(s.sj_surface, l > 0 ? dot(rn, c) / l : 0.0);
    }
    const double angle =
        l > 0 ? std::acos(std::clamp(dot(e1, e2) / l, -1.0, 1.0)) * 180 / std::numbers::pi : 0.0;
    s.angle_deviation_sum += std::fabs(angle - 90);
    s.angle_deviation_max = std::max(s.angle_deviation_max, std::fabs(angle - 90));
  }
  return s;
}

FaceShape face_shape(const PolyMesh& m, std::size_t f, const AabbTree* reference) {
  const auto vs = m.face(f);
  return polygon_shape(
      vs.size(), [&](std::size_t i) -> const Vec3& { return m.positions[vs[i]]; }, reference);
}

std::vector<std::array<Vec3, 3>> fan_triangles(const PolyMesh& m) {
  std::vector<std::array<Vec3, 3>> t;
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    const auto vs = m.face(f);
    for (std::size_t i = 1; i + 1 < vs.size(); ++i)
      t.push_back({m.positions[vs[0]], m.positions[vs[i]], m.positions[vs[i + 1]]});
  }
  return t;
}

// SplitMix64 (Steele, Lea and Flood 2014): its increment and its output function.
constexpr uint64_t kGolden = 0x9e3779b97f4a7c15ull;
uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

// The triangles' corners, each point once (a vertex is a corner of about six triangles), in the
// order of first use; `slot[3 * t + k]` is the index in the result of corner k of triangle t.
std::vector<Vec3> distinct_corners(const std::vector<std::array<Vec3, 3>>& tris,
                                   std::vector<uint32_t>& slot) {
  // Sorted by value, not through indices: a third of the time on bunny00's 226k corners.
  struct Corner {
    Vec3 p;
    uint32_t i;
    bool operator<(const Corner& o) const {
      if (p.x != o.p.x) return p.x < o.p.x;
      if (p.y != o.p.y) return p.y < o.p.y;
      if (p.z != o.p.z) return p.z < o.p.z;
      return i < o.i;
    }
  };
  std::vector<Corner> c(3 * tris.size());
  for (uint32_t i = 0; i < c.size(); ++i) c[i] = {tris[i / 3][i % 3], i};
  std::sort(c.begin(), c.end());
  std::vector<uint32_t> first_of(c.size());  // per corner, the corner (in file order) it repeats
  for (std::size_t k = 0; k < c.size(); ++k)
    first_of[c[k].i] = k == 0 || !(c[k].p == c[k - 1].p) ? c[k].i : first_of[c[k - 1].i];
  // c is sorted by (position, corner): the first of a run of equal positions is its smallest
  // corner, so first_of[i] <= i and the slots can be given in one pass in corner order.
  std::vector<Vec3> points;
  slot.assign(c.size(), 0);
  for (uint32_t i = 0; i < c.size(); ++i) {
    if (first_of[i] == i) {
      slot[i] = uint32_t(points.size());
      points.push_back(tris[i / 3][i % 3]);
    } else {
      slot[i] = slot[first_of[i]];
    }
  }
  return points;
}

// The closest points of `to` to `points`, in parallel: queried in Z-curve order (neighbouring
// queries walk the same tree nodes: input faces are often listed in no spatial order), stored in
// point order.
std::vector<AabbTree::Hit> closest_in(const std::vector<Vec3>& points, const AabbTree& to) {
  const std::vector<uint32_t> order = z_order(points);
  std::vector<AabbTree::Hit> hit(points.size());
  tbb::parallel_for(std::size_t(0), points.size(), [&](std::size_t k) {
    const uint32_t i = order[k];
    hit[i] = to.closest(points[i]);
  });
  return hit;
}

// The largest distance from the triangles of `from` to `to` within a guaranteed error, raising
// max_d (at max_at) found at the vertices and samples (`corner` holds each triangle's corners'
// closest points). A triangle's points are no farther from `to` than either of two bounds:
// - its farthest corner plus its longest edge / sqrt(3) (the distance is 1-Lipschitz, and every
//   point of a triangle lies within that of a corner);
// - its corners' largest distance to one triangle T of `to` (the distance to T is convex, so
//   its maximum over a triangle is at a corner), T the closest triangle of one of the corners:
//   tight where a piece lies over one triangle of `to`, as the quads over a coarse input do.
// Triangles whose bound exceeds the maximum found (by more than kMaxDistanceRelativeError of it,
// or 1e-6 of `scale`, the triangles' bounding-box diagonal) are cut into four at their edge
// midpoints and the midpoints measured, until no bound does: a branch and bound after Guthe,
// Borodin and Klein (2005), "Fast and accurate Hausdorff distance calculation between meshes".
// Samples alone miss the top of a narrow peak (20,000 of them put the elephant's quads 0.95% or
// 1.07% of the diagonal from the surface, by the draw). The work is bounded (`budget` measured
// points), which only surfaces that all but coincide reach: past it max_d is what was found, a
// lower bound.
void refine_maximum(const std::vector<std::array<Vec3, 3>>& from,
                    const std::vector<AabbTree::Hit>& corner, const AabbTree& to, double scale,
                    std::size_t budget, double& max_d, Vec3& max_at) {
  struct Piece {
    std::array<Vec3, 3> p;
    std::array<double, 3> d;
    std::array<uint32_t, 3> near;  // the corners' closest triangles of `to`
  };
  const double kInvSqrt3 = 1 / std::numbers::sqrt3;
  const auto& tris = to.triangles();
  auto open = [&](const Piece& t) {
    const double limit = max_d + std::max(kMaxDistanceRelativeError * max_d, 1e-6 * scale);
    const double longest = std::sqrt(
        std::max({dot(t.p[1] - t.p[0], t.p[1] - t.p[0]), dot(t.p[2] - t.p[1], t.p[2] - t.p[1]),
                  dot(t.p[0] - t.p[2], t.p[0] - t.p[2])}));
    if (std::max({t.d[0], t.d[1], t.d[2]}) + kInvSqrt3 * longest <= limit) return false;
    for (int k = 0; k < 3; ++k) {
      if (k > 0 && (t.near[k] == t.near[0] || (k == 2 && t.near[2] == t.near[1]))) continue;
      const auto& tri = tris[t.near[k]];
      double most = 0;
      for (int c = 0; c < 3 && most <= limit; ++c)
        most = std::max(most,
                        norm(t.p[c] - closest_point_on_triangle(t.p[c], tri[0], tri[1], tri[2])));
      if (most <= limit) return false;
    }
    return true;
  };
  std::vector<Piece> active;
  for (std::size_t t = 0; t < from.size(); ++t) {
    const AabbTree::Hit* h = &corner[3 * t];
    const Piece piece{from[t],
                      {h[0].distance, h[1].distance, h[2].distance},
                      {h[0].triangle, h[1].triangle, h[2].triangle}};
    if (open(piece)) active.push_back(piece);
  }
  std::size_t spent = 0;
  std::vector<Vec3> mid;
  std::vector<Piece> next;
  while (!active.empty() && spent < budget) {
    mid.clear();
    for (const Piece& t : active)
      for (int k = 0; k < 3; ++k) mid.push_back(0.5 * t.p[k] + 0.5 * t.p[(k + 1) % 3]);
    const std::vector<AabbTree::Hit> mh = closest_in(mid, to);
    spent += mid.size();
    for (std::size_t i = 0; i < mid.size(); ++i)
      if (mh[i].distance > max_d) max_d = mh[i].distance, max_at = mid[i];
    next.clear();
    for (std::size_t a = 0; a < active.size(); ++a) {
      const Piece& t = active[a];
      const Vec3 m0 = mid[3 * a], m1 = mid[3 * a + 1], m2 = mid[3 * a + 2];  // p0p1, p1p2, p2p0
      const double e0 = mh[3 * a].distance, e1 = mh[3 * a + 1].distance,
                   e2 = mh[3 * a + 2].distance;
      const uint32_t n0 = mh[3 * a].triangle, n1 = mh[3 * a + 1].triangle,
                     n2 = mh[3 * a + 2].triangle;
      for (const Piece& c : {Piece{{t.p[0], m0, m2}, {t.d[0], e0, e2}, {t.near[0], n0, n2}},
                             Piece{{m0, t.p[1], m1}, {e0, t.d[1], e1}, {n0, t.near[1], n1}},
                             Piece{{m2, m1, t.p[2]}, {e2, e1, t.d[2]}, {n2, n1, t.near[2]}},
                             Piece{{m0, m1, m2}, {e0, e1, e2}, {n0, n1, n2}}})
        if (open(c)) next.push_back(c);
    }
    std::swap(active, next);
  }
}

// One-sided distances from `from` to `to`: the maximum within kMaxDistanceRelativeError (from the
// vertices, area samples and refine_maximum), the sum and count for the mean (over the vertices
// and the area samples).
void sample_distances(const std::vector<std::array<Vec3, 3>>& from, const AabbTree& to,
                      uint32_t samples, uint64_t seed, double& max_d, Vec3& max_at, double& sum_d,
                      uint64_t& count) {
  double total = 0;
  Box3 box;
  for (const auto& t : from) {
    total += 0.5 * norm(cross(t[1] - t[0], t[2] - t[0]));
    for (const Vec3& c : t) box.add(c);
  }
  // Each triangle draws its share of the samples at the density samples / total area (the whole
  // part, and one more with the probability of the fraction) from a generator seeded by `seed`
  // and the triangle's corners: a triangle that stays keeps its points whatever changes
  // elsewhere, so the mean moves with what changed and not with a reshuffle of every sample.
  // Then the points' distances in parallel, the maximum and the sum in point order: the same
  // figures for any thread count.
  std::vector<uint32_t> slot;
  std::vector<Vec3> points = distinct_corners(from, slot);
  points.reserve(points.size() + samples);
  const double density = total > 0 ? double(samples) / total : 0;
  for (const auto& t : from) {
    uint64_t state = seed;
    for (const Vec3& c : t)
      for (int k = 0; k < 3; ++k) state = mix64((state + kGolden) ^ std::bit_cast<uint64_t>(c[k]));
    auto uniform = [&] { return double(mix64(state += kGolden) >> 11) * 0x1.0p-53; };
    const double expected = density * 0.5 * norm(cross(t[1] - t[0], t[2] - t[0]));
    double whole = std::floor(expected);
    if (uniform() < expected - whole) whole += 1;
    for (uint32_t s = 0; s < uint32_t(whole); ++s) {
      double a = uniform(), b = uniform();
      if (a + b > 1) a = 1 - a, b = 1 - b;
      points.push_back(t[0] + a * (t[1] - t[0]) + b * (t[2] - t[0]));
    }
  }
  const std::vector<AabbTree::Hit> hit = closest_in(points, to);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (hit[i].distance > max_d) max_d = hit[i].distance, max_at = points[i];
    sum_d += hit[i].distance;
    ++count;
  }
  std::vector<AabbTree::Hit> corner(slot.size());
  for (std::size_t i = 0; i < slot.size(); ++i) corner[i] = hit[slot[i]];
  // The budget is only reached where the surfaces all but coincide (every bound stays open until
  // the pieces are as small as the error allowed); elsewhere a few thousand points settle it.
  refine_maximum(from, corner, to, box.diagonal(), 4 * points.size() + 4096, max_d, max_at);
}

double mean_of(const std::vector<double>& x) {
  double sum = 0;
  for (const double v : x) sum += v;
  return x.empty() ? 0.0 : sum / double(x.size());
}

// Standard deviation over the mean (0 for no values or a mean of 0), in two passes: exactly 0
// for equal values.
double coefficient_of_variation(const std::vector<double>& x) {
  const double mean = mean_of(x);
  if (!(mean > 0)) return 0;
  double sum2 = 0;
  for (const double v : x) sum2 += (v - mean) * (v - mean);
  return std::sqrt(sum2 / double(x.size())) / mean;
}

// Every edge of the polygons once, in the order of first use.
std::vector<std::array<Vec3, 2>> unique_edges(const PolyMesh& m) {
  std::unordered_set<uint64_t> seen;
  seen.reserve(m.face_vertices.size());
  std::vector<std::array<Vec3, 2>> edges;
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    const auto vs = m.face(f);
    for (std::size_t i = 0; i < vs.size(); ++i) {
      const uint32_t a = vs[i], b = vs[(i + 1) % vs.size()];
      if (seen.insert(edge_key(a, b)).second) edges.push_back({m.positions[a], m.positions[b]});
    }
  }
  return edges;
}

// Scaled Jacobians (against the Newell normal and, with a reference, the surface's) and corner
// angles over every face.
void summarize_shapes(const PolyMesh& m, const std::vector<FaceShape>& shapes, bool surface,
                      QualityReport& q) {
  double sj_sum = 0, angle_sum = 0;
  uint32_t below_half = 0, corners_seen = 0;
  q.sj_min = q.sj_surface_min = INFINITY;
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    const FaceShape& s = shapes[f];
    angle_sum += s.angle_deviation_sum;
    q.angle_deviation_max = std::max(q.angle_deviation_max, s.angle_deviation_max);
    corners_seen += uint32_t(m.face(f).size());
    q.sj_min = std::min(q.sj_min, s.sj);
    sj_sum += s.sj;
    below_half += s.sj < 0.5;
    q.sj_invalid += s.sj <= kMinValidScaledJacobian;
    q.sj_nonpositive += s.sj <= 0;
    if (surface) {
      q.sj_surface_min = std::min(q.sj_surface_min, s.sj_surface);
      q.sj_surface_nonpositive += s.sj_surface <= 0;
    }
  }
  if (m.num_faces()) {
    q.sj_mean = sj_sum / double(m.num_faces());
    q.sj_below_half = 100.0 * below_half / double(m.num_faces());
  }
  if (!surface) q.sj_surface_min = 0;
  if (corners_seen) q.angle_deviation_mean = angle_sum / corners_seen;
}

// Aspect ratios and the spread of areas over the 4-sided faces.
void summarize_quads(const PolyMesh& m, const std::vector<FaceShape>& shapes, QualityReport& q) {
  std::vector<double> aspect, area;
  for (std::size_t f = 0; f < m.num_faces(); ++f)
    if (m.face(f).size() == 4) {
      aspect.push_back(shapes[f].aspect);
      area.push_back(shapes[f].area);
    }
  if (aspect.empty()) return;
  q.aspect_mean = mean_of(aspect);
  const auto above = std::count_if(aspect.begin(), aspect.end(), [](double a) { return a > 2; });
  q.aspect_above_2 = 100.0 * double(above) / double(aspect.size());
  // Nearest rank: the smallest value at least 95% of the quads do not exceed.
  const std::size_t rank = (95 * aspect.size() + 99) / 100 - 1;
  std::nth_element(aspect.begin(), aspect.begin() + std::ptrdiff_t(rank), aspect.end());
  q.aspect_p95 = aspect[rank];
  q.area_cv = coefficient_of_variation(area);
}

}  // namespace

SurfaceDistance surface_distance(const std::vector<std::array<Vec3, 3>>& a, const AabbTree& b_tree,
                                 uint32_t samples, uint64_t seed) {
  const AabbTree a_tree(a);
  double max_a = 0, sum_a = 0, max_b = 0, sum_b = 0;
  Vec3 at_a, at_b;
  uint64_t na = 0, nb = 0;
  sample_distances(a, b_tree, samples, seed, max_a, at_a, sum_a, na);
  sample_distances(b_tree.triangles(), a_tree, samples, seed + 1, max_b, at_b, sum_b, nb);
  SurfaceDistance d;
  d.max = std::max(max_a, max_b);
  d.on_b = max_b > max_a;
  d.at = d.on_b ? at_b : at_a;
  d.mean =
      0.5 * (sum_a / double(std::max<uint64_t>(na, 1)) + sum_b / double(std::max<uint64_t>(nb, 1)));
  return d;
}

Topology topology_of(const PolyMesh& m, bool* edge_manifold, bool* vertex_manifold, bool* oriented,
                     std::vector<uint32_t>* boundary_vertex_flag,
                     std::vector<uint32_t>* corner_count) {
  std::unordered_map<uint64_t, EdgeUse> edges;
  edges.reserve(m.face_vertices.size());
  std::vector<uint32_t> corner_base(m.num_faces() + 1, 0);
  for (std::size_t f = 0; f < m.num_faces(); ++f)
    corner_base[f + 1] = corner_base[f] + uint32_t(m.face(f).size());
  bool em = true, ori = true;
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    const auto vs = m.face(f);
    for (std::size_t i = 0; i < vs.size(); ++i) {
      const uint32_t a = vs[i], b = vs[(i + 1) % vs.size()];
      EdgeUse& e = edges[edge_key(a, b)];
      if (e.count == 0) {
        e.f0 = uint32_t(f);
        e.c0 = uint32_t(i);
      } else if (e.count == 1) {
        e.f1 = uint32_t(f);
        e.c1 = uint32_t(i);
      }
      ++e.count;
      e.forward += a < b;
    }
  }
  std::vector<char> used(m.num_vertices(), 0);
  for (const uint32_t v : m.face_vertices) used[v] = 1;
  UnionFind comp(uint32_t(m.num_vertices()));
  UnionFind bloops(uint32_t(m.num_vertices()));
  UnionFind corners(corner_base.back());
  std::vector<uint32_t> boundary(m.num_vertices(), 0);
  for (const auto& [key, e] : edges) {
    const uint32_t a = uint32_t(key >> 32), b = uint32_t(key & 0xFFFFFFFFu);
    comp.unite(a, b);
    if (e.count > 2) em = false;
    if (e.count == 2 && e.forward != 1) ori = false;
    if (e.count == 1) {
      bloops.unite(a, b);
      ++boundary[a];
      ++boundary[b];
    }
    if (e.count == 2) {  // glue the corners of both faces at each end of the edge
      const auto n0 = uint32_t(m.face(e.f0).size()), n1 = uint32_t(m.face(e.f1).size());
      const uint32_t f0a = corner_base[e.f0] + e.c0, f0b = corner_base[e.f0] + (e.c0 + 1) % n0;
      const uint32_t f1a = corner_base[e.f1] + e.c1, f1b = corner_base[e.f1] + (e.c1 + 1) % n1;
      // Face 1 runs the edge the other way (when oriented): its start is face 0's end.
      const bool same_start = m.face(e.f0)[e.c0] == m.face(e.f1)[e.c1];
      corners.unite(f0a, same_start ? f1a : f1b);
      corners.unite(f0b, same_start ? f1b : f1a);
    }
  }
  // Vertex manifold: the corners at each vertex form one fan, and it has 0 or 2 boundary edges.
  std::vector<uint32_t> fan(m.num_vertices(), kInvalid);
  std::vector<uint32_t> count(m.num_vertices(), 0);
  bool vm = true;
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    const auto vs = m.face(f);
    for (std::size_t i = 0; i < vs.size(); ++i) {
      const uint32_t r = corners.find(corner_base[f] + uint32_t(i));
      ++count[vs[i]];
      if (fan[vs[i]] == kInvalid)
        fan[vs[i]] = r;
      else if (fan[vs[i]] != r)
        vm = false;
    }
  }
  for (uint32_t v = 0; v < m.num_vertices(); ++v)
    if (boundary[v] != 0 && boundary[v] != 2) vm = false;
  Topology t;
  int64_t nv = 0;
  for (uint32_t v = 0; v < m.num_vertices(); ++v) {
    if (!used[v]) continue;
    ++nv;
    if (comp.find(v) == v) ++t.components;
    if (boundary[v] && bloops.find(v) == v) ++t.boundary_loops;
  }
  t.euler = nv - int64_t(edges.size()) + int64_t(m.num_faces());
  if (edge_manifold) *edge_manifold = em;
  if (vertex_manifold) *vertex_manifold = vm && em;
  if (oriented) *oriented = ori;
  if (boundary_vertex_flag) *boundary_vertex_flag = boundary;
  if (corner_count) *corner_count = count;
  return t;
}

QualityReport measure_quality(const PolyMesh& m, const PolyMesh* reference,
                              const QualityOptions& options) {
  // Distances and Jacobians square coordinates: meshes near the ends of the double range are
  // measured at a power-of-two scale (exact), and the lengths scaled back.
  const int exponent = magnitude_exponent(reference ? reference->positions : m.positions);
  if (std::abs(exponent) > kSafeExponent) {
    PolyMesh ms = m, rs = reference ? *reference : PolyMesh{};
    for (Vec3& p : ms.positions) p = ldexp(p, -exponent);
    for (Vec3& p : rs.positions) p = ldexp(p, -exponent);
    QualityReport q = measure_quality(ms, reference ? &rs : nullptr, options);
    q.edge_mean = std::ldexp(q.edge_mean, exponent);
    q.hausdorff_at = ldexp(q.hausdorff_at, exponent);
    q.feature_length = std::ldexp(q.feature_length, exponent);
    return q;
  }
  QualityReport q;
  q.vertices = m.num_vertices();
  q.faces = m.num_faces();
  for (std::size_t f = 0; f < m.num_faces(); ++f) q.non_quads += m.face(f).size() != 4;
  q.pure_quad = q.non_quads == 0 && q.faces > 0;
  std::vector<uint32_t> boundary, valence;
  q.topology =
      topology_of(m, &q.edge_manifold, &q.vertex_manifold, &q.oriented, &boundary, &valence);
  for (uint32_t v = 0; v < m.num_vertices(); ++v) {
    if (valence[v] == 0 || boundary[v]) continue;
    ++q.valence[int(valence[v])];
    q.irregular += valence[v] != 4;
  }

  std::optional<AabbTree> ref_tree;
  if (reference) {
    q.has_reference = true;
    q.reference_topology = topology_of(*reference, nullptr, nullptr, nullptr, nullptr, nullptr);
    q.same_topology = q.reference_topology->euler == q.topology.euler &&
                      q.reference_topology->components == q.topology.components &&
                      q.reference_topology->boundary_loops == q.topology.boundary_loops;
    ref_tree.emplace(fan_triangles(*reference));
  }

  std::vector<FaceShape> shapes(m.num_faces());
  tbb::parallel_for(std::size_t(0), m.num_faces(), [&](std::size_t f) {
    shapes[f] = face_shape(m, f, ref_tree ? &*ref_tree : nullptr);
  });
  summarize_shapes(m, shapes, ref_tree.has_value(), q);
  summarize_quads(m, shapes, q);

  const std::vector<std::array<Vec3, 2>> edges = unique_edges(m);
  std::vector<double> lengths(edges.size());
  for (std::size_t e = 0; e < edges.size(); ++e) lengths[e] = norm(edges[e][1] - edges[e][0]);
  q.edge_mean = mean_of(lengths);
  q.edge_cv = coefficient_of_variation(lengths);
  if (reference) {
    q.feature_angle_deg = options.feature_angle_deg;
    const FeatureCoverage c = feature_coverage(feature_edges(*reference, options.feature_angle_deg),
                                               edges, kFeatureCoverageTolerance * q.edge_mean);
    q.feature_length = c.length;
    q.feature_coverage = c.share();
  }

  // Two-sided distances, over the reference's bounding-box diagonal.
  if (ref_tree) {
    Box3 box;
    for (const Vec3& p : reference->positions) box.add(p);
    const double diag = box.diagonal() > 0 ? box.diagonal() : 1.0;
    const SurfaceDistance d =
        surface_distance(fan_triangles(m), *ref_tree, options.samples, options.seed);
    q.hausdorff = d.max / diag;
    q.hausdorff_on_input = d.on_b;
    q.hausdorff_at = d.at;
    q.mean_distance = d.mean / diag;
  }
  return q;
}

double quad_scaled_jacobian(const std::array<Vec3, 4>& q) {
  return polygon_shape(
             4, [&](std::size_t i) -> const Vec3& { return q[i]; }, nullptr)
      .sj;
}

std::array<double, 4> quad_corner_scaled_jacobians(const std::array<Vec3, 4>& q) {
  const Vec3 n = normalized(newell_vector(4, [&](std::size_t i) -> const Vec3& { return q[i]; }));
  std::array<double, 4> sj;
  for (std::size_t i = 0; i < 4; ++i) {
    const Vec3 e1 = q[(i + 1) % 4] - q[i], e2 = q[(i + 3) % 4] - q[i];
    const double l = norm(e1) * norm(e2);
    sj[i] = l > 0 ? dot(n, cross(e1, e2)) / l : 0.0;
  }
  return sj;
}

double quad_aspect_ratio(const std::array<Vec3, 4>& q) {
  return polygon_shape(
             4, [&](std::size_t i) -> const Vec3& { return q[i]; }, nullptr)
      .aspect;
}

std::vector<double> surface_scaled_jacobians(const PolyMesh& quads, const PolyMesh& reference) {
  const AabbTree tree(fan_triangles(reference));
  std::vector<double> sj(quads.num_faces());
  for (std::size_t f = 0; f < quads.num_faces(); ++f)
    sj[f] = face_shape(quads, f, &tree).sj_surface;
  return sj;
}

}  // namespace isoquad
