// Variational Shape Approximation (Cohen-Steiner, Alliez, Desbrun 2004) with the L2,1 metric:
// the surface is split into K connected regions, each approximated by a plane (paper §3.1,
// DESIGN.md §2.1). Feature edges are flooding barriers; results are deterministic.
#pragma once

#include <cstdint>
#include <vector>

#include "core/element_data.hpp"
#include "core/tri_mesh.hpp"

namespace isoquad {

struct VsaOptions {
  uint32_t patches = 0;           // K; 0 chooses K from the error drop (bounded by the size)
  double target_edge_length = 0;  // h (mesh units); bounds K by area/(16 h^2) and sets the
                                  // smallest patch (2 h^2); 0: no size bound
  double compactness = 0.05;      // weight of the centroid-distance term (0: pure L2,1)
  double error_drop = 0.1;        // automatic K: stop when the error falls below this fraction
  uint32_t max_iterations = 100;  // Lloyd iterations after seeding
  uint32_t teleport_rounds = 3;
  uint64_t seed = 1;
};

struct Proxy {
  Vec3 normal;    // unit normal of the fitted plane
  Vec3 centroid;  // area-weighted centroid of the region
  uint32_t seed_face = kInvalid;
  double error = 0, area = 0;
};

struct Segmentation {
  FaceData<uint32_t> face_patch;   // patch id per face, 0..num_patches-1
  std::vector<Proxy> proxies;      // one per patch
  std::vector<double> energy_log;  // total error after every partition/fit iteration
  uint32_t num_patches() const { return static_cast<uint32_t>(proxies.size()); }
};

// \pre `barrier` has one entry per edge (1 = never flood across it; feature edges).
// Every region is connected and contains no barrier edge in its interior. Regions enclosed by
// barriers get a patch each even beyond K.
Segmentation segment_vsa(const TriMesh& mesh, const EdgeData<char>& barrier,
                         const VsaOptions& options);

// `labels` with each listed region cut in two by a two-proxy VSA inside it (the new parts get
// ids after the largest label).
FaceData<uint32_t> split_vsa_regions(const TriMesh& mesh, const EdgeData<char>& barrier,
                                     const FaceData<uint32_t>& labels,
                                     const std::vector<uint32_t>& regions,
                                     const VsaOptions& options);

// The L2,1 (+ compactness) energy of a labelling with its best-fit proxies.
double vsa_energy(const TriMesh& mesh, const FaceData<uint32_t>& labels, uint32_t num_patches,
                  double compactness);

}  // namespace isoquad
