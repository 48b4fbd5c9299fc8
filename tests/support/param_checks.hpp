// Independent checks of a seamless map: the certificate, seam vertices consistent across their
// transition, interior vertices single-valued, meta-vertices exactly on their lattice points.
#pragma once

#include <gtest/gtest.h>

#include <cmath>

#include "param/param.hpp"

namespace isoquad::test {

inline void expect_seamless(const TriMesh& mesh, const FaceData<uint32_t>& labels,
                            const MetaMesh& meta, const Layout& layout, const ParamMap& map,
                            double tolerance = 1e-9) {
  // First uv seen per (vertex, chart), through any face of that chart.
  std::vector<std::vector<std::pair<uint32_t, UV>>> seen(mesh.num_vertices());
  uint32_t mismatches = 0, off_lattice = 0, inconsistent = 0;
  for (uint32_t f = 0; f < mesh.num_faces(); ++f)
    for (int c = 0; c < 3; ++c) {
      const uint32_t v = mesh.face(f)[c];
      const UV uv = map.uv[f][c];
      auto& s = seen[v];
      auto it =
          std::find_if(s.begin(), s.end(), [&](const auto& e) { return e.first == labels[f]; });
      if (it == s.end())
        s.emplace_back(labels[f], uv);
      else if (it->second != uv)
        ++mismatches;  // one chart, one position: bit-identical
      if (meta.vertex_meta_vertex[v] != kInvalid &&
          (uv[0] != std::round(uv[0]) || uv[1] != std::round(uv[1]) || uv[0] < 0 || uv[1] < 0 ||
           uv[0] > double(layout.charts[labels[f]].width) ||
           uv[1] > double(layout.charts[labels[f]].height)))
        ++off_lattice;
    }
  for (uint32_t e = 0; e < meta.edges.size(); ++e) {
    const MetaEdge& me = meta.edges[e];
    if (me.right == kInvalid) continue;
    const Transition& t = layout.transition[e];
    for (const uint32_t v : me.vertices) {
      UV l{NAN, NAN}, r{NAN, NAN};
      for (const auto& [chart, uv] : seen[v]) {
        if (chart == me.left) l = uv;
        if (chart == me.right) r = uv;
      }
      // R^k l + t, with R the counter-clockwise quarter turn.
      UV m = l;
      for (int k = 0; k < t.k; ++k) m = {-m[1], m[0]};
      m = {m[0] + double(t.t[0]), m[1] + double(t.t[1])};
      if (!(std::hypot(m[0] - r[0], m[1] - r[1]) <= tolerance)) ++inconsistent;
    }
  }
  EXPECT_EQ(mismatches, 0u) << "vertices with two positions in one chart";
  EXPECT_EQ(off_lattice, 0u) << "meta-vertex corners off their lattice points";
  EXPECT_EQ(inconsistent, 0u) << "seam vertices whose charts disagree under the transition";
}

inline void expect_certified(const TriMesh& mesh, const FaceData<uint32_t>& labels,
                             const MetaMesh& meta, const Layout& layout, const Param& param) {
  const Certificate c = certify(mesh, labels, meta, layout, param.map);
  EXPECT_EQ(c.flipped, 0u);
  EXPECT_EQ(c.degenerate, 0u);
  EXPECT_EQ(c.bad_angle_sums, 0u);
  expect_seamless(mesh, labels, meta, layout, param.map);
  expect_seamless(mesh, labels, meta, layout, param.locked);
}

}  // namespace isoquad::test
