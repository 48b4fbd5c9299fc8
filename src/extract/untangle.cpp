#include "extract/untangle.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <optional>

#include <tbb/parallel_for.h>

#include "extract/collapse.hpp"
#include "extract/surface_walk.hpp"
#include "metrics/aabb_tree.hpp"
#include "metrics/quality.hpp"

namespace isoquad {

namespace {

// A meta-edge's polyline on the surface, by arc length.
struct Polyline {
  std::vector<Vec3> points;
  std::vector<double> at;  // arc length at each point

  double parameter_of(const Vec3& p) const {  // arc length of the closest point
    double best = INFINITY, s = 0;
    for (std::size_t i = 0; i + 1 < points.size(); ++i) {
      const Vec3 d = points[i + 1] - points[i];
      const double l2 = squared_norm(d);
      const double t = l2 > 0 ? std::clamp(dot(p - points[i], d) / l2, 0.0, 1.0) : 0.0;
      const double dist = squared_norm(points[i] + t * d - p);
      if (dist < best) best = dist, s = at[i] + t * (at[i + 1] - at[i]);
    }
    return s;
  }
  Vec3 point_at(double s) const {
    s = std::clamp(s, 0.0, at.back());
    const std::size_t i = std::min<std::size_t>(
        std::upper_bound(at.begin(), at.end(), s) - at.begin(), points.size() - 1);
    if (i == 0) return points[0];
    const double l = at[i] - at[i - 1];
    return l > 0 ? points[i - 1] + ((s - at[i - 1]) / l) * (points[i] - points[i - 1]) : points[i];
  }
};

// A trial place of one vertex: the quads as they would be with vertex `v` at `x`, on the
// surface's face `face`, and every other vertex where it is. Trials of one vertex read the
// mesh but do not write it, so they are judged in parallel.
struct Moved {
  uint32_t v = kInvalid;
  Vec3 x;
  uint32_t face = 0;
};

struct Untangler {
  QuadMesh& qm;
  const TriMesh& base;
  const AabbTree& tree;     // base's faces, in order
  std::vector<char> fixed;  // a pinned meta-vertex, or on a crease or the boundary (those slide)
  std::vector<const Polyline*> slide;  // the crease or boundary a vertex may slide along
  std::vector<Vec3> origin;            // where the map put each vertex
  double reach = 0;                    // how far from there any vertex may go
  double fidelity = 0;                 // how far a singularity's quads may leave that point
  double short_edge = 0;               // edges below this count against a corner

  const Vec3& at(uint32_t w, const Moved& m) const { return w == m.v ? m.x : qm.positions[w]; }
  uint32_t face_of(uint32_t w, const Moved& m) const {
    return w == m.v ? m.face : qm.surface[w].face;
  }

  // Distance from x to the quads around v.
  double distance_to_fan(uint32_t v, const Vec3& x, const Moved& m) const {
    double best = INFINITY;
    for (const uint32_t f : around[v]) {
      const auto& q = qm.quads[f];
      best =
          std::min(best, distance_to_quad({at(q[0], m), at(q[1], m), at(q[2], m), at(q[3], m)}, x));
    }
    return best;
  }
  std::vector<std::vector<uint32_t>> around;  // quads at each vertex
  std::vector<std::vector<uint32_t>> nbr;     // quad-edge neighbours of each vertex

  // The surface normal at corner k of quad q as `isoquad quality` takes it: at the surface
  // point closest to a point just inside the corner (at a vertex on a crease, the side the quad
  // lies on), averaged where that point is on an edge or vertex. With the vertex's own face,
  // the two disagreed near zero; with a walk from it to that point, or with the first of tied
  // triangles, the untangler saw 4 folded quads on the hand at 1,500 quads where the metric saw
  // 5 (a quad corner on a ridge, one side's normal giving +0.56 and the other's -0.62).
  Vec3 corner_normal(const std::array<uint32_t, 4>& q, int k, const Vec3& e1, const Vec3& e2,
                     const Moved& m) const {
    return tree.normal_at_closest(at(q[k], m) + 0.05 * (e1 + e2), face_of(q[k], m));
  }

