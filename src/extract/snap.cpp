#include "extract/snap.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "extract/surface_guard.hpp"
#include "extract/surface_walk.hpp"
#include "metrics/aabb_tree.hpp"
#include "metrics/quality.hpp"

namespace isoquad {

namespace {

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
  std::optional<AabbTree> surface_tree;
  if (!base_tree) surface_tree.emplace(face_triangles(base));
  const AabbTree& surface = base_tree ? *base_tree : *surface_tree;
  SurfaceGuard s(qm, base, surface, far, o.min_sj);
  const Roles roles = snap_roles(qm, meta);
  auto on_meta_edge = [&](uint32_t e, const Vec3& x) {
    for (const uint32_t w : meta.edges[e].vertices)
      if (seams.position(w) == x) return true;
    return false;
  };
  const uint32_t nb = base.num_vertices();
  std::vector<uint32_t> tips;
  for (uint32_t b = 0; b < nb; ++b) {
    report.farthest_before = std::max(report.farthest_before, s.distance(b));
    if (s.distance(b) > far) tips.push_back(b);
  }
  report.tips = uint32_t(tips.size());
  std::sort(tips.begin(), tips.end(), [&](uint32_t a, uint32_t b) {
    return s.distance(a) != s.distance(b) ? s.distance(a) > s.distance(b) : a < b;
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
      SurfaceGuard::Shape shape = s.shape(v);
      std::optional<SurfaceGuard::Local> before;
      const Vec3 p0 = qm.positions[v];
      const uint32_t face0 = qm.surface[v].face;
      bool moved = s.try_move(v, tip, onto, shape, before, true);
      for (const double part : {0.5, 0.25}) {  // not along creases: off them
        if (moved || roles.crease[v] != kInvalid) break;
        moved = s.try_move(v, tip, project_locally(base, face0, p0 + part * (x - p0)), shape,
                           before, true);
      }
      if (!moved) {
        failed[v].push_back(x);
        continue;
      }
      ++report.snapped;
      report.moved.push_back(v);
      for (const uint32_t g : s.quads_at(v))
        for (const uint32_t w : qm.quads[g]) failed[w].clear();
    }
  };
  for (const uint32_t t : tips)
    work_on(s.closest_quad(t), base.position(t), t, [&] { return s.distance(t) <= far; });

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
    report.farthest_after = std::max(report.farthest_after, s.distance(b));
    report.left += s.distance(b) > far;
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace isoquad
