#include "layout/straighten.hpp"

#include <algorithm>
#include <iterator>

#include "layout/meta_mesh.hpp"
#include "seg/geodesic.hpp"
#include "seg/patch_topology.hpp"

namespace isoquad {

double seam_length(const TriMesh& m, const FaceData<uint32_t>& labels,
                   const EdgeData<char>& feature) {
  double len = 0;
  for (uint32_t e = 0; e < m.num_edges(); ++e) {
    const uint32_t h = m.edge_halfedge(e);
    if (m.twin(h) == kInvalid || feature[e]) continue;
    if (labels[TriMesh::face_of(h)] != labels[TriMesh::face_of(m.twin(h))])
      len += norm(m.position(m.to(h)) - m.position(m.from(h)));
  }
  return len;
}

namespace {

// The paper's rule: face (a,b,c) of P whose edges a-b and b-c lie on one P|Q seam, b not a
// junction, goes to Q; the seam then runs along a-c, which is shorter. P stays a disk because
// a-c is interior to P. Repeats until nothing changes.
uint32_t relabel_ears(const TriMesh& m, FaceData<uint32_t>& labels, const EdgeData<char>& feature) {
  uint32_t moved = 0;
  for (bool changed = true; changed;) {
    changed = false;
    for (uint32_t f = 0; f < m.num_faces(); ++f) {
      const uint32_t p = labels[f];
      for (uint32_t i = 0; i < 3; ++i) {
        const uint32_t ab = 3 * f + i, bc = TriMesh::next(ab), ca = TriMesh::next(bc);
        const uint32_t tab = m.twin(ab), tbc = m.twin(bc), tca = m.twin(ca);
        if (tab == kInvalid || tbc == kInvalid || tca == kInvalid) continue;
        const uint32_t q = labels[TriMesh::face_of(tab)];
        if (q == p || labels[TriMesh::face_of(tbc)] != q || labels[TriMesh::face_of(tca)] != p)
          continue;
        if (feature[m.edge(ab)] || feature[m.edge(bc)]) continue;
        // b must see only P (this face) and Q: otherwise it is a junction.
        bool only_pq = true;
        m.for_each_outgoing(m.to(ab), [&](uint32_t h) {
          const uint32_t l = labels[TriMesh::face_of(h)];
          only_pq = only_pq && (l == q || TriMesh::face_of(h) == f);
        });
        if (!only_pq || m.is_boundary_vertex(m.to(ab))) continue;
        labels[f] = q;
        ++moved;
        changed = true;
        break;
      }
    }
  }
  return moved;
}

// What smooth_seam reuses from seam to seam, so that each costs about its two patches, not the
// mesh: the path search's arrays, marks (all 0 between calls) and each patch's faces in
// increasing order.
struct SeamScratch {
  PathScratch path;
  std::vector<char> cut, left;
  std::vector<std::vector<uint32_t>> faces;
};

// Replaces the seam of meta-edge e by the shortest path between its ends inside P and Q.
bool smooth_seam(const TriMesh& m, FaceData<uint32_t>& labels, const MetaEdge& e,
                 SeamScratch& scratch) {
  const uint32_t p = e.left, q = e.right;
  auto in_pq = [&](uint32_t f) { return labels[f] == p || labels[f] == q; };
  auto inner_edge = [&](uint32_t edge) {
    const uint32_t h = m.edge_halfedge(edge);
    return m.twin(h) != kInvalid && in_pq(TriMesh::face_of(h)) &&
           in_pq(TriMesh::face_of(m.twin(h)));
  };
  auto inner_vertex = [&](uint32_t v) {
    if (m.is_boundary_vertex(v)) return false;
    bool all = true;
    m.for_each_outgoing(v, [&](uint32_t h) { all = all && in_pq(TriMesh::face_of(h)); });
    return all;
  };
  const uint32_t a = e.vertices.front(), b = e.vertices.back();
  double length = INFINITY;
  const std::vector<uint32_t> path = vertex_path(
      m, a, b,
      [&](uint32_t v, uint32_t edge) { return inner_edge(edge) && (v == b || inner_vertex(v)); },
      scratch.path, length);
  if (path.size() < 2 || length >= e.length * (1 - 1e-9)) return false;

  // Halfedges along the path, and the faces on their left.
  std::vector<char>& cut = scratch.cut;
  std::vector<uint32_t> cut_edges, left_faces;
  for (std::size_t i = 0; i + 1 < path.size(); ++i)
    m.for_each_outgoing(path[i], [&](uint32_t h) {
      if (m.to(h) == path[i + 1]) {
        cut[m.edge(h)] = 1;
        cut_edges.push_back(m.edge(h));
        left_faces.push_back(TriMesh::face_of(h));
      }
    });
  // Flood P and Q from the left side without crossing the path: that side becomes P.
  std::vector<char>& left = scratch.left;
  std::vector<uint32_t> stack = left_faces;
  for (uint32_t f : stack) left[f] = 1;
  while (!stack.empty()) {
    const uint32_t f = stack.back();
    stack.pop_back();
    for (uint32_t i = 0; i < 3; ++i) {
      const uint32_t h = 3 * f + i;
      if (m.twin(h) == kInvalid || cut[m.edge(h)]) continue;
      const uint32_t g = TriMesh::face_of(m.twin(h));
      if (!left[g] && in_pq(g)) {
        left[g] = 1;
        stack.push_back(g);
      }
    }
  }
  for (const uint32_t c : cut_edges) cut[c] = 0;
  // The faces of P and Q in increasing order, relabelled by side (undone if rejected).
  std::vector<uint32_t> region;
  std::merge(scratch.faces[p].begin(), scratch.faces[p].end(), scratch.faces[q].begin(),
             scratch.faces[q].end(), std::back_inserter(region));
  uint32_t left_count = 0;
  for (const uint32_t f : region) left_count += left[f];
  const uint32_t total = uint32_t(region.size());
  auto reject = [&] {
    for (const uint32_t f : region) left[f] = 0;
    return false;
  };
  if (left_count == 0 || left_count == total) return reject();  // the path does not separate
  const auto before_a = wedges_at(m, labels, a).size(), before_b = wedges_at(m, labels, b).size();
  std::vector<uint32_t> saved(total);
  for (uint32_t i = 0; i < total; ++i) {
    saved[i] = labels[region[i]];
    labels[region[i]] = left[region[i]] ? p : q;
  }
  bool ok =
      wedges_at(m, labels, a).size() == before_a && wedges_at(m, labels, b).size() == before_b;
  if (ok) {
    const auto topo = local_patch_topology(m, labels, region, {p, q});
    ok = topo[0].is_disk() && topo[1].is_disk();
  }
  if (!ok) {
    for (uint32_t i = 0; i < total; ++i) labels[region[i]] = saved[i];
    return reject();
  }
  scratch.faces[p].clear();
  scratch.faces[q].clear();
  for (const uint32_t f : region) scratch.faces[labels[f]].push_back(f);
  for (const uint32_t f : region) left[f] = 0;
  return true;
}

}  // namespace

void straighten_seams(const TriMesh& m, FaceData<uint32_t>& labels, uint32_t n,
                      const EdgeData<char>& feature, StraightenLog& log) {
  log.seam_length_before = seam_length(m, labels, feature);
  log.ears += relabel_ears(m, labels, feature);
  // Junctions only (one inserted point on seam loops without any), so that seams run between them.
  MetaMeshOptions one;
  one.min_corners = 1;
  const MetaMesh junctions = build_meta_mesh(m, labels, n, feature, one);
  SeamScratch scratch;
  scratch.cut.assign(m.num_edges(), 0);
  scratch.left.assign(m.num_faces(), 0);
  scratch.faces.resize(n);
  for (uint32_t f = 0; f < m.num_faces(); ++f) scratch.faces.at(labels[f]).push_back(f);
  for (const MetaEdge& e : junctions.edges) {
    if (e.right == kInvalid || e.feature || e.mv0 == e.mv1) continue;
    if (smooth_seam(m, labels, e, scratch)) ++log.geodesic;
  }
  log.ears += relabel_ears(m, labels, feature);
  log.seam_length_after = seam_length(m, labels, feature);
}

}  // namespace isoquad
