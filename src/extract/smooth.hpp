// Tangential smoothing of an extracted quad mesh (DESIGN.md §8.2 step 5): every free vertex
// moves towards the average of its neighbours and is projected back onto the input surface by a
// local closest-point search that starts from its current face (a global search could jump to
// another sheet in thin parts). Vertices on feature or mesh-boundary meta-edges, the
// meta-vertices at their ends and the vertices given as pinned stay; other meta-vertices move. A
// move is taken only if the local guard allows it (extract/surface_guard.hpp): no quad around the
// vertex ends below min(its scaled Jacobian before, `min_sj`), against its own normal or the
// surface normal at its corners, so no quad is folded and good quads are not damaged; no surface
// vertex ends farther from the quads than it was or `far`, and the quads' sample points end within
// `far` of the surface, so the smoothing does not cut off what the quads reached (quads farther
// than `far` already stay as they are).
#pragma once

#include <vector>

#include "extract/extract.hpp"
#include "layout/meta_mesh.hpp"
#include "metrics/aabb_tree.hpp"

namespace isoquad {

struct SmoothOptions {
  uint32_t iterations = 0;  // sweeps over the vertices, in vertex order
  double edge_length = 0;   // the target quad edge h (mesh units): the unit of `far`
  double far = 0.1;         // the distance a move may leave between the quads and the surface
  double min_sj = 0.2;      // no quad's scaled Jacobians fall below min(before, this)
};

struct SmoothReport {
  uint32_t iterations = 0, moves = 0, rejected = 0;
  double seconds = 0;
};

// `surface_tree`, if given, is a tree of base's faces in order (face_triangles); built here
// otherwise. `pinned`: further vertices that stay (the corners the tip snapping put onto tips).
// \pre every quad corner's SurfacePoint is on `base`; options.edge_length > 0.
void smooth_quads(QuadMesh& quads, const TriMesh& base, const MetaMesh& meta,
                  const SmoothOptions& options, SmoothReport& report,
                  const AabbTree* surface_tree = nullptr, const std::vector<uint32_t>& pinned = {});

}  // namespace isoquad
