// The meta-mesh (paper §2, §3.3; DESIGN.md §3.1): meta-vertices where three or more patches meet
// (plus junctions and corners on the mesh boundary, plus inserted ones), meta-edges as vertex
// paths between them with their left and right patch, and meta-faces as CCW cycles of
// meta-edges. It is a multigraph: two patches may share several meta-edges.
#pragma once

#include <cstdint>
#include <vector>

#include "core/element_data.hpp"
#include "core/tri_mesh.hpp"

namespace isoquad {

struct MetaVertex {
  uint32_t vertex = kInvalid;           // mesh vertex
  bool on_boundary = false;             // on the mesh boundary
  bool inserted = false;                // added to give a patch 4 corners (or on request)
  std::vector<uint32_t> wedge_patches;  // patches around it, CCW
};

struct MetaEdge {
  uint32_t mv0 = kInvalid, mv1 = kInvalid;
  std::vector<uint32_t> vertices;   // mesh vertices from mv0 to mv1
  std::vector<uint32_t> halfedges;  // in `left`: vertices[i] -> vertices[i+1]
  uint32_t left = kInvalid;         // the patch on the left of mv0 -> mv1
  uint32_t right = kInvalid;        // the other patch; kInvalid on the mesh boundary
  bool feature = false;             // every mesh edge on it is a feature edge
  double length = 0;                // length of the polyline
  double geodesic = 0;              // shortest distance between its ends inside its patches
};

struct BoundaryItem {
  uint32_t edge;
  bool forward;  // the patch is the edge's left patch
};

struct MetaFace {
  uint32_t patch;
  std::vector<BoundaryItem> cycle;  // CCW, patch on the left; item i starts at a meta-vertex
  uint32_t start_vertex(std::size_t i, const std::vector<MetaEdge>& edges) const {
    const MetaEdge& e = edges[cycle[i].edge];
    return cycle[i].forward ? e.mv0 : e.mv1;
  }
};

struct MetaMesh {
  std::vector<MetaVertex> vertices;
  std::vector<MetaEdge> edges;
  std::vector<MetaFace> faces;              // face p is patch p
  VertexData<uint32_t> vertex_meta_vertex;  // mesh vertex -> meta-vertex, or kInvalid
  VertexData<uint32_t> vertex_meta_edge;  // seam vertex that is not a meta-vertex -> its meta-edge
  uint32_t inserted = 0;                  // meta-vertices inserted to reach 4 per patch
  std::vector<uint32_t> inserted_vertices;  // their mesh vertices (pass as `forced` to rebuild)
  int64_t euler() const {
    return int64_t(vertices.size()) - int64_t(edges.size()) + int64_t(faces.size());
  }
};

struct MetaMeshOptions {
  double boundary_corner_deg = 45;  // a boundary stretch turning more than this holds a corner
  double corner_window = 0;         // arc length over which turning is summed (0: 3 mean edges)
  uint32_t min_corners = 4;         // meta-vertices per patch (inserted where fewer)
  std::vector<uint32_t> forced;     // mesh vertices that are meta-vertices whatever the wedges
};

// \pre every patch is a disk and not pinched (make_disk_patches).
// Inserts meta-vertices (at seam vertices) until every patch has options.min_corners.
// \throw Error(layout, E301) when a patch has too few seam vertices to take them.
MetaMesh build_meta_mesh(const TriMesh& mesh, const FaceData<uint32_t>& labels,
                         uint32_t num_patches, const EdgeData<char>& feature,
                         const MetaMeshOptions& options = {});

// Checks the invariants (every meta-edge a simple path between two distinct patches, cycles
// closed and consistent, chi equal to the mesh's); throws Error(internal) naming the first
// violation.
void check_meta_mesh(const TriMesh& mesh, const FaceData<uint32_t>& labels, const MetaMesh& meta);

}  // namespace isoquad
