// Segmentation stage (paper §3.1, first part of §3.4): VSA patches, repaired into disks, and the
// meta-mesh over them.
#pragma once

#include "core/refined_mesh.hpp"
#include "layout/meta_mesh.hpp"
#include "layout/straighten.hpp"
#include "seg/disk_patches.hpp"
#include "seg/tip_split.hpp"
#include "seg/vsa.hpp"

namespace isoquad {

struct SegmentOptions {
  VsaOptions vsa;
  MetaMeshOptions meta;
  bool straighten = true;
  // Surface vertices to make meta-vertices by cutting their patches into wedges
  // (seg/tip_split.hpp): tips an earlier run's quads cut off.
  std::vector<uint32_t> tips;
  // A VSA partition of this mesh with these options from an earlier call, used instead of
  // running VSA again (the tips change only what follows it).
  const FaceData<uint32_t>* vsa_labels = nullptr;
  // make_disk_patches's `piecewise` cut of non-disk patches (the pipeline's last alternatives).
  bool piecewise_disks = false;

  // The options for a target quad edge length h (mesh units): it bounds K and the smallest
  // patch, and sets the window of boundary-corner detection.
  static SegmentOptions sized(double h, uint32_t patches = 0, uint64_t seed = 1) {
    SegmentOptions o;
    o.vsa.patches = patches;
    o.vsa.seed = seed;
    o.vsa.target_edge_length = h;
    o.meta.corner_window = h;
    return o;
  }
};

struct SegmentResult {
  RefinedMesh refined;        // the input mesh after the dividing-edge split, with provenance
  EdgeData<char> feature;     // feature edges of the refined mesh
  FaceData<uint32_t> labels;  // patch per face of the refined mesh
  uint32_t num_patches = 0;
  uint32_t vsa_patches = 0;       // before topology repair
  FaceData<uint32_t> vsa_labels;  // VSA's partition, before topology repair
  DiskRepairLog repair;
  TipSplitLog tip_split;
  StraightenLog straighten;
  uint32_t dividing_splits = 0;  // edges split for 3-connectedness
  MetaMesh meta;                 // on the refined mesh; meta-edges carry geodesic lengths
  std::vector<double> energy_log;
};

// Sets every meta-edge's geodesic length (DESIGN.md §3.4): the shortest distance between its
// ends inside its one or two patches (facing sides measured alike, so the bias cancels).
void measure_geodesic_lengths(const TriMesh& mesh, const FaceData<uint32_t>& labels,
                              MetaMesh& meta);

// Runs VSA, topology repair, straightening, the meta-mesh, the dividing-edge split and the
// geodesic lengths. \throw Error(unsupported_topology, E201) or Error(layout, E301) as the
// steps do.
SegmentResult segment(const TriMesh& mesh, const EdgeData<char>& feature,
                      const SegmentOptions& options);

}  // namespace isoquad
