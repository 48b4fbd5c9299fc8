// Tip splits (beyond the paper): a patch is cut into wedges at a tip of the surface, so that the
// tip becomes a meta-vertex. A harmonic map crowds a thin protrusion inside a patch (a horn, a
// toe) into a small corner of its rectangle, where no integer line reaches the tip, and the
// quads cut it off; a meta-vertex is always a lattice point, so the quads reach it.
//
// At a tip inside one patch, the patch is cut into three wedges of equal angle at the tip; at a
// tip on a seam between two patches, the larger is cut in two. Either way three patches meet
// at the tip. Each wedge is the set of the patch's faces whose nearest face of the tip's fan
// (face Dijkstra between centroids inside the patch) lies in that wedge's angular sector: the
// geodesic wedges from the tip, connected by construction. A tip on the mesh boundary is only
// listed, to be forced a meta-vertex (MetaMeshOptions::forced); a tip where three patches meet
// already is left alone.
#pragma once

#include <cstdint>
#include <vector>

#include "core/element_data.hpp"
#include "core/tri_mesh.hpp"

namespace isoquad {

struct TipSplitLog {
  uint32_t tips = 0;               // tips asked for
  uint32_t split = 0;              // tips that became junctions of three patches
  std::vector<uint32_t> boundary;  // tips on the mesh boundary, to be forced meta-vertices
};

// Relabels `labels` in place; new patches get labels from `num_patches` on, which is raised.
// Deterministic: tips in the order given, sectors from each tip's first outgoing halfedge.
// \pre every tip is a vertex of `mesh`; labels hold patch ids below num_patches.
void split_patches_at_tips(const TriMesh& mesh, const std::vector<uint32_t>& tips,
                           FaceData<uint32_t>& labels, uint32_t& num_patches, TipSplitLog& log);

}  // namespace isoquad