  // Corner k of quad f against the surface normal: n . (e1 x e2) / (|e1| |e2|), -1 on an edge of
  // length 0.
  double surface_corner_sj(uint32_t f, int k, const Moved& m = {}) const {
    const auto& q = qm.quads[f];
    const Vec3& p = at(q[k], m);
    const Vec3 e1 = at(q[(k + 1) % 4], m) - p, e2 = at(q[(k + 3) % 4], m) - p;
    const double l = norm(e1) * norm(e2);
    return l > 0 ? dot(corner_normal(q, k, e1, e2, m), cross(e1, e2)) / l : -1.0;
  }

  // The scaled Jacobians of quad f's four corners, as the moves judge them: each the lower of
  // its value against the surface normal and against the quad's own (Newell) normal. The
  // surface alone accepts a quad bent across a ridge or a finger with a reflex corner in its own
  // plane, which the output's validity (metrics/quality.hpp kMinValidScaledJacobian) refuses;
  // the own normal alone accepts a quad turned over as a whole. A corner on an edge shorter than
  // `short_edge` counts its positive value scaled down by the edge's share of it, and one on a
  // collapsed edge counts -1: the scaled Jacobian alone does not see edge length, and on fandisk
  // folds were traded for quads with two coincident corners.
  // `known` >= 0 names a corner whose surface value is passed in `known_surface` instead of
  // computed (the corner opposite a moved vertex: its edges and surface normal do not change,
  // but its own-normal value does, with the quad's normal). `m`: a trial place of one vertex.
  std::array<double, 4> corner_sj(uint32_t f, int known = -1, double known_surface = 0,
                                  const Moved& m = {}) const {
    const auto& q = qm.quads[f];
    const std::array<double, 4> own =
        quad_corner_scaled_jacobians({at(q[0], m), at(q[1], m), at(q[2], m), at(q[3], m)});
    std::array<double, 4> sj;
    for (int k = 0; k < 4; ++k) {
      const Vec3& p = at(q[k], m);
      const Vec3 e1 = at(q[(k + 1) % 4], m) - p, e2 = at(q[(k + 3) % 4], m) - p;
      const double shortest = std::min(norm(e1), norm(e2));
      if (!(shortest > 0)) {
        sj[k] = -1;
        continue;
      }
      sj[k] = std::min(k == known ? known_surface : surface_corner_sj(f, k, m), own[k]);
      if (sj[k] > 0 && shortest < short_edge) sj[k] *= shortest / short_edge;
    }
    return sj;
  }
  double quad_sj(uint32_t f) const {
    const auto sj = corner_sj(f);
    return std::min(std::min(sj[0], sj[1]), std::min(sj[2], sj[3]));
  }

  // v's neighbourhood: the squared shortfall of its quads' corners below `cap`. Moving v changes
  // only those corners, so a move that lowers it lowers the sum over the whole mesh: the sweeps
  // descend one energy and end.
  struct Local {
    double shortfall = 0;
  };
  // `opposite` holds, per quad at v, the surface value of its corner opposite v: moving v does
  // not change it (its edges do not end at v), so a trial looks up only three surface normals.
  // It stops once the sum reaches `stop`: terms are not negative, so such a trial cannot be
  // better than one at `stop` (the decisions are the same as with the whole sum).
  Local local_quality(uint32_t v, double cap, const std::vector<std::pair<int, double>>& opposite,
                      double stop = INFINITY, const Moved& m = {}) const {
    Local l;
    for (std::size_t i = 0; i < around[v].size() && l.shortfall < stop; ++i)
      for (const double s : corner_sj(around[v][i], opposite[i].first, opposite[i].second, m))
        if (s < cap) l.shortfall += (cap - s) * (cap - s);
    return l;
  }
  // Better: less shortfall. Requiring also that the worst corner around v not drop (as this did
  // before) left tangles where two corners must trade: 52 folded quads on the corpus at 1,500
  // quads against 39 without it, 108 against 61 at the default size.
  static bool better(const Local& a, const Local& b) { return a.shortfall < b.shortfall - 1e-12; }

