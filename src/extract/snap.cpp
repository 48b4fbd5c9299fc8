#include "extract/snap.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include "extract/surface_walk.hpp"
#include "metrics/aabb_tree.hpp"
#include "metrics/quality.hpp"

namespace isoquad {

namespace {

// How far the scaled Jacobian against the corners' own face normals may fall below the bound
// before a move is rejected without the exact value: a prefilter (no search), since most
// rejected moves fold a quad outright. The two differ where a corner's face is not the one just
// inside the quad (at a crease, across a triangle edge).
constexpr double kRoughMargin = 0.5;

struct Snapper {
  QuadMesh& qm;
  const TriMesh& base;
  const AabbTree& surface;  // base's faces: normals, and distances from the quads
  double tolerance = 0;     // far: what a move may leave any surface vertex at
  double min_sj = 0;
  std::vector<std::vector<uint32_t>> around;  // quads at each corner
  // Per surface vertex: the quad it is closest to (among the quads near it) and the distance.
  std::vector<uint32_t> closest;
  std::vector<double> distance;
  std::vector<std::vector<uint32_t>> assigned;  // per quad: the surface vertices closest to it

  double quad_distance(uint32_t f, const Vec3& x) const {
    const auto& q = qm.quads[f];
    const auto& p = qm.positions;
    return std::min(norm(closest_point_on_triangle(x, p[q[0]], p[q[1]], p[q[2]]) - x),
                    norm(closest_point_on_triangle(x, p[q[0]], p[q[2]], p[q[3]]) - x));
  }
  Box3 quad_box(uint32_t f) const {
    Box3 b;
    for (const uint32_t w : qm.quads[f]) b.add(qm.positions[w]);
    return b;
  }
  static double box_distance(const Box3& b, const Vec3& x) {
    double d2 = 0;
    for (int i = 0; i < 3; ++i) {
      const double d = std::max({b.lo[i] - x[i], 0.0, x[i] - b.hi[i]});
      d2 += d * d;
    }
    return std::sqrt(d2);
  }
  // Lowers dist[i] (and sets near[i]) where quad f is closer to verts[i].
  void closer(uint32_t f, const std::vector<uint32_t>& verts, std::vector<double>& dist,
              std::vector<uint32_t>& near) const {
    const Box3 box = quad_box(f);
    for (std::size_t i = 0; i < verts.size(); ++i) {
      const Vec3& x = base.position(verts[i]);
      if (box_distance(box, x) >= dist[i]) continue;
      const double d = quad_distance(f, x);
      if (d < dist[i]) dist[i] = d, near[i] = f;
    }
  }

  // Every surface vertex's closest quad, from scratch.
  // The queries are independent (in parallel); the lists are filled in vertex order.
  void assign_surface_vertices(const AabbTree& quads) {
    const uint32_t nb = base.num_vertices();
    closest.resize(nb);
    distance.resize(nb);
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, nb, 1024), [&](const auto& r) {
      for (uint32_t b = r.begin(); b < r.end(); ++b) {
        const AabbTree::Hit hit = quads.closest(base.position(b));
        closest[b] = hit.triangle / 2;
        distance[b] = hit.distance;
      }
    });
    assigned.assign(qm.quads.size(), {});
    for (uint32_t b = 0; b < nb; ++b) assigned[closest[b]].push_back(b);
  }

  // The smallest scaled Jacobian of quad f's corners against the surface normal just inside
  // each corner (as `isoquad quality` takes it); with `rough`, against the normal of the face
  // each corner is on (kRoughMargin).
  double surface_sj(uint32_t f, bool rough = false) const {
    return quad_corner_sj(qm, f, [&](uint32_t v, const Vec3& inside) {
      return rough ? face_normal(base, qm.surface[v].face)
                   : surface.normal_at_closest(inside, qm.surface[v].face);
    });
  }

