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
// patch no interior vertex to be its centre, the surface is refined (every edge split at its
// midpoint, with provenance); where a centre has too few neighbours for its paths, the edges
// opposite it are split; then the cut is tried again.
//
// Not yet always successful, as the paper's repair would be: the paths are found one after the
// other (each leaving the centre between the previous one and the first, in the targets' order,
// from each start in turn), and on some patches they still block each other however fine the
// surface. Forced on at 1,500 quads it succeeds on sphere, cactus, cow, fandisk and
// mesh_with_border and fails (E403) on bunny00, eight, nefertiti, rotor and a synthetic torus
// with 8 patches. No corpus mesh needs it: the cheaper repairs always succeed there.
#pragma once

#include <cstdint>

#include "seg/segment.hpp"

namespace isoquad {

struct QuadSplitReport {
  uint32_t patches_before = 0, patches_after = 0;
  uint32_t refinements = 0;       // whole-surface midpoint splits needed to fit the cuts
  uint32_t dropped_inserted = 0;  // valence-2 meta-vertices merged away first
};

// Rewrites `seg` (refined mesh, features, labels, meta-mesh with geodesic lengths) so that every
// patch is a disk with exactly four meta-vertices.
// \throw Error(layout, E403) if the cuts do not fit after eight refinements.
void split_patches_into_quads(SegmentResult& seg, QuadSplitReport& report);

}  // namespace isoquad
