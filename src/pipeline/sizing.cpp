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

double default_quad_count(const TriMesh& mesh) {
  return std::clamp(mesh.num_faces() / 8.0, 1000.0, 20000.0);
}

double component_edge_length(const TriMesh& component, double share, const SizeRequest& r,
                             double scale) {
  if (r.edge_length > 0) return r.edge_length * scale;
  const double quads = r.quads > 0 ? r.quads * share : default_quad_count(component);
  return edge_length_for_quads(component, quads);
}

}  // namespace isoquad
