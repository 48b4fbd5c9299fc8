#include "seg/patch_topology.hpp"

#include <algorithm>

namespace isoquad {

bool is_patch_boundary(const TriMesh& mesh, const FaceData<uint32_t>& labels, uint32_t h) {
  const uint32_t t = mesh.twin(h);
  return t == kInvalid || labels[TriMesh::face_of(t)] != labels[TriMesh::face_of(h)];
}

uint32_t next_patch_boundary_halfedge(const TriMesh& mesh, const FaceData<uint32_t>& labels, uint32_t h) {
  // Turn around to(h) through the patch's faces until leaving it.
  uint32_t cur = TriMesh::next(h);
  while (!is_patch_boundary(mesh, labels, cur)) cur = TriMesh::next(mesh.twin(cur));
  return cur;
}

std::vector<PatchTopology> patch_topology(const TriMesh& mesh, const FaceData<uint32_t>& labels,
                                          uint32_t num_patches) {
  std::vector<PatchTopology> t(num_patches);
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) ++t[labels[f]].faces;
  for (uint32_t e = 0; e < mesh.num_edges(); ++e) {
    const uint32_t h = mesh.edge_halfedge(e);
    const uint32_t p = labels[TriMesh::face_of(h)];
    ++t[p].edges;
    if (mesh.twin(h) != kInvalid && labels[TriMesh::face_of(mesh.twin(h))] != p)
      ++t[labels[TriMesh::face_of(mesh.twin(h))]].edges;
  }
  std::vector<uint32_t> seen;  // patches already counted at the current vertex
  for (uint32_t v = 0; v < mesh.num_vertices(); ++v) {
    seen.clear();
    mesh.for_each_outgoing(v, [&](uint32_t h) {
      const uint32_t p = labels[TriMesh::face_of(h)];
      if (std::find(seen.begin(), seen.end(), p) == seen.end()) seen.push_back(p);
    });
    for (uint32_t p : seen) ++t[p].vertices;
  }
  std::vector<char> visited(mesh.num_halfedges(), 0);
  for (uint32_t h0 = 0; h0 < mesh.num_halfedges(); ++h0) {
    if (visited[h0] || !is_patch_boundary(mesh, labels, h0)) continue;
    ++t[labels[TriMesh::face_of(h0)]].boundary_loops;
    for (uint32_t h = h0; !visited[h]; h = next_patch_boundary_halfedge(mesh, labels, h)) {
      visited[h] = 1;
      ++t[labels[TriMesh::face_of(h)]].boundary_edges;
    }
  }
  return t;
}

std::vector<Wedge> wedges_at(const TriMesh& mesh, const FaceData<uint32_t>& labels, uint32_t v) {
  std::vector<Wedge> w;
  mesh.for_each_outgoing(v, [&](uint32_t h) {
    const uint32_t f = TriMesh::face_of(h);
    if (w.empty() || w.back().patch != labels[f]) w.push_back({labels[f], {}});
    w.back().faces.push_back(f);
  });
  // Around an interior vertex the fan is cyclic: the last run continues the first.
  if (!mesh.is_boundary_vertex(v) && w.size() > 1 && w.front().patch == w.back().patch) {
    w.back().faces.insert(w.back().faces.end(), w.front().faces.begin(), w.front().faces.end());
    w.erase(w.begin());
  }
  return w;
}

}  // namespace isoquad
