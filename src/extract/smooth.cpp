#include "extract/smooth.hpp"

#include <algorithm>
#include <chrono>
#include <optional>

#include "extract/surface_guard.hpp"
#include "extract/surface_walk.hpp"

namespace isoquad {

void smooth_quads(QuadMesh& qm, const TriMesh& base, const MetaMesh& meta, const SmoothOptions& o,
                  SmoothReport& report, const AabbTree* surface_tree,
                  const std::vector<uint32_t>& pinned) {
  const auto t0 = std::chrono::steady_clock::now();
  report = {};
  if (o.iterations == 0 || qm.quads.empty()) return;
  std::optional<AabbTree> own_tree;
  if (!surface_tree) own_tree.emplace(face_triangles(base));
  SurfaceGuard guard(qm, base, surface_tree ? *surface_tree : *own_tree, o.far * o.edge_length,
                     o.min_sj);
  const uint32_t n = uint32_t(qm.positions.size());
  // Held: meta-vertices on the boundary or at an end of a crease or boundary meta-edge, and
  // the vertices along such meta-edges. Other meta-vertices (the field's singularities, the
  // layout's junctions) move like any vertex: nothing but the map put them where they are.
  std::vector<char> held(meta.vertices.size(), 0);
  for (uint32_t m = 0; m < meta.vertices.size(); ++m) held[m] = meta.vertices[m].on_boundary;
  for (const MetaEdge& e : meta.edges)
    if (e.feature || e.right == kInvalid) held[e.mv0] = held[e.mv1] = 1;
  std::vector<char> fixed(n, 0);
  for (uint32_t v = 0; v < n; ++v) {
    const uint32_t m = qm.vertex_meta_vertex[v], e = qm.vertex_meta_edge[v];
    fixed[v] = m != kInvalid
                   ? held[m]
                   : e != kInvalid && (meta.edges[e].feature || meta.edges[e].right == kInvalid);
  }
  for (const uint32_t v : pinned) fixed.at(v) = 1;
  std::vector<std::vector<uint32_t>> nbr(n);
  for (const auto& q : qm.quads)
    for (int i = 0; i < 4; ++i) {
      nbr[q[i]].push_back(q[(i + 1) % 4]);
      nbr[q[(i + 1) % 4]].push_back(q[i]);
    }
  for (auto& l : nbr) {
    std::sort(l.begin(), l.end());
    l.erase(std::unique(l.begin(), l.end()), l.end());
  }
  for (uint32_t it = 0; it < o.iterations; ++it) {
    ++report.iterations;
    for (uint32_t v = 0; v < n; ++v) {
      if (fixed[v] || nbr[v].empty()) continue;
      Vec3 avg;
      for (const uint32_t w : nbr[v]) avg += qm.positions[w];
      avg = avg / double(nbr[v].size());
      SurfaceGuard::Shape shape = guard.shape(v);
      std::optional<SurfaceGuard::Local> before;
      const SurfacePoint to = project_locally(base, qm.surface[v].face, avg);
      if (guard.try_move(v, kInvalid, to, shape, before, false))
        ++report.moves;
      else
        ++report.rejected;
    }
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace isoquad
