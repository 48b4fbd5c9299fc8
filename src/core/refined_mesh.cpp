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

// The refined mesh from its pieces: `old_edge[f][i]`, the base edge that halfedge i of new face f
// lies on (kInvalid inside a face), passes the edge flags on.
RefinedMesh assemble(const RefinedMesh& in, std::vector<Vec3> positions, std::vector<Tri> faces,
                     std::vector<uint32_t> base_face,
                     std::vector<std::array<std::array<double, 3>, 3>> bary,
                     std::vector<uint32_t> labels,
                     const std::vector<std::array<uint32_t, 3>>& old_edge,
                     FaceData<uint32_t>* face_labels, EdgeData<char>* edge_flags) {
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

}  // namespace

RefinedMesh split_edges(const RefinedMesh& in, const std::vector<uint32_t>& edges,
                        FaceData<uint32_t>* face_labels, EdgeData<char>* edge_flags) {
  const TriMesh& m = in.mesh;
  std::vector<uint32_t> mid(m.num_edges(), kInvalid);  // edge -> new vertex
  std::vector<Vec3> positions = m.positions();
  for (uint32_t e : edges) {
    if (mid[e] != kInvalid) continue;
    const uint32_t h = m.edge_halfedge(e);
    mid[e] = uint32_t(positions.size());
    positions.push_back(0.5 * (m.position(m.from(h)) + m.position(m.to(h))));
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
      mb[i] = midpoint(cb[i], cb[(i + 1) % 3]);
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
  return assemble(in, std::move(positions), std::move(faces), std::move(base_face), std::move(bary),
                  std::move(labels), old_edge, face_labels, edge_flags);
}

RefinedMesh cut_along_chords(const RefinedMesh& in, const std::vector<EdgePoint>& points,
                             const std::vector<Chord>& chords, FaceData<uint32_t>* face_labels,
                             EdgeData<char>* edge_flags) {
  const TriMesh& m = in.mesh;
  const uint32_t nv = m.num_vertices();
  std::vector<Vec3> positions = m.positions();
  std::vector<std::vector<std::pair<double, uint32_t>>> on_edge(m.num_edges());
  for (uint32_t i = 0; i < points.size(); ++i) {
    const uint32_t h = m.edge_halfedge(points[i].edge);
    const double t = points[i].fraction;
    positions.push_back((1 - t) * m.position(m.from(h)) + t * m.position(m.to(h)));
    on_edge[points[i].edge].emplace_back(t, nv + i);
  }
  for (auto& list : on_edge) std::sort(list.begin(), list.end());
  std::vector<std::vector<const Chord*>> chords_of(m.num_faces());
  for (const Chord& c : chords) chords_of[c.face].push_back(&c);

  std::vector<Tri> faces;
  std::vector<uint32_t> base_face, labels;
  std::vector<std::array<std::array<double, 3>, 3>> bary;
  std::vector<std::array<uint32_t, 3>> old_edge;  // per corner i: base edge of halfedge i
  for (uint32_t f = 0; f < m.num_faces(); ++f) {
    const Tri& t = m.face(f);
    const auto& cb = in.corner_bary[f];
    // The face's boundary, CCW: corners and edge points, with each vertex's barycentric
    // coordinates and the base edge of the boundary piece that starts at it.
    std::vector<uint32_t> ring, piece_edge;
    std::vector<std::array<double, 3>> ring_bary;
    for (uint32_t i = 0; i < 3; ++i) {
      const uint32_t e = m.edge(3 * f + i);
      ring.push_back(t[i]), ring_bary.push_back(cb[i]), piece_edge.push_back(e);
      const bool forward = m.from(m.edge_halfedge(e)) == t[i];
      auto list = on_edge[e];
      if (!forward) std::reverse(list.begin(), list.end());
      for (const auto& [frac, id] : list) {
        const double s = forward ? frac : 1 - frac;
        std::array<double, 3> b;
        for (int k = 0; k < 3; ++k) b[k] = (1 - s) * cb[i][k] + s * cb[(i + 1) % 3][k];
        ring.push_back(id), ring_bary.push_back(b), piece_edge.push_back(e);
      }
    }
    const uint32_t n = uint32_t(ring.size());
    auto at = [&](uint32_t v) {
      for (uint32_t j = 0; j < n; ++j)
        if (ring[j] == v) return j;
      return kInvalid;
    };
    // Pieces as lists of ring positions; each chord splits the piece holding both its ends.
    std::vector<std::vector<uint32_t>> pieces(1);
    for (uint32_t j = 0; j < n; ++j) pieces[0].push_back(j);
    for (const Chord* c : chords_of[f]) {
      const uint32_t a = at(c->a), b = at(c->b);
      if (a == kInvalid || b == kInvalid || a == b) continue;
      for (std::size_t q = 0; q < pieces.size(); ++q) {
        std::vector<uint32_t>& piece = pieces[q];
        const auto ia = std::find(piece.begin(), piece.end(), a);
        const auto ib = std::find(piece.begin(), piece.end(), b);
        if (ia == piece.end() || ib == piece.end()) continue;
        const std::size_t pa = std::size_t(ia - piece.begin()),
                          pb = std::size_t(ib - piece.begin());
        const std::size_t k = piece.size();
        if ((pa + 1) % k == pb || (pb + 1) % k == pa) break;  // already an edge of the piece
        std::vector<uint32_t> one, two;
        for (std::size_t i = pa;; i = (i + 1) % k) {
          one.push_back(piece[i]);
          if (i == pb) break;
        }
        for (std::size_t i = pb;; i = (i + 1) % k) {
          two.push_back(piece[i]);
          if (i == pa) break;
        }
        piece = std::move(one);
        pieces.push_back(std::move(two));
        break;
      }
    }
    // Ear clipping (each piece is convex, with collinear runs along the face's edges).
    const Vec3 normal = m.face_normal(f);
    const double tiny = 1e-14 * std::max(m.face_area(f), 1e-300);
    auto emit = [&](uint32_t i, uint32_t j, uint32_t k) {
      faces.push_back({ring[i], ring[j], ring[k]});
      bary.push_back({ring_bary[i], ring_bary[j], ring_bary[k]});
      base_face.push_back(in.base_face[f]);
      if (face_labels) labels.push_back((*face_labels)[f]);
      auto along = [&](uint32_t u, uint32_t v) {
        return (u + 1) % n == v ? piece_edge[u] : kInvalid;
      };
      old_edge.push_back({along(i, j), along(j, k), along(k, i)});
    };
    for (std::vector<uint32_t> piece : pieces) {
      while (piece.size() > 3) {
        const std::size_t k = piece.size();
        std::size_t ear = 0;
        double best = -INFINITY;
        for (std::size_t i = 0; i < k; ++i) {  // the ear with the largest smallest angle
          const Vec3 p = positions[ring[piece[(i + k - 1) % k]]], q = positions[ring[piece[i]]],
                     r = positions[ring[piece[(i + 1) % k]]];
          auto area2 = [&](const Vec3& a, const Vec3& b, const Vec3& w) {
            return dot(cross(b - a, w - a), normal);
          };
          if (area2(p, q, r) <= tiny) continue;
          // No other vertex of the piece in the ear or on its diagonal (the collinear points
          // along the face's edges would be).
          bool empty = true;
          for (std::size_t j = 0; j < k && empty; ++j) {
            if (j == i || j == (i + 1) % k || j == (i + k - 1) % k) continue;
            const Vec3 w = positions[ring[piece[j]]];
            empty = area2(p, q, w) < -tiny || area2(q, r, w) < -tiny || area2(r, p, w) < -tiny;
          }
          if (!empty) continue;
          double least = INFINITY;
          for (const auto& [x, y, z] :
               {std::array{p, q, r}, std::array{q, r, p}, std::array{r, p, q}}) {
            const Vec3 u = y - x, w = z - x;
            least = std::min(least, angle_between(u, w));
          }
          if (least > best) best = least, ear = i;
        }
        emit(piece[(ear + k - 1) % k], piece[ear], piece[(ear + 1) % k]);
        piece.erase(piece.begin() + std::ptrdiff_t(ear));
      }
      if (piece.size() == 3) emit(piece[0], piece[1], piece[2]);
    }
  }
  return assemble(in, std::move(positions), std::move(faces), std::move(base_face), std::move(bary),
                  std::move(labels), old_edge, face_labels, edge_flags);
}

}  // namespace isoquad
