#include "layout/divide_split.hpp"

namespace isoquad {

namespace {
bool on_patch_boundary(const TriMesh& m, const FaceData<uint32_t>& labels, uint32_t v, uint32_t p) {
  if (m.is_boundary_vertex(v)) return true;
  bool other = false;
  m.for_each_outgoing(v, [&](uint32_t h) { other = other || labels[TriMesh::face_of(h)] != p; });
  return other;
}
}  // namespace

std::vector<uint32_t> dividing_edges(const TriMesh& m, const FaceData<uint32_t>& labels) {
  std::vector<uint32_t> out;
  for (uint32_t e = 0; e < m.num_edges(); ++e) {
    const uint32_t h = m.edge_halfedge(e), t = m.twin(h);
    if (t == kInvalid) continue;
    const uint32_t p = labels[TriMesh::face_of(h)];
    if (labels[TriMesh::face_of(t)] != p) continue;  // a seam, not interior
    if (on_patch_boundary(m, labels, m.from(h), p) && on_patch_boundary(m, labels, m.to(h), p))
      out.push_back(e);
  }
  return out;
}

uint32_t split_dividing_edges(RefinedMesh& refined, FaceData<uint32_t>& labels,
                              EdgeData<char>& feature) {
  uint32_t total = 0;
  for (int round = 0; round < 4; ++round) {
    const std::vector<uint32_t> edges = dividing_edges(refined.mesh, labels);
    if (edges.empty()) break;
    refined = split_edges(refined, edges, &labels, &feature);
    total += uint32_t(edges.size());
  }
  return total;
}

}  // namespace isoquad
