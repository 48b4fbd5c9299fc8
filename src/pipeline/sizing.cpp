#include "pipeline/sizing.hpp"

#include <algorithm>
#include <cmath>

namespace isoquad {

double surface_area(const TriMesh& mesh) {
  double a = 0;
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) a += mesh.face_area(f);
  return a;
}

double edge_length_for_quads(const TriMesh& mesh, double quads) {
  return std::sqrt(surface_area(mesh) / std::max(quads, 1.0));
}

double default_quad_count(std::size_t triangles, double share) {
  return std::clamp(double(triangles) / 8.0, 1000.0 * share, 20000.0 * share);
}

ComponentSize component_size(const PreparedMesh& prep, uint32_t c, const SizeRequest& r) {
  double total_area = 0;
  std::size_t triangles = 0;  // of the components that take a share
  for (const PreparedComponent& comp : prep.components) {
    if (comp.mesh.num_faces() < kTriangleSplitBelowFaces) continue;
    triangles += comp.mesh.num_faces();
    total_area += surface_area(comp.mesh);
  }
  const TriMesh& mesh = prep.components.at(c).mesh;
  ComponentSize s;
  if (mesh.num_faces() < kTriangleSplitBelowFaces) {
    s.area_share = 0;
    s.edge_length = edge_length_for_quads(mesh, 3.0 * mesh.num_faces());
    return s;
  }
  s.area_share = total_area > 0 ? surface_area(mesh) / total_area : 1.0;
  if (r.edge_length > 0) {
    s.edge_length = r.edge_length * prep.normalization.scale;
    return s;
  }
  s.quads = r.quads > 0 ? r.quads * s.area_share : 0;
  s.edge_length = edge_length_for_quads(
      mesh, r.quads > 0 ? s.quads : default_quad_count(triangles) * s.area_share);
  return s;
}

}  // namespace isoquad
