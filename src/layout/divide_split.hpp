// The dividing-edge split (paper §3.4 "3-connectedness"; DESIGN.md §3.3). Floater's theorem
// makes a convex-combination map of a disk onto a convex polygon one-to-one iff no interior edge
// with both ends on the boundary is mapped into the boundary. On a rectangle, such an edge can
// lie along a side, so every interior edge of a patch whose two ends are on the patch's
// boundary is split at its midpoint; the new vertex is interior.
#pragma once

#include <vector>

#include "core/refined_mesh.hpp"

namespace isoquad {

std::vector<uint32_t> dividing_edges(const TriMesh& mesh, const FaceData<uint32_t>& labels);

// Splits until none is left; labels and features follow. Returns the number of edges split.
uint32_t split_dividing_edges(RefinedMesh& refined, FaceData<uint32_t>& labels,
                              EdgeData<char>& feature);

}  // namespace isoquad
