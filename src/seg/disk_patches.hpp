// Topology repair of a segmentation (paper §3.1 "patches should be cut into subpatches
// homeomorphic to disks"; DESIGN.md §2.2): afterwards every patch is connected, a disk, and not
// pinched (no vertex sees the same patch in two wedges).
#pragma once

#include <cstdint>

#include "core/element_data.hpp"
#include "core/tri_mesh.hpp"

namespace isoquad {

struct DiskRepairLog {
  uint32_t disconnected_split = 0;  // labels that fell apart and became several patches
  uint32_t pinches_fixed = 0;       // wedges relabelled
  uint32_t voronoi_splits = 0;      // non-disk patches split into disks by geodesic Voronoi cells
  uint32_t two_path_cuts = 0;       // patches with holes cut along two paths
  uint32_t tiny_merged = 0;         // patches too small for four corners, merged into a neighbour
  uint32_t islands_merged = 0;      // disks inside a hole of a patch (a narrow ring round them)
  uint32_t strips_cut = 0;          // strips from a small hole to the outer loop
  uint32_t handles_cut = 0;         // rings cut off round a handle inside a patch
  uint32_t rounds = 0;
};

// Relabels in place and returns the new number of patches (labels 0..n-1, ordered by first face).
// \throw Error(unsupported_topology, E201) if a patch cannot be made a disk.
// `piecewise`: where no Voronoi split of a patch gives only disks, keep the one whose non-disk
// cells are smallest and cut those again in the next round (a handle or a hole far smaller than
// a cell); otherwise E201, which the field layout takes as a traced layout to pass over.
uint32_t make_disk_patches(const TriMesh& mesh, FaceData<uint32_t>& labels, DiskRepairLog& log,
                           bool piecewise = false);

// Renumbers labels 0..n-1 in order of first face; returns n.
uint32_t compact_labels(FaceData<uint32_t>& labels);

}  // namespace isoquad
