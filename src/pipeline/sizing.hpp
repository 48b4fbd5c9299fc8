// The target quad size h, from what the user asks for.
#pragma once

#include <cstddef>

#include "core/tri_mesh.hpp"
#include "prep/prepare.hpp"

namespace isoquad {

double surface_area(const TriMesh& mesh);

// h such that the surface holds about `quads` squares of side h: sqrt(area / quads).
double edge_length_for_quads(const TriMesh& mesh, double quads);

// The quad count used when neither a count nor an edge length is given: one quad per 8
// triangles, clamped to [1000, 20000], where an input under 8,000 triangles counts as if split
// 1-to-4 until it has 8,000 (as subdivide_coarse refines it: 1,000 to 4,000 quads). This is the
// count single meshes got when the layout re-took the default on the subdivided surface (the cow
// 3,119 quads, not 1,000, at which it folds); now it is one budget for all the components.
double default_quad_count(std::size_t triangles);

// A component with fewer faces than four patches of three faces each (the smallest patch the
// segmentation keeps, seg/disk_patches.cpp) is not segmented: each of its triangles is split
// into three quads (extract/split_triangles.hpp), and it takes no share of the count. Such
// components were dropped before (under 10 faces: a tetrahedron beside a sphere, a lone
// triangle).
constexpr uint32_t kTriangleSplitBelowFaces = 12;

// What the user asks for, for the whole mesh.
struct SizeRequest {
  double edge_length = 0;  // input units; 0: use quads
  double quads = 0;        // for the whole mesh; 0: default_quad_count of all its triangles
};

// One component's part of a request: the quad count is one budget for the whole mesh, shared
// out by area among the components not split into quads (with the default count too: per component,
// 18 components of 76 triangles each asked for 1,000 quads, and 43,745 in all after the layout's
// own default on the subdivided surface).
struct ComponentSize {
  double area_share = 1;   // of the surface of the components not split into quads (0 if split)
  double quads = 0;        // its share of the count; 0 with an edge length
  double edge_length = 0;  // h in the mesh's (normalized) units
};
ComponentSize component_size(const PreparedMesh& prep, uint32_t component,
                             const SizeRequest& request);

}  // namespace isoquad