  // Moves v to the best of its trial positions in its tangent plane; true if it moved.
  bool improve(uint32_t v, double cap) {
    const Vec3 p0 = qm.positions[v];
    const SurfacePoint s0 = qm.surface[v];
    std::vector<std::pair<int, double>> opposite;
    for (const uint32_t f : around[v]) {
      const auto& q = qm.quads[f];
      const int k = int((std::find(q.begin(), q.end(), v) - q.begin() + 2) % 4);
      opposite.push_back({k, surface_corner_sj(f, k)});
    }
    const Local q0 = local_quality(v, cap, opposite);
    double len = 0;
    Vec3 avg;
    for (const uint32_t w : nbr[v]) {
      len += norm(qm.positions[w] - p0);
      avg += qm.positions[w];
    }
    len /= double(nbr[v].size());
    avg = avg / double(nbr[v].size());
    const Vec3 n = face_normal(base, s0.face);
    // A tangent frame from the normal's smallest component (deterministic).
    const Vec3 axis = std::fabs(n.x) <= std::fabs(n.y) && std::fabs(n.x) <= std::fabs(n.z)
                          ? Vec3{1, 0, 0}
                          : (std::fabs(n.y) <= std::fabs(n.z) ? Vec3{0, 1, 0} : Vec3{0, 0, 1});
    const Vec3 t1 = normalized(cross(n, axis)), t2 = cross(n, t1);
    // Steps scale with the local edge length, but never beyond the reach: along a stretched
    // quad they would carry a vertex far from where the map put it.
    len = std::min(len, reach);
    std::vector<Vec3> points;
    if (const Polyline* line = slide[v]) {
      const double s = line->parameter_of(p0);
      for (const double step : {0.4, 0.2, 0.1, 0.05})
        for (const double sign : {-1.0, 1.0})
          points.push_back(line->point_at(s + sign * step * len));
    } else {
      points.push_back(avg);
      for (const double step : {0.8, 0.4, 0.2, 0.1, 0.05})
        for (int k = 0; k < 8; ++k) {
          const double a = k * std::numbers::pi / 4;
          points.push_back(p0 + (step * len) * (std::cos(a) * t1 + std::sin(a) * t2));
        }
    }
    // A singularity or crease vertex must keep covering the surface point the map chose: it may
    // glide along the surface, not cut off a tip (a horn, a finger) it stood on.
    const bool guarded =
        qm.vertex_meta_vertex[v] != kInvalid || slide[v] || (v < qm.merged.size() && qm.merged[v]);
    struct Trial {
      bool ok = false;
      SurfacePoint s;
      Vec3 x;
      Local q;
    };
    std::vector<Trial> trials(points.size());
    // Each trial's shortfall is summed until it passes q0's; taken in order below, the first
    // best trial wins, as when they were tried one by one (a trial cut short there was cut
    // short because it could not win; here it is cut short later or not at all, with the same
    // partial sums).
    const double stop = q0.shortfall - 1e-12;
    tbb::parallel_for(std::size_t(0), points.size(), [&](std::size_t i) {
      const SurfacePoint s = project_locally(base, s0.face, points[i]);
      const Vec3 x = position_of(base, s);
      if (squared_norm(x - origin[v]) > reach * reach) return;
      const Moved m{v, x, s.face};
      if (guarded && !(distance_to_fan(v, origin[v], m) <= fidelity)) return;
      trials[i] = {true, s, x, local_quality(v, cap, opposite, stop, m)};
    });
    Local best_q = q0;
    SurfacePoint best = s0;
    Vec3 best_p = p0;
    for (const Trial& t : trials)
      if (t.ok && better(t.q, best_q)) best_q = t.q, best = t.s, best_p = t.x;
    qm.positions[v] = best_p;
    qm.surface[v] = best;
    return better(best_q, q0);
  }
};

// Which vertices stay and which slide: meta-vertices where a crease or the mesh boundary meets
// stay; the others are singularities of the quad mesh whose exact place on the surface is free.
// Vertices on a crease or the boundary slide along its polyline (one per meta-edge, in `lines`).
struct Roles {
  std::vector<char> fixed;
  std::vector<const Polyline*> slide;
  std::vector<Polyline> lines;
};

Roles vertex_roles(const QuadMesh& qm, const TriMesh& seams, const MetaMesh& meta,
                   const UntangleOptions& o) {
  const uint32_t n = uint32_t(qm.positions.size());
  Roles r{std::vector<char>(n, 0), std::vector<const Polyline*>(n, nullptr),
          std::vector<Polyline>(meta.edges.size())};
  std::vector<char> pinned(meta.vertices.size(), 0);
  for (uint32_t m = 0; m < meta.vertices.size(); ++m) pinned[m] = meta.vertices[m].on_boundary;
  for (const MetaEdge& e : meta.edges)
    if (e.feature || e.right == kInvalid) pinned[e.mv0] = pinned[e.mv1] = 1;
  for (uint32_t v = 0; v < n; ++v) {
    const uint32_t e = qm.vertex_meta_edge[v];
    const bool crease = e != kInvalid && (meta.edges[e].feature || meta.edges[e].right == kInvalid);
    const uint32_t m = qm.vertex_meta_vertex[v];
    r.fixed[v] = (m != kInvalid && (pinned[m] || !o.move_singularities)) || crease;
    if (!crease || m != kInvalid || !o.slide) continue;
    Polyline& line = r.lines[e];
    if (line.points.empty())
      for (const uint32_t w : meta.edges[e].vertices) {
        line.at.push_back(line.points.empty()
                              ? 0.0
                              : line.at.back() + norm(seams.position(w) - line.points.back()));
        line.points.push_back(seams.position(w));
      }
    r.slide[v] = &line;
  }
  return r;
}

// The untangling sweeps; `worst` gets the lowest corner of each quad left folded.
void untangle_sweeps(QuadMesh& qm, const TriMesh& base, const AabbTree& tree, const TriMesh& seams,
                     const MetaMesh& meta, const UntangleOptions& o, UntangleReport& report,
                     std::vector<int>& worst) {
  // With collapses to follow, degenerate quads count as folded too (kFoldedAtOrBelow).
  const double folded_at = o.collapse_rounds > 0 ? kFoldedAtOrBelow : 0.0;
  const uint32_t n = uint32_t(qm.positions.size());
  Roles roles = vertex_roles(qm, seams, meta, o);
  Untangler u{qm,
              base,
              tree,
              std::move(roles.fixed),
              std::move(roles.slide),
              qm.mapped,
              o.reach * o.edge_length,
              o.fidelity * o.edge_length,
              o.short_edge * o.edge_length,
              std::vector<std::vector<uint32_t>>(n),
              std::vector<std::vector<uint32_t>>(n)};
  for (uint32_t f = 0; f < qm.quads.size(); ++f)
    for (int i = 0; i < 4; ++i) {
      const uint32_t a = qm.quads[f][i], b = qm.quads[f][(i + 1) % 4];
      u.nbr[a].push_back(b);
      u.nbr[b].push_back(a);
      u.around[a].push_back(f);
    }
  for (auto& l : u.nbr) {
    std::sort(l.begin(), l.end());
    l.erase(std::unique(l.begin(), l.end()), l.end());
  }
  std::vector<double> sj(qm.quads.size());
  auto measure = [&](uint32_t& folded, double& worst) {
    folded = 0;
    worst = 1;
    tbb::parallel_for(std::size_t(0), sj.size(), [&](std::size_t f) { sj[f] = u.quad_sj(f); });
    for (uint32_t f = 0; f < sj.size(); ++f) {
      folded += sj[f] <= folded_at;
      worst = std::min(worst, sj[f]);
    }
  };
  measure(report.folded_before, report.min_before);
  // Move clock: when each vertex last moved, and when its last attempt found nothing (0: never).
  uint64_t clock = 0, round_start = 0;
  std::vector<uint64_t> moved_at(n, 0), failed_at(n, 0);
  for (uint32_t round = 0; round < o.max_rounds; ++round) {
    std::vector<uint32_t> active;
    for (uint32_t f = 0; f < sj.size(); ++f)
      if (sj[f] < o.target)
        for (const uint32_t v : qm.quads[f])
          if (!u.fixed[v] || u.slide[v]) active.push_back(v);
    std::sort(active.begin(), active.end());
    active.erase(std::unique(active.begin(), active.end()), active.end());
    if (active.empty()) break;
    ++report.rounds;
    uint32_t moved = 0;
    for (const uint32_t v : active) {
      // A move depends only on the quads around v: if none of their corners moved since v
      // last found no better place, it would find none again.
      if (failed_at[v] > 0) {
        bool changed = false;
        for (const uint32_t f : u.around[v])
          for (const uint32_t w : qm.quads[f]) changed |= moved_at[w] > failed_at[v];
        if (!changed) continue;
      }
      ++clock;
      if (u.improve(v, o.target)) {
        ++moved;
        moved_at[v] = clock;
        failed_at[v] = 0;
      } else {
        failed_at[v] = clock;
      }
    }
    report.moves += moved;
    std::vector<uint32_t> touched;
    for (const uint32_t v : active)
      for (const uint32_t f : u.around[v])
        if (std::any_of(qm.quads[f].begin(), qm.quads[f].end(),
                        [&](uint32_t w) { return moved_at[w] > round_start; }))
          touched.push_back(f);
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    tbb::parallel_for(std::size_t(0), touched.size(),
                      [&](std::size_t i) { sj[touched[i]] = u.quad_sj(touched[i]); });
    round_start = clock;
    if (moved == 0) break;
  }
  measure(report.folded_after, report.min_after);
  report.folded.clear();
  worst.clear();
  report.nonpositive = report.degenerate = 0;
  for (uint32_t f = 0; f < sj.size(); ++f) {
    report.nonpositive += sj[f] <= 0;
    report.degenerate += sj[f] <= kFoldedAtOrBelow;
  }
  for (uint32_t f = 0; f < sj.size(); ++f)
    if (sj[f] <= folded_at) {
      report.folded.push_back(f);
      const auto c = u.corner_sj(f);
      worst.push_back(int(std::min_element(c.begin(), c.end()) - c.begin()));
    }
}

// Replaces quad f by five: a quad inside it and four between the two. Corner k, whose vertex
// is pinned to a crease or the boundary with an angle near 180 degrees, then has two quads on
// that side; its inner corner starts nearer to it than the others so that the inner quad does
// not copy that angle. The new vertices are on the surface (walked to from the opposite
// corner's face) and free.
void split_quad_in_five(QuadMesh& qm, const TriMesh& base, uint32_t f, int k) {
  const std::array<uint32_t, 4> q = qm.quads[f];
  Vec3 c;
  for (const uint32_t v : q) c += qm.positions[v];
  c = c / 4.0;
  const uint32_t start = qm.surface[q[(k + 2) % 4]].face;
  std::array<uint32_t, 4> inner{};
  for (int i = 0; i < 4; ++i) {
    const double t = i == k ? 0.7 : 0.5;
    const SurfacePoint s = project_locally(base, start, c + t * (qm.positions[q[i]] - c));
    inner[i] = uint32_t(qm.positions.size());
    qm.positions.push_back(position_of(base, s));
    qm.surface.push_back(s);
    qm.vertex_meta_vertex.push_back(kInvalid);
    qm.vertex_meta_edge.push_back(kInvalid);
    qm.placed.push_back(QuadMesh::Placed::direct);
    if (!qm.mapped.empty()) qm.mapped.push_back(qm.positions.back());
    if (!qm.merged.empty()) qm.merged.push_back(0);
  }
  qm.quads[f] = inner;
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 1) % 4;
    qm.quads.push_back({q[i], q[j], inner[j], inner[i]});
    qm.quad_patch.push_back(qm.quad_patch[f]);
  }
}

