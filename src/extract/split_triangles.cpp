#include "extract/split_triangles.hpp"

namespace isoquad {

QuadMesh split_triangles_into_quads(const TriMesh& mesh) {
  QuadMesh q;
  const uint32_t nv = mesh.num_vertices(), ne = mesh.num_edges(), nf = mesh.num_faces();
  q.positions.resize(nv + ne + nf);
  q.surface.resize(q.positions.size());
  // Where each new vertex lies in one face that holds it (provenance, as extraction gives it).
  const auto place = [&](uint32_t v, uint32_t f, std::array<double, 3> bary) {
    const Tri& t = mesh.face(f);
    q.positions[v] = bary[0] * mesh.position(t[0]) + bary[1] * mesh.position(t[1]) +
                     bary[2] * mesh.position(t[2]);
    q.surface[v] = {f, bary};
  };
  for (uint32_t f = 0; f < nf; ++f) {
    const Tri& t = mesh.face(f);
    for (uint32_t i = 0; i < 3; ++i) {
      std::array<double, 3> corner{}, middle{};
      corner[i] = 1;
      middle[i] = middle[(i + 1) % 3] = 0.5;
      place(t[i], f, corner);
      place(nv + mesh.edge(3 * f + i), f, middle);  // the edge from corner i to corner i + 1
    }
    place(nv + ne + f, f, {1.0 / 3, 1.0 / 3, 1.0 / 3});
  }
  for (uint32_t f = 0; f < nf; ++f) {
    const Tri& t = mesh.face(f);
    const uint32_t centroid = nv + ne + f;
    for (uint32_t i = 0; i < 3; ++i) {
      const uint32_t next = nv + mesh.edge(3 * f + i), prev = nv + mesh.edge(3 * f + (i + 2) % 3);
      q.quads.push_back({t[i], next, centroid, prev});
      q.quad_patch.push_back(f);
    }
  }
  const std::size_t n = q.positions.size();
  q.vertex_meta_vertex.assign(n, kInvalid);
  q.vertex_meta_edge.assign(n, kInvalid);
  q.placed.assign(n, QuadMesh::Placed::direct);
  q.mapped = q.positions;
  q.merged.assign(n, 0);
  return q;
}

}  // namespace isoquad
