// Segmentation stage (paper §3.1, first part of §3.4): VSA patches, repaired into disks, and the
// meta-mesh over them.
#pragma once

#include "layout/meta_mesh.hpp"
#include "layout/straighten.hpp"
#include "seg/disk_patches.hpp"
#include "seg/vsa.hpp"

namespace isoquad {

struct SegmentOptions {
  VsaOptions vsa;
  MetaMeshOptions meta;
  bool straighten = true;
};

struct SegmentResult {
  FaceData<uint32_t> labels;  // patch per face of the mesh
  uint32_t num_patches = 0;
  uint32_t vsa_patches = 0;   // before topology repair
  DiskRepairLog repair;
  StraightenLog straighten;
  MetaMesh meta;
  std::vector<double> energy_log;
};

// \throw Error(unsupported_topology, E201) or Error(layout, E301) as the steps do.
SegmentResult segment(const TriMesh& mesh, const EdgeData<char>& feature, const SegmentOptions& options);

}  // namespace isoquad
