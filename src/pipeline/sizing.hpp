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
// triangles, clamped to [1000, 20000] times `share`, the part of the input's area they cover.
// Taken twice: on the whole input, for the size h shared out by area (component_size), at which
// a coarse component is split 1-to-4 until it has 8 triangles per quad (subdivide_coarse); then
// by the layout, on the surface it works on, with the component's share
// (LayoutOptions::default_share). So an input under 8,000 triangles gets a quad per 8 of its
// triangles as if split 1-to-4 until it has 8,000 (the cow 2,902, not 1,000, at which it folds),
// and 18 spheres of 80 triangles 160 quads each, where each component's own count asked for at
// least 1,000 (1,368 triangles in 18 components: 43,745 quads in all).
double default_quad_count(std::size_t triangles, double share = 1);

// A component with fewer faces than four patches of three faces each (the smallest patch the
// segmentation keeps, seg/disk_patches.cpp) is not segmented: each of its triangles is split
// into three quads (extract/split_triangles.hpp), and it takes no share of the count. Such
// components were dropped before (under 10 faces: a tetrahedron beside a sphere, a lone
// triangle).
constexpr uint32_t kTriangleSplitBelowFaces = 12;

// What the user asks for, for the whole mesh.
struct SizeRequest {
  double edge_length = 0;  // input units; 0: use quads
  double quads = 0;        // for the whole mesh; 0: the default (default_quad_count)
};

// One component's part of a request: a quad count, given or the default, is one budget for the
// whole mesh, shared out by area among the components not split into quads.
struct ComponentSize {
  double area_share = 1;   // of the surface of the components not split into quads (0 if split)
  double quads = 0;        // its share of a count asked for; 0 at the default size or with a length
  double edge_length = 0;  // h in the mesh's (normalized) units
};
ComponentSize component_size(const PreparedMesh& prep, uint32_t component,
                             const SizeRequest& request);

}  // namespace isoquad