  // What moving v changes: its quads (`changed`: sample points checked) and the distances of
  // the surface vertices closest to one of them, which the move may take farther (`verts`, with
  // the tip being worked on: other vertices can only come closer). `others` is each such
  // vertex's distance to the quads next to the changed ones, which do not move.
  struct Local {
    uint32_t v = kInvalid;
    Vec3 position;
    SurfacePoint surface;
    std::vector<uint32_t> changed, verts;
    std::vector<uint32_t> near;  // per entry of verts: its closest quad of those measured
    std::vector<double> dist, others;
    std::vector<uint32_t> others_near;
    double samples = 0;  // largest distance of the samples on the changed quads to the surface
    double worst() const {
      double w = samples;
      for (const double d : dist) w = std::max(w, d);
      return w;
    }
  };
  Local local(uint32_t v, uint32_t tip) const {
    Local l;
    l.v = v;
    l.position = qm.positions[v];
    l.surface = qm.surface[v];
    l.changed = around[v];
    std::vector<uint32_t> ring;
    for (const uint32_t f : l.changed) {
      for (const uint32_t w : qm.quads[f])
        ring.insert(ring.end(), around[w].begin(), around[w].end());
      l.verts.insert(l.verts.end(), assigned[f].begin(), assigned[f].end());
    }
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    if (tip != kInvalid) l.verts.push_back(tip);
    std::sort(l.verts.begin(), l.verts.end());
    l.verts.erase(std::unique(l.verts.begin(), l.verts.end()), l.verts.end());
    // A vertex closest to a quad that stays keeps that distance at most.
    l.others.assign(l.verts.size(), INFINITY);
    l.others_near.assign(l.verts.size(), kInvalid);
    for (std::size_t i = 0; i < l.verts.size(); ++i)
      if (std::find(l.changed.begin(), l.changed.end(), closest[l.verts[i]]) == l.changed.end()) {
        l.others[i] = distance[l.verts[i]];
        l.others_near[i] = closest[l.verts[i]];
      }
    for (const uint32_t f : ring)
      if (std::find(l.changed.begin(), l.changed.end(), f) == l.changed.end())
        closer(f, l.verts, l.others, l.others_near);
    return l;
  }
  void measure_vertices(Local& l) const {
    l.near = l.others_near;
    l.dist = l.others;
    for (const uint32_t f : l.changed) closer(f, l.verts, l.dist, l.near);
  }
  void measure_samples(Local& l) const {
    l.samples = 0;
    for (const uint32_t f : l.changed) {
      const auto& q = qm.quads[f];
      const auto& p = qm.positions;
      // A grid of step 1/3 on each of the quad's two triangles, as the metric sees the quad.
      for (const auto& [a, b, c] : {std::array<uint32_t, 3>{q[0], q[1], q[2]}, {q[0], q[2], q[3]}})
        for (int i = 0; i <= 3; ++i)
          for (int j = 0; i + j <= 3; ++j) {
            if (i == 3 || j == 3 || i + j == 0) continue;  // the corners are on the surface
            const Vec3 x = (i * p[a] + j * p[b] + (3 - i - j) * p[c]) / 3.0;
            l.samples = std::max(l.samples, surface.closest(x).distance);
          }
    }
  }

  // Quad f's scaled Jacobian against its own (Newell) normal, as `isoquad quality` counts it.
  double own_sj(uint32_t f) const {
    const auto& q = qm.quads[f];
    const auto& p = qm.positions;
    return quad_scaled_jacobian({p[q[0]], p[q[1]], p[q[2]], p[q[3]]});
  }

  // v's quads' scaled Jacobians before its move: against their own normals, against the
  // corners' face normals (`rough`) and, measured on first use, against the surface.
  struct Shape {
    std::vector<double> own, rough;
    std::optional<std::vector<double>> exact;
  };

