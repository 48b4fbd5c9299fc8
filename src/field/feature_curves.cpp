#include "field/feature_curves.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/union_find.hpp"

namespace isoquad {

namespace {

// The halfedges leaving v along feature edges (boundary edges are never features).
std::vector<uint32_t> feature_out(const TriMesh& mesh, const EdgeData<char>& feature, uint32_t v) {
  std::vector<uint32_t> out;
  mesh.for_each_outgoing(v, [&](uint32_t h) {
    if (feature[mesh.edge(h)]) out.push_back(h);
  });
  return out;
}

Vec3 direction(const TriMesh& mesh, uint32_t h) {
  return normalized(mesh.position(mesh.to(h)) - mesh.position(mesh.from(h)));
}

}  // namespace

std::vector<FeatureCurve> feature_curves(const TriMesh& mesh, const EdgeData<char>& feature,
                                         double corner_deg) {
  const double cos_corner = std::cos(corner_deg * std::numbers::pi / 180);
  // A vertex continues a curve when exactly two feature edges meet there at a gentle turn.
  VertexData<char> through(mesh.num_vertices(), 0);
  for (uint32_t v = 0; v < mesh.num_vertices(); ++v) {
    const std::vector<uint32_t> out = feature_out(mesh, feature, v);
    if (out.size() == 2 && dot(direction(mesh, out[0]), -direction(mesh, out[1])) >= cos_corner)
      through[v] = 1;
  }
  EdgeData<char> used(mesh.num_edges(), 0);
  std::vector<FeatureCurve> curves;
  auto walk = [&](uint32_t h, FeatureCurve& c) {
    // Follows the chain from halfedge h until a node or a used edge.
    while (!used[mesh.edge(h)]) {
      used[mesh.edge(h)] = 1;
      c.halfedges.push_back(h);
      c.length += norm(mesh.position(mesh.to(h)) - mesh.position(mesh.from(h)));
      const uint32_t v = mesh.to(h);
      if (!through[v]) return;
      uint32_t next = kInvalid;
      for (uint32_t g : feature_out(mesh, feature, v))
        if (mesh.edge(g) != mesh.edge(h)) next = g;
      h = next;
    }
    c.closed = true;
  };
  // Open curves first, from their nodes; what is left are closed loops.
  for (uint32_t v = 0; v < mesh.num_vertices(); ++v) {
    if (through[v]) continue;
    for (uint32_t h : feature_out(mesh, feature, v)) {
      if (used[mesh.edge(h)]) continue;
      FeatureCurve c;
      walk(h, c);
      c.closed = false;
      curves.push_back(std::move(c));
    }
  }
  for (uint32_t e = 0; e < mesh.num_edges(); ++e) {
    if (!feature[e] || used[e]) continue;
    FeatureCurve c;
    walk(mesh.edge_halfedge(e), c);
    curves.push_back(std::move(c));
  }
  return curves;
}

EdgeData<char> long_features(const TriMesh& mesh, const EdgeData<char>& feature,
                             const FeatureNetworkRule& rule, uint32_t* dropped_networks) {
  // Networks: feature edges connected through shared vertices.
  UnionFind networks(mesh.num_vertices());
  for (uint32_t e = 0; e < mesh.num_edges(); ++e)
    if (feature[e]) {
      const uint32_t h = mesh.edge_halfedge(e);
      networks.unite(mesh.from(h), mesh.to(h));
    }
  // Per network (at its root vertex): length, and dihedral angle times length.
  std::vector<double> length(mesh.num_vertices(), 0.0), bend(mesh.num_vertices(), 0.0);
  for (uint32_t e = 0; e < mesh.num_edges(); ++e)
    if (feature[e]) {
      const uint32_t h = mesh.edge_halfedge(e);
      const double l = norm(mesh.position(mesh.to(h)) - mesh.position(mesh.from(h)));
      const double cosine = dot(mesh.face_normal(TriMesh::face_of(h)),
                                mesh.face_normal(TriMesh::face_of(mesh.twin(h))));
      const uint32_t r = networks.find(mesh.from(h));
      length[r] += l;
      bend[r] += l * std::acos(std::clamp(cosine, -1.0, 1.0));
    }
  const double weak = rule.weak_angle_deg * std::numbers::pi / 180;
  auto kept_network = [&](uint32_t r) {
    if (!(length[r] >= rule.min_length)) return false;
    return length[r] >= rule.weak_length || bend[r] >= weak * length[r];
  };
  EdgeData<char> kept(mesh.num_edges(), 0);
  uint32_t dropped = 0;
  for (uint32_t v = 0; v < mesh.num_vertices(); ++v)
    if (length[v] > 0 && !kept_network(v)) ++dropped;
  for (uint32_t e = 0; e < mesh.num_edges(); ++e)
    if (feature[e]) kept[e] = kept_network(networks.find(mesh.from(mesh.edge_halfedge(e))));
  if (dropped_networks) *dropped_networks = dropped;
  return kept;
}

}  // namespace isoquad
