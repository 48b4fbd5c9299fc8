// TriMesh: the immutable, index-based directed-edge triangle mesh every stage works on
// (DESIGN.md §0.4, Instant Meshes' dedge layout). Halfedge h = 3f + i runs from corner i of
// face f to corner (i+1)%3; next/prev are implicit. A mesh is rebuilt, never mutated.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/element_data.hpp"
#include "core/vec.hpp"

namespace isoquad {

using Tri = std::array<uint32_t, 3>;

class TriMesh {
 public:
  TriMesh() = default;
  // \pre faces are consistently oriented, every edge has at most two faces (opposite
  //      directions), every vertex has at least one face and a single fan, indices in range.
  // \throw Error(invalid_input, E100) naming the offending vertices or faces otherwise.
  TriMesh(std::vector<Vec3> positions, std::vector<Tri> faces);
  // The same connectivity (vertex, face, halfedge and edge ids) at other positions, without
  // rebuilding it (a smoothed copy). \pre positions.size() == num_vertices().
  // \throw Error(internal, E700) if the count differs.
  TriMesh with_positions(std::vector<Vec3> positions) const;

  uint32_t num_vertices() const { return static_cast<uint32_t>(positions_.size()); }
  uint32_t num_faces() const { return static_cast<uint32_t>(faces_.size()); }
  uint32_t num_halfedges() const { return 3 * num_faces(); }
  uint32_t num_edges() const { return static_cast<uint32_t>(edge_halfedge_.size()); }

  const Vec3& position(uint32_t v) const { return positions_[v]; }
  const std::vector<Vec3>& positions() const { return positions_; }
  const Tri& face(uint32_t f) const { return faces_[f]; }
  const std::vector<Tri>& faces() const { return faces_; }

  static uint32_t face_of(uint32_t h) { return h / 3; }
  static uint32_t next(uint32_t h) { return h % 3 == 2 ? h - 2 : h + 1; }
  static uint32_t prev(uint32_t h) { return h % 3 == 0 ? h + 2 : h - 1; }
  uint32_t from(uint32_t h) const { return faces_[h / 3][h % 3]; }
  uint32_t to(uint32_t h) const { return faces_[h / 3][(h % 3 + 1) % 3]; }
  uint32_t twin(uint32_t h) const { return twin_[h]; }  // kInvalid on the mesh boundary
  bool is_boundary_halfedge(uint32_t h) const { return twin_[h] == kInvalid; }

  uint32_t edge(uint32_t h) const { return halfedge_edge_[h]; }
  uint32_t edge_halfedge(uint32_t e) const {
    return edge_halfedge_[e];
  }  // the side that has a face
  bool is_boundary_edge(uint32_t e) const { return is_boundary_halfedge(edge_halfedge_[e]); }

  // An outgoing halfedge of v; for a boundary vertex the one on the boundary, so that
  // for_each_outgoing visits the whole fan.
  uint32_t outgoing(uint32_t v) const { return outgoing_[v]; }
  bool is_boundary_vertex(uint32_t v) const { return is_boundary_halfedge(outgoing_[v]); }

  // Visits the outgoing halfedges of v in CCW order (seen from outside), starting at
  // outgoing(v). The one traversal of a vertex's fan in the code base.
  template <class Fn>
  void for_each_outgoing(uint32_t v, Fn&& fn) const {
    const uint32_t start = outgoing_[v];
    uint32_t h = start;
    do {
      fn(h);
      h = twin_[prev(h)];
    } while (h != kInvalid && h != start);
  }
  uint32_t valence(uint32_t v) const;  // number of incident edges

  // Boundary loops as halfedge cycles following the face orientation (the hole on the right).
  const std::vector<std::vector<uint32_t>>& boundary_loops() const { return boundary_loops_; }

  // Connected components (through shared edges).
  uint32_t num_components() const { return static_cast<uint32_t>(component_topology_.size()); }
  uint32_t component_of_face(uint32_t f) const { return face_component_[f]; }
  uint32_t component_of_vertex(uint32_t v) const { return face_component_[face_of(outgoing_[v])]; }
  struct ComponentTopology {
    uint32_t vertices = 0, edges = 0, faces = 0, boundary_loops = 0;
    int64_t euler() const { return int64_t(vertices) - int64_t(edges) + int64_t(faces); }
    // Orientable genus from chi = 2 - 2g - b.
    int64_t genus() const { return (2 - euler() - int64_t(boundary_loops)) / 2; }
  };
  const std::vector<ComponentTopology>& components() const { return component_topology_; }
  int64_t euler_characteristic() const {
    return int64_t(num_vertices()) - int64_t(num_edges()) + int64_t(num_faces());
  }

  Vec3 face_normal(uint32_t f) const;  // unit normal (zero for a degenerate face)
  double face_area(uint32_t f) const;
  Box3 bounding_box() const;

 private:
  std::vector<Vec3> positions_;
  std::vector<Tri> faces_;
  std::vector<uint32_t> twin_;
  std::vector<uint32_t> halfedge_edge_;
  std::vector<uint32_t> edge_halfedge_;
  std::vector<uint32_t> outgoing_;
  std::vector<std::vector<uint32_t>> boundary_loops_;
  std::vector<uint32_t> face_component_;
  std::vector<ComponentTopology> component_topology_;
};

}  // namespace isoquad