  // Moves v to s if that is better (see snap.hpp); true if it did. The quads' shape is checked
  // first: it is cheap and fails most often. `before` is v's neighbourhood as it is, measured
  // on first use.
  bool try_move(uint32_t v, uint32_t tip, const SurfacePoint& s, Shape& shape,
                std::optional<Local>& before) {
    const Vec3 old_p = qm.positions[v];
    const SurfacePoint old_s = qm.surface[v];
    auto place = [&](const Vec3& p, const SurfacePoint& sp) {
      qm.positions[v] = p;
      qm.surface[v] = sp;
    };
    place(position_of(base, s), s);
    bool ok = true;
    for (std::size_t i = 0; ok && i < around[v].size(); ++i)
      ok = surface_sj(around[v][i], true) >= std::min(shape.rough[i], min_sj) - kRoughMargin &&
           own_sj(around[v][i]) >= std::min(shape.own[i], min_sj);
    if (ok && !shape.exact) {
      place(old_p, old_s);
      shape.exact.emplace();
      for (const uint32_t f : around[v]) shape.exact->push_back(surface_sj(f));
      place(position_of(base, s), s);
    }
    for (std::size_t i = 0; ok && i < around[v].size(); ++i)
      ok = surface_sj(around[v][i]) >= std::min((*shape.exact)[i], min_sj);
    Local after;
    if (ok) {
      if (!before) {
        place(old_p, old_s);
        before = local(v, tip);
        measure_vertices(*before);
        measure_samples(*before);
        place(position_of(base, s), s);
      }
      after = *before;
      measure_vertices(after);
      for (std::size_t i = 0; ok && i < before->verts.size(); ++i)
        ok = after.dist[i] <= std::max(before->dist[i], tolerance);
      if (ok) {
        measure_samples(after);
        ok = after.samples <= std::max(before->samples, tolerance) &&
             after.worst() < before->worst() * (1 - 1e-6);
      }
    }
    if (!ok) {
      place(old_p, old_s);
      return false;
    }
    for (std::size_t i = 0; i < after.verts.size(); ++i) {
      const uint32_t b = after.verts[i];
      if (after.near[i] != closest[b]) {
        auto& from = assigned[closest[b]];
        from.erase(std::find(from.begin(), from.end(), b));
        assigned[after.near[i]].push_back(b);
        closest[b] = after.near[i];
      }
      distance[b] = after.dist[i];
    }
    return true;
  }
};

// Meta-vertices where creases or the boundary meet stay (`fixed`); crease and boundary vertices
// move only along their meta-edge (`crease`), onto one of its own vertices.
struct Roles {
  std::vector<char> fixed;
  std::vector<uint32_t> crease;
};
Roles snap_roles(const QuadMesh& qm, const MetaMesh& meta) {
  std::vector<char> pinned(meta.vertices.size(), 0);
  for (uint32_t m = 0; m < meta.vertices.size(); ++m) pinned[m] = meta.vertices[m].on_boundary;
  for (const MetaEdge& e : meta.edges)
    if (e.feature || e.right == kInvalid) pinned[e.mv0] = pinned[e.mv1] = 1;
  const std::size_t n = qm.positions.size();
  Roles r{std::vector<char>(n, 0), std::vector<uint32_t>(n, kInvalid)};
  for (uint32_t v = 0; v < n; ++v) {
    const uint32_t m = qm.vertex_meta_vertex[v], e = qm.vertex_meta_edge[v];
    r.fixed[v] = m != kInvalid && pinned[m];
    if (m == kInvalid && e != kInvalid &&
        (meta.edges[e].feature || meta.edges[e].right == kInvalid))
      r.crease[v] = e;
  }
  return r;
}

}  // namespace

