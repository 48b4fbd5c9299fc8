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
                  SmoothReport& report) {
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
      double before = 1;
      for (const uint32_t f : around[v])
        before = std::min(before, quad_sj(qm.positions, qm.quads[f]));
      const SurfacePoint s = project_locally(base, qm.surface[v].face, avg);
      const Vec3 old = qm.positions[v];
      qm.positions[v] = position_of(base, s);
      double after = 1;
      for (const uint32_t f : around[v])
        after = std::min(after, quad_sj(qm.positions, qm.quads[f]));
      if (after >= std::min(before, 0.2)) {
        qm.surface[v] = s;
        ++report.moves;
      } else {
        qm.positions[v] = old;
        ++report.rejected;
      }
    }
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace isoquad
