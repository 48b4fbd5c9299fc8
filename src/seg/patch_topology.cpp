#include "seg/patch_topology.hpp"

#include <algorithm>
#include <cmath>

namespace isoquad {

bool is_patch_boundary(const TriMesh& mesh, const FaceData<uint32_t>& labels, uint32_t h) {
  const uint32_t t = mesh.twin(h);
  return t == kInvalid || labels[TriMesh::face_of(t)] != labels[TriMesh::face_of(h)];
}

uint32_t next_patch_boundary_halfedge(const TriMesh& mesh, const FaceData<uint32_t>& labels,
                                      uint32_t h) {
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

std::vector<PatchTopology> local_patch_topology(const TriMesh& mesh,
                                                const FaceData<uint32_t>& labels,
                                                const std::vector<uint32_t>& faces,
                                                const std::vector<uint32_t>& patches) {
  std::vector<PatchTopology> t(patches.size());
  auto slot = [&](uint32_t p) {
    return std::size_t(std::find(patches.begin(), patches.end(), p) - patches.begin());
  };
  // Scratch marks sized for the mesh (a memset is far cheaper than sorting the region).
  const std::size_t nv = mesh.num_vertices();
  std::vector<char> vertex_seen(nv * patches.size(), 0);  // per patch slot
  std::vector<char> visited(mesh.num_halfedges(), 0);
  for (uint32_t f : faces) {
    const std::size_t k = slot(labels[f]);
    if (k == patches.size()) continue;
    ++t[k].faces;
    for (uint32_t i = 0; i < 3; ++i) {
      const uint32_t h = 3 * f + i, tw = mesh.twin(h);
      char& seen = vertex_seen[k * nv + mesh.from(h)];
      if (!seen) ++t[k].vertices;
      seen = 1;
      if (tw == kInvalid || labels[TriMesh::face_of(tw)] != labels[f] || h < tw) ++t[k].edges;
    }
  }
  for (uint32_t f : faces) {
    const std::size_t k = slot(labels[f]);
    if (k == patches.size()) continue;
    for (uint32_t i = 0; i < 3; ++i) {
      const uint32_t h0 = 3 * f + i;
      if (visited[h0] || !is_patch_boundary(mesh, labels, h0)) continue;
      ++t[k].boundary_loops;
      for (uint32_t h = h0; !visited[h]; h = next_patch_boundary_halfedge(mesh, labels, h)) {
        visited[h] = 1;
        ++t[k].boundary_edges;
      }
    }
  }
  return t;
}

double corner_angle(const TriMesh& mesh, uint32_t h) {
  const Vec3 o = mesh.position(mesh.from(h));
  const Vec3 a = mesh.position(mesh.to(h)) - o, b = mesh.position(mesh.from(TriMesh::prev(h))) - o;
  return angle_between(a, b);
}

double patch_angle(const TriMesh& mesh, const FaceData<uint32_t>& labels, uint32_t v, uint32_t p) {
  double sum = 0;
  mesh.for_each_outgoing(v, [&](uint32_t h) {
    if (p == kInvalid || labels[TriMesh::face_of(h)] == p) sum += corner_angle(mesh, h);
  });
  return sum;
}

uint32_t wedge_count(const TriMesh& mesh, const FaceData<uint32_t>& labels, uint32_t v) {
  uint32_t changes = 0, first = kInvalid, prev = kInvalid;
  mesh.for_each_outgoing(v, [&](uint32_t h) {
    const uint32_t l = labels[TriMesh::face_of(h)];
    if (first == kInvalid)
      first = l;
    else if (l != prev)
      ++changes;
    prev = l;
  });
  if (mesh.is_boundary_vertex(v)) return changes + 1;
  if (prev != first) ++changes;  // the fan closes
  return std::max(changes, 1u);
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
