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

}  // namespace isoquad
