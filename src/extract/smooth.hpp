// Optional tangential smoothing of an extracted quad mesh (DESIGN.md §8.2 step 5): every free
// vertex moves towards the average of its neighbours and is projected back onto the input
// surface by a local closest-point search that starts from its current face (a global search
// could jump to another sheet in thin parts). Meta-vertices and vertices on feature or
// mesh-boundary meta-edges stay. A move is taken only if the smallest scaled Jacobian of the
// quads around the vertex (against their own normal and, given the surface's tree, at each
// corner against the surface normal) does not drop below min(its old value, 0.2), so no quad is
// folded and good quads are not damaged.
#pragma once

#include <vector>

#include "extract/extract.hpp"
#include "layout/meta_mesh.hpp"
#include "metrics/aabb_tree.hpp"

namespace isoquad {

struct SmoothReport {
  uint32_t iterations = 0, moves = 0, rejected = 0;
  double seconds = 0;
};

// `surface_tree`, if given, is a tree of base's faces in order (face_triangles): the guard then
// also takes each corner's scaled Jacobian against the surface normal there (as `isoquad
// quality` and the untangler take it), so no move folds a quad against the surface.
void smooth_quads(QuadMesh& quads, const TriMesh& base, const MetaMesh& meta, uint32_t iterations,
                  SmoothReport& report, const AabbTree* surface_tree = nullptr);

}  // namespace isoquad
