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

double default_quad_count(std::size_t triangles) {
  double t = double(triangles);
  while (t > 0 && t < 8000) t *= 4;  // as if split 1-to-4 until there are 8,000 (subdivide_coarse)
  return std::clamp(t / 8.0, 1000.0, 20000.0);
}

ComponentSize component_size(const PreparedMesh& prep, uint32_t c, const SizeRequest& r) {
  double total_area = 0;
  std::size_t triangles = 0;
  for (const PreparedComponent& comp : prep.components) {
    triangles += comp.mesh.num_faces();
    if (comp.mesh.num_faces() >= kTriangleSplitBelowFaces) total_area += surface_area(comp.mesh);
  }
  const TriMesh& mesh = prep.components.at(c).mesh;
  ComponentSize s;
  if (mesh.num_faces() < kTriangleSplitBelowFaces) {
    s.area_share = 0;
    s.quads = 3.0 * mesh.num_faces();
    s.edge_length = edge_length_for_quads(mesh, s.quads);
    return s;
  }
  s.area_share = total_area > 0 ? surface_area(mesh) / total_area : 1.0;
  if (r.edge_length > 0) {
    s.edge_length = r.edge_length * prep.normalization.scale;
    return s;
  }
  s.quads = (r.quads > 0 ? r.quads : default_quad_count(triangles)) * s.area_share;
  s.edge_length = edge_length_for_quads(mesh, s.quads);
  return s;
}

}  // namespace isoquad
