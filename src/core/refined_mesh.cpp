#include "core/refined_mesh.hpp"

#include <algorithm>

namespace isoquad {

SurfacePoint RefinedMesh::vertex_origin(uint32_t v) const {
  const uint32_t h = mesh.outgoing(v);
  const uint32_t f = TriMesh::face_of(h);
  return {base_face[f], corner_bary[f][h % 3]};
}

RefinedMesh identity_refinement(const TriMesh& base) {
  RefinedMesh r;
  r.mesh = base;
  r.base_vertices = base.num_vertices();
  r.base_face = FaceData<uint32_t>(base.num_faces());
  r.corner_bary = FaceData<std::array<std::array<double, 3>, 3>>(base.num_faces());
  for (uint32_t f = 0; f < base.num_faces(); ++f) {
    r.base_face[f] = f;
    r.corner_bary[f] = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  }
  return r;
}

namespace {
std::array<double, 3> midpoint(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])};
}
}  // namespace

RefinedMesh split_edges(const RefinedMesh& in, const std::vector<uint32_t>& edges,
                        FaceData<uint32_t>* face_labels, EdgeData<char>* edge_flags,
                        const std::vector<double>* fractions) {
  const TriMesh& m = in.mesh;
  std::vector<uint32_t> mid(m.num_edges(), kInvalid);  // edge -> new vertex
  std::vector<double> at(fractions ? m.num_edges() : 0, 0.5);
  std::vector<Vec3> positions = m.positions();
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const uint32_t e = edges[i];
    if (mid[e] != kInvalid) continue;
    const uint32_t h = m.edge_halfedge(e);
    const double t = fractions ? (*fractions)[i] : 0.5;
    if (fractions) at[e] = t;
    mid[e] = uint32_t(positions.size());
    positions.push_back((1 - t) * m.position(m.from(h)) + t * m.position(m.to(h)));
  }
  std::vector<Tri> faces;
  std::vector<uint32_t> base_face, labels;
  std::vector<std::array<std::array<double, 3>, 3>> bary;
  std::vector<std::array<uint32_t, 3>>
      old_edge;  // per new face corner i: base edge of halfedge i, or kInvalid
  for (uint32_t f = 0; f < m.num_faces(); ++f) {
    // Corners of the face and of the edge midpoints, as (vertex, barycentric, edge-of-origin).
    const Tri& t = m.face(f);
    const auto& cb = in.corner_bary[f];
    uint32_t ms[3];
    std::array<double, 3> mb[3];
    int splits = 0, first = -1;
    for (int i = 0; i < 3; ++i) {
      ms[i] = mid[m.edge(3 * f + i)];
      if (!fractions) {
        mb[i] = midpoint(cb[i], cb[(i + 1) % 3]);
      } else {  // the fraction is from the edge's own halfedge's start
        const uint32_t e = m.edge(3 * f + i);
        const double s = m.from(m.edge_halfedge(e)) == t[i] ? at[e] : 1 - at[e];
        for (int k = 0; k < 3; ++k) mb[i][k] = (1 - s) * cb[i][k] + s * cb[(i + 1) % 3][k];
      }
      if (ms[i] != kInvalid) {
        ++splits;
        if (first < 0) first = i;
      }
    }
    // Rotate so that the pattern starts at a fixed edge.
    int r = 0;
    if (splits == 1) r = first;
    if (splits == 2)
      r = ms[0] == kInvalid ? 1 : (ms[1] == kInvalid ? 2 : 0);  // unsplit edge becomes edge 2
    auto V = [&](int i) { return t[(i + r) % 3]; };
    auto B = [&](int i) { return cb[(i + r) % 3]; };
    auto M = [&](int i) { return ms[(i + r) % 3]; };
    auto MB = [&](int i) { return mb[(i + r) % 3]; };
    auto E = [&](int i) { return m.edge(3 * f + (i + r) % 3); };
    struct Corner {
      uint32_t v;
      std::array<double, 3> b;
    };
    auto emit = [&](Corner a, Corner b, Corner c, std::array<uint32_t, 3> origin) {
      faces.push_back({a.v, b.v, c.v});
      bary.push_back({a.b, b.b, c.b});
      base_face.push_back(in.base_face[f]);
      if (face_labels) labels.push_back((*face_labels)[f]);
      old_edge.push_back(origin);
    };
    const uint32_t X = kInvalid;
    const Corner v0{V(0), B(0)}, v1{V(1), B(1)}, v2{V(2), B(2)};
    if (splits == 0) {
      emit({t[0], cb[0]}, {t[1], cb[1]}, {t[2], cb[2]},
           {m.edge(3 * f), m.edge(3 * f + 1), m.edge(3 * f + 2)});
    } else if (splits == 1) {
      const Corner m0{M(0), MB(0)};
      emit(v0, m0, v2, {E(0), X, E(2)});
      emit(m0, v1, v2, {E(0), E(1), X});
    } else if (splits == 2) {
      const Corner m0{M(0), MB(0)}, m1{M(1), MB(1)};
      emit(m0, v1, m1, {E(0), E(1), X});
      // The remaining quad v0, m0, m1, v2 is cut along its shorter diagonal.
      if (norm(positions[v0.v] - positions[m1.v]) <= norm(positions[m0.v] - positions[v2.v])) {
        emit(v0, m0, m1, {E(0), X, X});
        emit(v0, m1, v2, {X, E(1), E(2)});
      } else {
        emit(v0, m0, v2, {E(0), X, E(2)});
        emit(m0, m1, v2, {X, E(1), X});
      }
    } else {
      const Corner m0{M(0), MB(0)}, m1{M(1), MB(1)}, m2{M(2), MB(2)};
      emit(v0, m0, m2, {E(0), X, E(2)});
      emit(m0, v1, m1, {E(0), E(1), X});
      emit(m2, m1, v2, {X, E(1), E(2)});
      emit(m0, m1, m2, {X, X, X});
    }
  }
  RefinedMesh out;
  out.base_vertices = in.base_vertices;
  out.mesh = TriMesh(std::move(positions), std::move(faces));
  out.base_face = FaceData<uint32_t>(std::move(base_face));
  out.corner_bary = FaceData<std::array<std::array<double, 3>, 3>>(std::move(bary));
  if (face_labels) *face_labels = FaceData<uint32_t>(std::move(labels));
  if (edge_flags) {
    EdgeData<char> flags(out.mesh.num_edges(), 0);
    for (uint32_t nf = 0; nf < out.mesh.num_faces(); ++nf)
      for (int i = 0; i < 3; ++i)
        if (old_edge[nf][i] != kInvalid)
          flags[out.mesh.edge(3 * nf + i)] = (*edge_flags)[old_edge[nf][i]];
    *edge_flags = std::move(flags);
  }
  return out;
}

}  // namespace isoquad
