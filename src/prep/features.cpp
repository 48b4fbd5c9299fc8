#include <cmath>
#include <numbers>

#include "prep/steps.hpp"

namespace isoquad::prep {

EdgeData<char> mark_features(const TriMesh& mesh, double feature_angle_deg) {
  EdgeData<char> feature(mesh.num_edges(), 0);
  if (feature_angle_deg <= 0) return feature;
  const double cos_limit = std::cos(feature_angle_deg * std::numbers::pi / 180.0);
  for (uint32_t e = 0; e < mesh.num_edges(); ++e) {
    const uint32_t h = mesh.edge_halfedge(e);
    if (mesh.is_boundary_halfedge(h)) continue;
    const Vec3 n0 = mesh.face_normal(TriMesh::face_of(h));
    const Vec3 n1 = mesh.face_normal(TriMesh::face_of(mesh.twin(h)));
    if (squared_norm(n0) == 0 || squared_norm(n1) == 0) continue;  // degenerate face: no angle
    // The dihedral angle between the normals exceeds the limit iff their cosine is below it.
    if (dot(n0, n1) < cos_limit) feature[e] = 1;
  }
  return feature;
}

}  // namespace isoquad::prep
