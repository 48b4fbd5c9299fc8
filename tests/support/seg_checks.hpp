// Properties every segmentation must have, whatever the input (shared by unit and corpus tests).
#pragma once

#include <gtest/gtest.h>
#include <set>

#include "layout/divide_split.hpp"
#include "seg/patch_topology.hpp"
#include "seg/segment.hpp"

namespace isoquad::test {

inline bool patch_connected(const TriMesh& m, const FaceData<uint32_t>& labels, uint32_t p) {
  std::vector<uint32_t> faces;
  for (uint32_t f = 0; f < m.num_faces(); ++f)
    if (labels[f] == p) faces.push_back(f);
  if (faces.empty()) return false;
  std::set<uint32_t> seen{faces[0]};
  std::vector<uint32_t> stack{faces[0]};
  while (!stack.empty()) {
    const uint32_t f = stack.back();
    stack.pop_back();
    for (uint32_t i = 0; i < 3; ++i) {
      const uint32_t t = m.twin(3 * f + i);
      if (t != kInvalid && labels[TriMesh::face_of(t)] == p &&
          seen.insert(TriMesh::face_of(t)).second)
        stack.push_back(TriMesh::face_of(t));
    }
  }
  return seen.size() == faces.size();
}

// Checks on the refined mesh (after the dividing-edge split), where labels and meta-mesh live.
inline void expect_valid_segmentation(const TriMesh& base, const SegmentResult& r) {
  const TriMesh& m = r.refined.mesh;
  const auto topo = patch_topology(m, r.labels, r.num_patches);
  uint32_t bad = 0;
  for (uint32_t p = 0; p < r.num_patches && bad < 5; ++p) {
    const bool ok =
        patch_connected(m, r.labels, p) && topo[p].is_disk() && r.meta.faces[p].cycle.size() >= 4;
    EXPECT_TRUE(ok) << "patch " << p << ": loops " << topo[p].boundary_loops << ", euler "
                    << topo[p].euler() << ", meta-vertices " << r.meta.faces[p].cycle.size();
    bad += !ok;
  }
  for (uint32_t v = 0; v < m.num_vertices(); ++v) {  // no pinch: a patch in one wedge per vertex
    std::set<uint32_t> seen;
    for (const Wedge& w : wedges_at(m, r.labels, v))
      if (!seen.insert(w.patch).second)
        ADD_FAILURE() << "patch " << w.patch << " pinched at vertex " << v;
  }
  EXPECT_NO_THROW(check_meta_mesh(m, r.labels, r.meta));
  EXPECT_EQ(r.meta.euler(), m.euler_characteristic());
  EXPECT_LE(r.straighten.seam_length_after, r.straighten.seam_length_before * (1 + 1e-12));
  // 3-connectedness: no interior edge of a patch has both ends on its boundary.
  EXPECT_TRUE(dividing_edges(m, r.labels).empty());
  // Provenance: every vertex is reproduced from its base face and barycentric coordinates.
  for (uint32_t v = 0; v < m.num_vertices(); ++v) {
    const SurfacePoint sp = r.refined.vertex_origin(v);
    const Tri& t = base.face(sp.face);
    const Vec3 p = sp.bary[0] * base.position(t[0]) + sp.bary[1] * base.position(t[1]) +
                   sp.bary[2] * base.position(t[2]);
    EXPECT_LT(norm(p - m.position(v)), 1e-14) << "vertex " << v;
  }
  for (const MetaEdge& e : r.meta.edges) {
    EXPECT_GT(e.geodesic, 0.0);
    EXPECT_LE(e.geodesic, e.length * (1 + 1e-12));
  }
}

}  // namespace isoquad::test