// Folds left where a quad opens to about 180 degrees at a vertex pinned to a crease or the
// boundary (a patch corner on a straight crease) and no diagonal collapse could remove it: the
// quad is split in five, so that the vertex has two quads on that side, and swept again; kept
// if fewer quads fold.
void split_crease_corners(QuadMesh& qm, const TriMesh& base, const AabbTree& tree,
                          const TriMesh& seams, const MetaMesh& meta, const UntangleOptions& o,
                          UntangleReport& report) {
  const Roles roles = vertex_roles(qm, seams, meta, o);
  QuadMesh trial = qm;
  uint32_t split = 0;
  for (const uint32_t f : report.folded) {
    const auto& q = qm.quads[f];
    int k = -1;
    double widest = 0;
    for (int i = 0; i < 4; ++i) {
      if (!roles.fixed[q[i]] && !roles.slide[q[i]]) continue;
      const Vec3 a = qm.positions[q[(i + 1) % 4]] - qm.positions[q[i]];
      const Vec3 b = qm.positions[q[(i + 3) % 4]] - qm.positions[q[i]];
      const double angle = angle_between(a, b);
      if (angle > widest) widest = angle, k = i;
    }
    if (k < 0 || widest < 150.0 * std::numbers::pi / 180.0) continue;
    split_quad_in_five(trial, base, f, k);
    ++split;
  }
  if (split == 0) return;
  UntangleReport again;
  std::vector<int> worst;
  untangle_sweeps(trial, base, tree, seams, meta, o, again, worst);
  if (!(fold_score(again) < fold_score(report))) return;
  qm = std::move(trial);
  report.folded_after = again.folded_after;
  report.min_after = again.min_after;
  report.folded = std::move(again.folded);
  report.nonpositive = again.nonpositive;
  report.degenerate = again.degenerate;
  report.rounds += again.rounds;
  report.moves += again.moves;
  report.split = split;
}

}  // namespace

