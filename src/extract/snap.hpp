// Tip snapping after extraction and untangling (beyond the paper): the quads' corners lie on the
// input surface, but where the map spreads a thin protrusion (a toe, a horn's tip, a corner of
// an open scan's boundary) over few lattice points, no corner lands on its tip and the quads cut
// it off. Every surface vertex farther than `far` (in h) from the quads is such a tip; nearby
// quad corners are moved onto it (or halfway, or a quarter of the way), walking over the
// surface from where they are, so they stay on the sheet they were on. A move is taken only if
// the distance between the surface and the quads it changes drops (both ways: surface
// vertices to the quads and points of the moved quads to the surface), no surface vertex near
// them ends farther than max(its distance before, `far`), and no moved quad's scaled Jacobian,
// against the surface or against its own normal, falls below min(its value before, `min_sj`),
// so no fold is made. Vertices on creases and the mesh boundary move only onto tips on their own
// crease or boundary (so they stay on it); meta-vertices where creases or the boundary meet stay.
// Deterministic: tips in order of distance, then vertex id.
#pragma once

#include <cstdint>
#include <vector>

#include "extract/extract.hpp"
#include "layout/meta_mesh.hpp"
#include "metrics/aabb_tree.hpp"

namespace isoquad {

struct SnapOptions {
  double edge_length = 0;  // the target quad edge h (mesh units): the unit of the two below
  double far = 0.25;       // surface vertices farther than this from the quads are tips
  double reach = 2.5;      // a quad corner is moved onto a tip at most this far away
  double min_sj = 0.2;     // no moved quad's scaled Jacobians fall below min(before, this)
};

struct SnapReport {
  uint32_t tips = 0;     // surface vertices farther than `far` from the quads, before
  uint32_t gaps = 0;     // quads with a triangle centroid farther than `far` from the surface
  uint32_t snapped = 0;  // moves taken
  std::vector<uint32_t> moved;  // the vertices moved, in order (a vertex once per move)
  uint32_t left = 0;            // tips still farther than `far` after
  double farthest_before = 0, farthest_after = 0;  // largest surface-vertex distance (mesh units)
  double seconds = 0;
};

// `base` is the surface the quads' SurfacePoints refer to; `seams` the mesh whose vertices the
// meta-edges list (base with its dividing edges split); `base_tree`, if given, a tree of base's
// faces in order (face_triangles), built here otherwise.
// \pre every quad corner's SurfacePoint is on `base`; options.edge_length > 0.
void snap_tips(QuadMesh& quads, const TriMesh& base, const TriMesh& seams, const MetaMesh& meta,
               const SnapOptions& options, SnapReport& report, const AabbTree* base_tree = nullptr);

}  // namespace isoquad
