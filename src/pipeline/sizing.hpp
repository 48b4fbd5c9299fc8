// The target quad size h, from what the user asks for.
#pragma once

#include "core/tri_mesh.hpp"

namespace isoquad {

double surface_area(const TriMesh& mesh);

// h such that the surface holds about `quads` squares of side h: sqrt(area / quads).
double edge_length_for_quads(const TriMesh& mesh, double quads);

// The quad count used when neither a count nor an edge length is given: one quad per 8 input
// triangles, clamped to [1000, 20000].
double default_quad_count(const TriMesh& mesh);

// The edge length h (in the mesh's units) for one component of a mesh: from an explicit length
// (given in input units, converted by `scale`), or from a quad count shared out by area.
struct SizeRequest {
  double edge_length = 0;  // input units; 0: use quads
  double quads = 0;        // for the whole mesh; 0: the default for each component
};
double component_edge_length(const TriMesh& component, double component_share,
                             const SizeRequest& request, double scale);

}  // namespace isoquad