void untangle_quads(QuadMesh& qm, const TriMesh& base, const TriMesh& seams, const MetaMesh& meta,
                    const UntangleOptions& o, UntangleReport& report, const AabbTree* base_tree) {
  const auto t0 = std::chrono::steady_clock::now();
  std::optional<AabbTree> own;
  if (!base_tree) own.emplace(face_triangles(base));
  const AabbTree& tree = base_tree ? *base_tree : *own;
  if (qm.mapped.size() != qm.positions.size()) qm.mapped = qm.positions;
  std::vector<int> worst;
  untangle_sweeps(qm, base, tree, seams, meta, o, report, worst);
  // Folds the sweeps could not move: collapse a diagonal of each folded quad and sweep again.
  // A collapse can pass a fold to a neighbour, which the next round removes (fandisk at 1,500
  // quads: 1 -> 1 -> 0; rotor 3 -> 4 -> ...), so every round runs; the best mesh seen (fewest
  // folds, then the highest lowest corner) is kept.
  auto score = [](const UntangleReport& r) { return std::pair(fold_score(r), -r.min_after); };
  QuadMesh best = qm;
  UntangleReport best_report = report;
  for (uint32_t round = 0; round < o.collapse_rounds && !report.folded.empty(); ++round) {
    std::vector<CollapseRequest> requests;
    for (std::size_t i = 0; i < report.folded.size(); ++i)
      requests.push_back({report.folded[i], worst[i]});
    std::vector<char> movable = vertex_roles(qm, seams, meta, o).fixed;
    for (char& m : movable) m = !m;
    CollapseReport cr;
    const QuadMesh before = qm;
    collapse_diagonals(qm, movable, requests, o.collapse_offset * o.edge_length, cr);
    if (cr.collapsed == 0) break;
    // The collapse keeps the mesh manifold by construction; this check guards it.
    bool em = false, vm = false, ori = false;
    const Topology now = topology_of(as_poly(qm), &em, &vm, &ori, nullptr, nullptr);
    const Topology was = topology_of(as_poly(before), nullptr, nullptr, nullptr, nullptr, nullptr);
    if (!(em && vm && ori && now.euler == was.euler && now.components == was.components &&
          now.boundary_loops == was.boundary_loops))
      break;
    UntangleReport again;
    std::vector<int> worst_again;
    untangle_sweeps(qm, base, tree, seams, meta, o, again, worst_again);
    report.folded_after = again.folded_after;
    report.min_after = again.min_after;
    report.folded = std::move(again.folded);
    report.nonpositive = again.nonpositive;
    report.degenerate = again.degenerate;
    worst = std::move(worst_again);
    report.rounds += again.rounds;
    report.moves += again.moves;
    report.collapsed += cr.collapsed;
    report.doublets += cr.doublets;
    report.refused = cr.refused;
    if (score(report) < score(best_report)) {
      best = qm;
      best_report = report;
    }
  }
  // The rounds after the best one are undone but their work is counted.
  best_report.rounds = report.rounds;
  best_report.moves = report.moves;
  qm = std::move(best);
  report = std::move(best_report);
  if (o.split_crease_corners && o.collapse_rounds > 0 && !report.folded.empty())
    split_crease_corners(qm, base, tree, seams, meta, o, report);
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace isoquad
