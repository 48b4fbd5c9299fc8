// Seam straightening (paper §3.4 "convert the boundary to use these edges"; DESIGN.md §3.2).
// VSA seams are staircases. Two relabelling passes make them shorter and straighter while every
// patch stays a disk and the meta-mesh keeps its topology:
//  1. ears: a face with two edges on the same seam joins the other patch (the paper's rule);
//  2. geodesic: a seam between two junctions is replaced by the shortest path inside the two
//     patches, when that keeps both disks.
// Feature seams and the mesh boundary are never moved. No seam ever gets longer.
#pragma once

#include <cstdint>

#include "core/element_data.hpp"
#include "core/tri_mesh.hpp"

namespace isoquad {

struct StraightenLog {
  uint32_t ears = 0;                                     // faces relabelled by the ear rule
  uint32_t geodesic = 0;                                 // seams replaced by shortest paths
  double seam_length_before = 0, seam_length_after = 0;  // interior, non-feature seams
};

// \pre every patch is a disk (make_disk_patches).
void straighten_seams(const TriMesh& mesh, FaceData<uint32_t>& labels, uint32_t num_patches,
                      const EdgeData<char>& feature, StraightenLog& log);

// Total length of mesh edges between two different patches that are not feature edges.
double seam_length(const TriMesh& mesh, const FaceData<uint32_t>& labels,
                   const EdgeData<char>& feature);

}  // namespace isoquad
