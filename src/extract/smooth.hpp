// Optional tangential smoothing of an extracted quad mesh (DESIGN.md §8.2 step 5): every free
// vertex moves towards the average of its neighbours and is projected back onto the input
// surface by a local closest-point search that starts from its current face (a global search
// could jump to another sheet in thin parts). Meta-vertices and vertices on feature or
// mesh-boundary meta-edges stay. A move is taken only if the smallest scaled Jacobian of the
// quads around the vertex does not drop below min(its old value, 0.2), so folds are undone and
// good quads are not damaged.
#pragma once

#include <vector>

#include "extract/extract.hpp"
#include "layout/meta_mesh.hpp"

namespace isoquad {

struct SmoothReport {
  uint32_t iterations = 0, moves = 0, rejected = 0;
  double seconds = 0;
};

void smooth_quads(QuadMesh& quads, const TriMesh& base, const MetaMesh& meta, uint32_t iterations,
                  SmoothReport& report);

}  // namespace isoquad
