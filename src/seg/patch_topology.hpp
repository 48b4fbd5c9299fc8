// Topology of patches (sets of faces with one label): counts, boundary loops, disk test, wedges
// and pinches (DESIGN.md §2.2a-b).
#pragma once

#include <cstdint>
#include <vector>

#include "core/element_data.hpp"
#include "core/tri_mesh.hpp"

namespace isoquad {

struct PatchTopology {
  uint32_t faces = 0, vertices = 0, edges = 0, boundary_loops = 0;
  uint32_t boundary_edges = 0;  // halfedges of the patch on its boundary
  int64_t euler() const { return int64_t(vertices) - int64_t(edges) + int64_t(faces); }
  // A disk: connected, one boundary loop, chi = 1 (a pinched patch has two loops).
  bool is_disk() const { return faces > 0 && boundary_loops == 1 && euler() == 1; }
};

std::vector<PatchTopology> patch_topology(const TriMesh& mesh, const FaceData<uint32_t>& labels,
                                          uint32_t num_patches);

// The same for a few patches, given all their faces; O(faces) plus a clear of scratch
// arrays, instead of a pass over the whole mesh.
std::vector<PatchTopology> local_patch_topology(const TriMesh& mesh,
                                                const FaceData<uint32_t>& labels,
                                                const std::vector<uint32_t>& faces,
                                                const std::vector<uint32_t>& patches);

// The boundary halfedge of h's patch that follows h (patch on the left); h must be a boundary
// halfedge of its patch (its twin in another patch or on the mesh boundary).
uint32_t next_patch_boundary_halfedge(const TriMesh& mesh, const FaceData<uint32_t>& labels,
                                      uint32_t h);
bool is_patch_boundary(const TriMesh& mesh, const FaceData<uint32_t>& labels, uint32_t h);

// The angle of h's face at h's start vertex.
double corner_angle(const TriMesh& mesh, uint32_t h);

// Sum of the face angles at v over the faces of patch p (over every face if p is kInvalid).
double patch_angle(const TriMesh& mesh, const FaceData<uint32_t>& labels, uint32_t v, uint32_t p);

// Maximal runs of equal labels around a vertex, in CCW order.
struct Wedge {
  uint32_t patch;
  std::vector<uint32_t> faces;
};
std::vector<Wedge> wedges_at(const TriMesh& mesh, const FaceData<uint32_t>& labels, uint32_t v);
// The number of wedges at v, without building them.
uint32_t wedge_count(const TriMesh& mesh, const FaceData<uint32_t>& labels, uint32_t v);

}  // namespace isoquad
