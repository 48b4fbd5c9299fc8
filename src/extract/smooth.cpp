#include "extract/smooth.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "extract/surface_walk.hpp"
#include "metrics/quality.hpp"

namespace isoquad {

namespace {

double quad_sj(const std::vector<Vec3>& x, const std::array<uint32_t, 4>& q) {
  return quad_scaled_jacobian({x[q[0]], x[q[1]], x[q[2]], x[q[3]]});
}

}  // namespace

void smooth_quads(QuadMesh& qm, const TriMesh& base, const MetaMesh& meta, uint32_t iterations,
                  SmoothReport& report, const AabbTree* surface_tree) {
  // The guard's values of one quad: its own scaled Jacobian, and against the surface if known.
  auto guard = [&](uint32_t f) {
    const double on_surface =
        surface_tree
            ? quad_corner_sj(qm, f,
                             [&](uint32_t v, const Vec3& inside) {
                               return surface_tree->normal_at_closest(inside, qm.surface[v].face);
                             })
            : 1.0;
    return std::pair(quad_sj(qm.positions, qm.quads[f]), on_surface);
  };
  std::vector<std::pair<double, double>> before;
  const auto t0 = std::chrono::steady_clock::now();
  const uint32_t n = uint32_t(qm.positions.size());
  std::vector<char> fixed(n, 0);
  for (uint32_t v = 0; v < n; ++v) {
    const uint32_t e = qm.vertex_meta_edge[v];
    fixed[v] = qm.vertex_meta_vertex[v] != kInvalid ||
               (e != kInvalid && (meta.edges[e].feature || meta.edges[e].right == kInvalid));
  }
  std::vector<std::vector<uint32_t>> nbr(n), around(n);
  for (uint32_t f = 0; f < qm.quads.size(); ++f)
    for (int i = 0; i < 4; ++i) {
      const uint32_t a = qm.quads[f][i], b = qm.quads[f][(i + 1) % 4];
      nbr[a].push_back(b);
      nbr[b].push_back(a);
      around[a].push_back(f);
    }
  for (auto& l : nbr) {
    std::sort(l.begin(), l.end());
    l.erase(std::unique(l.begin(), l.end()), l.end());
  }
  for (uint32_t it = 0; it < iterations; ++it) {
    ++report.iterations;
    for (uint32_t v = 0; v < n; ++v) {
      if (fixed[v] || nbr[v].empty()) continue;
      Vec3 avg;
      for (const uint32_t w : nbr[v]) avg += qm.positions[w];
      avg = avg / double(nbr[v].size());
      before.clear();
      for (const uint32_t f : around[v]) before.push_back(guard(f));
      const SurfacePoint s = project_locally(base, qm.surface[v].face, avg);
      const Vec3 old = qm.positions[v];
      const SurfacePoint old_surface = qm.surface[v];
      qm.positions[v] = position_of(base, s);
      qm.surface[v] = s;  // the corner normals' search starts from it
      // Without the surface's tree, the worst quad around v may not get worse; with it, no quad
      // may, by either measure (a quad folded already would otherwise let others fold).
      bool ok = true;
      if (surface_tree) {
        for (std::size_t i = 0; i < around[v].size() && ok; ++i) {
          const auto [own, on_surface] = guard(around[v][i]);
          ok = own >= std::min(before[i].first, 0.2) &&
               on_surface >= std::min(before[i].second, 0.2);
        }
      } else {
        double worst_before = 1, worst_after = 1;
        for (std::size_t i = 0; i < around[v].size(); ++i) {
          worst_before = std::min(worst_before, before[i].first);
          worst_after = std::min(worst_after, guard(around[v][i]).first);
        }
        ok = worst_after >= std::min(worst_before, 0.2);
      }
      if (ok) {
        ++report.moves;
      } else {
        qm.positions[v] = old;
        qm.surface[v] = old_surface;
        ++report.rejected;
      }
    }
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace isoquad
