#include "metrics/feature_coverage.hpp"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "metrics/aabb_tree.hpp"
#include "prep/prepare.hpp"

namespace isoquad {

std::vector<std::array<Vec3, 2>> feature_edges(const PolyMesh& mesh, double feature_angle_deg) {
  std::vector<std::array<Vec3, 2>> out;
  if (feature_angle_deg <= 0 || mesh.num_faces() == 0) return out;
  PrepOptions o;
  o.feature_angle_deg = feature_angle_deg;
  o.diagnose = true;  // measure what can be prepared; what remesh would refuse has no features
  const PreparedMesh prep = prepare(mesh, o);
  for (const PreparedComponent& c : prep.components)
    for (uint32_t e = 0; e < c.mesh.num_edges(); ++e) {
      if (!c.feature[e]) continue;
      const uint32_t h = c.mesh.edge_halfedge(e);
      // The input's own points (welding moved none, without --weld-eps), not the normalized ones
      // mapped back.
      out.push_back({mesh.positions[c.input_vertex[c.mesh.from(h)]],
                     mesh.positions[c.input_vertex[c.mesh.to(h)]]});
    }
  return out;
}

FeatureCoverage feature_coverage(const std::vector<std::array<Vec3, 2>>& features,
                                 const std::vector<std::array<Vec3, 2>>& edges, double tolerance) {
  FeatureCoverage c;
  for (const auto& f : features) c.length += norm(f[1] - f[0]);
  if (features.empty() || edges.empty() || !(c.length > 0)) return c;
  // Segments as triangles with a repeated corner: the closest point on (a, b, b) is the closest
  // point on ab.
  std::vector<std::array<Vec3, 3>> segments;
  segments.reserve(edges.size());
  for (const auto& e : edges) segments.push_back({e[0], e[1], e[1]});
  const AabbTree tree(std::move(segments));
  constexpr double kMostPieces = 1e6;
  const double piece = std::max(tolerance / 4, c.length / kMostPieces);
  std::vector<double> covered(features.size(), 0.0);
  tbb::parallel_for(std::size_t(0), features.size(), [&](std::size_t i) {
    const auto& [a, b] = features[i];
    const auto n = uint32_t(std::max(1.0, std::ceil(norm(b - a) / piece)));
    uint32_t near = 0;
    for (uint32_t k = 0; k < n; ++k) {
      const Vec3 p = a + ((k + 0.5) / n) * (b - a);
      near += tree.closest(p).distance <= tolerance;
    }
    covered[i] = norm(b - a) * near / n;
  });
  for (const double l : covered) c.covered += l;  // in edge order: the same for any thread count
  return c;
}

}  // namespace isoquad
