// A TriMesh obtained from a base mesh by splitting edges, with the provenance of every face and
// vertex: which base face contains it and its barycentric coordinates there, so that any point
// computed later (a quad vertex) can be placed exactly on the input surface.
#pragma once

#include <array>
#include <vector>

#include "core/element_data.hpp"
#include "core/tri_mesh.hpp"

namespace isoquad {

// A point on the base mesh: a face and barycentric coordinates (summing to 1).
struct SurfacePoint {
  uint32_t face = kInvalid;
  std::array<double, 3> bary{};
};

struct RefinedMesh {
  TriMesh mesh;
  FaceData<uint32_t> base_face;                                // base face containing each face
  FaceData<std::array<std::array<double, 3>, 3>> corner_bary;  // each corner in its base face
  uint32_t base_vertices = 0;  // vertices [0, base_vertices) are the base mesh's, same ids

  // The base-mesh point of a vertex (through one of its faces).
  SurfacePoint vertex_origin(uint32_t v) const;
};

RefinedMesh identity_refinement(const TriMesh& base);

// Splits each listed edge at its midpoint; every triangle with split edges is divided (into 2,
// 3 or 4). New vertices are appended; old ids stay. Face data in `face_labels` is inherited by
// the pieces; edge flags in `edge_flags` are inherited by the two halves (new edges get 0).
RefinedMesh split_edges(const RefinedMesh& in, const std::vector<uint32_t>& edges,
                        FaceData<uint32_t>* face_labels, EdgeData<char>* edge_flags);

// A point inside an edge, at `fraction` from the start of the edge's halfedge.
struct EdgePoint {
  uint32_t edge;
  double fraction;
};

// A straight cut across one face between two points of its boundary: corners (vertex ids of
// `in`) or edge points (id num_vertices() + their index in `points`).
struct Chord {
  uint32_t face, a, b;
};

// Inserts the edge points (any number per edge) and cuts every face along its chords, which
// must not cross; each face's pieces (convex) are triangulated by ear clipping. New vertices are
// the points, appended in their order; every chord and every piece of a split edge is an edge
// of the result. Labels and edge flags are inherited as by split_edges.
RefinedMesh cut_along_chords(const RefinedMesh& in, const std::vector<EdgePoint>& points,
                             const std::vector<Chord>& chords, FaceData<uint32_t>* face_labels,
                             EdgeData<char>* edge_flags);

}  // namespace isoquad