void snap_tips(QuadMesh& qm, const TriMesh& base, const TriMesh& seams, const MetaMesh& meta,
               const SnapOptions& o, SnapReport& report, const AabbTree* base_tree) {
  const auto t0 = std::chrono::steady_clock::now();
  report = {};
  const uint32_t n = uint32_t(qm.positions.size());
  const double h = o.edge_length, far = o.far * h;
  std::optional<AabbTree> surface_tree, quad_tree;
  tbb::parallel_invoke(
      [&] {
        if (!base_tree) surface_tree.emplace(face_triangles(base));
      },
      [&] { quad_tree.emplace(fan_triangles(qm)); });
  const AabbTree& surface = base_tree ? *base_tree : *surface_tree;
  Snapper s{qm, base, surface, far, o.min_sj, {}, {}, {}, {}};
  s.around.resize(n);
  for (uint32_t f = 0; f < qm.quads.size(); ++f)
    for (const uint32_t v : qm.quads[f]) s.around[v].push_back(f);
  s.assign_surface_vertices(*quad_tree);
  quad_tree.reset();
  const Roles roles = snap_roles(qm, meta);
  auto on_meta_edge = [&](uint32_t e, const Vec3& x) {
    for (const uint32_t w : meta.edges[e].vertices)
      if (seams.position(w) == x) return true;
    return false;
  };
  const uint32_t nb = base.num_vertices();
  std::vector<uint32_t> tips;
  for (uint32_t b = 0; b < nb; ++b) {
    report.farthest_before = std::max(report.farthest_before, s.distance[b]);
    if (s.distance[b] > far) tips.push_back(b);
  }
  report.tips = uint32_t(tips.size());
  std::sort(tips.begin(), tips.end(), [&](uint32_t a, uint32_t b) {
    return s.distance[a] != s.distance[b] ? s.distance[a] > s.distance[b] : a < b;
  });

  // Moves a corner of quad f towards x (onto it, else half or a quarter of the way), the
  // nearest corner first, until `done`. A corner that could not move towards a point this close
  // since its quads last changed is not tried again (on a protrusion nothing can reach, every
  // vertex below its tip would try the same moves).
  std::vector<std::vector<Vec3>> failed(n);
  auto work_on = [&](uint32_t f, const Vec3& x, uint32_t tip, auto&& done) {
    std::array<uint32_t, 4> cand = qm.quads[f];
    std::stable_sort(cand.begin(), cand.end(), [&](uint32_t a, uint32_t b) {
      return norm(qm.positions[a] - x) < norm(qm.positions[b] - x);
    });
    for (const uint32_t v : cand) {
      if (done()) return;
      if (roles.fixed[v] || norm(qm.positions[v] - x) > o.reach * h ||
          (roles.crease[v] != kInvalid && !on_meta_edge(roles.crease[v], x)) ||
          std::any_of(failed[v].begin(), failed[v].end(),
                      [&](const Vec3& y) { return norm(y - x) < far; }))
        continue;
      const SurfacePoint onto = project_locally(base, qm.surface[v].face, x);
      if (norm(position_of(base, onto) - x) > 1e-9 * h) continue;  // not reached over the surface
      Snapper::Shape shape;
      for (const uint32_t g : s.around[v]) {
        shape.rough.push_back(s.surface_sj(g, true));
        shape.own.push_back(s.own_sj(g));
      }
      std::optional<Snapper::Local> before;
      const Vec3 p0 = qm.positions[v];
      const uint32_t face0 = qm.surface[v].face;
      bool moved = s.try_move(v, tip, onto, shape, before);
      for (const double part : {0.5, 0.25}) {  // not along creases: off them
        if (moved || roles.crease[v] != kInvalid) break;
        moved =
            s.try_move(v, tip, project_locally(base, face0, p0 + part * (x - p0)), shape, before);
      }
      if (!moved) {
        failed[v].push_back(x);
        continue;
      }
      ++report.snapped;
      for (const uint32_t g : s.around[v])
        for (const uint32_t w : qm.quads[g]) failed[w].clear();
    }
  };
  for (const uint32_t t : tips)
    work_on(s.closest[t], base.position(t), t, [&] { return s.distance[t] <= far; });

  // Then quads far from the surface inside (across a saddle, over a groove): a corner moves
  // towards the surface point closest to the farther of the quad's two triangle centroids.
  auto centroid_gap = [&](uint32_t f, Vec3& target) {
    const auto& q = qm.quads[f];
    const auto& p = qm.positions;
    double gap = 0;
    for (const Vec3& c :
         {(p[q[0]] + p[q[1]] + p[q[2]]) / 3.0, (p[q[0]] + p[q[2]] + p[q[3]]) / 3.0}) {
      const AabbTree::Hit hit = surface.closest(c);
      if (hit.distance > gap) gap = hit.distance, target = hit.point;
    }
    return gap;
  };
  std::vector<double> gap_of(qm.quads.size());
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, uint32_t(qm.quads.size()), 256),
                    [&](const auto& r) {
                      Vec3 target;
                      for (uint32_t f = r.begin(); f < r.end(); ++f)
                        gap_of[f] = centroid_gap(f, target);
                    });
  std::vector<std::pair<double, uint32_t>> gaps;
  for (uint32_t f = 0; f < qm.quads.size(); ++f)
    if (gap_of[f] > far) gaps.push_back({-gap_of[f], f});
  std::sort(gaps.begin(), gaps.end());
  report.gaps = uint32_t(gaps.size());
  for (const auto& [gap, f] : gaps) {
    Vec3 target;
    if (centroid_gap(f, target) <= far) continue;
    const uint32_t snapped = report.snapped;
    work_on(f, target, kInvalid, [&] { return report.snapped > snapped; });
  }

  for (uint32_t b = 0; b < nb; ++b) {
    report.farthest_after = std::max(report.farthest_after, s.distance[b]);
    report.left += s.distance[b] > far;
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace isoquad
