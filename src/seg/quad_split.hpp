// The last-resort layout repair (paper §5; DESIGN.md §5.4 step 3): make every patch four-sided,
// so that giving every meta-edge the same length satisfies every side equation. The paper pairs
// patches with an odd number of meta-vertices along dual paths and then cuts each patch into
// four-gons; here the meta-mesh gets one Catmull-Clark step instead, which needs no pairing: a
// meta-vertex at the middle of every meta-edge (shared by its two patches, so parity never
// arises), one at the centre of every patch, and the patch cut along vertex-disjoint shortest
// paths from its centre to its edge midpoints into as many sectors as it has sides. Every sector
// has four meta-vertices: the centre, two midpoints and the junction between them.
//
// Meta-vertices inserted only to give a patch four corners (valence 2 inside the surface) are
// dropped first where both their patches keep three junctions: after the split they would be
// corners on both sides, a vertex with two quads. Where a meta-edge has no vertex inside, or a
// patch no interior vertex to be its centre, the surface is refined (edges split at their
// midpoints, with provenance) and the cut is tried again.
//
// The paths come from a convex map of each patch (Floater's mean value map, the boundary on the
// unit circle with the side midpoints evenly spaced): seen from the centre (the interior vertex
// nearest the middle of the map) the rays to the midpoints are straight, leave in the sides'
// order and never meet. A patch is cut along mesh edges inside each ray's cell (the vertices
// nearer to it than to any other ray) when that fits; else along the rays themselves: the map
// is affine on each triangle, so a ray is straight on the surface too, and every edge it crosses
// gets a vertex there and every triangle it crosses a chord (core/refined_mesh.hpp). Rays never
// cross, so this always fits, on any surface and at any resolution; refinement is left for
// degenerate cases (a side of one edge, a patch without interior vertex, numerical trouble).
//
// Forced on at 1,500 quads it succeeds on all 19 corpus meshes (0.8-7 s end to end, the largest
// on bunny00), where the cheaper repairs are never needed. The result is valid but not pretty:
// the centres become singularities of valence 3 to 11 (one per side of the old patch).
#pragma once

#include <cstdint>

#include "seg/segment.hpp"

namespace isoquad {

struct QuadSplitReport {
  uint32_t patches_before = 0, patches_after = 0;
  uint32_t refinements = 0;       // midpoint refinements needed before the cut fitted
  uint32_t dropped_inserted = 0;  // valence-2 meta-vertices merged away first
};

// Rewrites `seg` (refined mesh, features, labels, meta-mesh with geodesic lengths) so that every
// patch is a disk with exactly four meta-vertices.
// \throw Error(layout, E403) if the cuts do not fit after 12 refinements or a million faces
// (not seen: only degenerate patches are refined).
void split_patches_into_quads(SegmentResult& seg, QuadSplitReport& report);

}  // namespace isoquad
