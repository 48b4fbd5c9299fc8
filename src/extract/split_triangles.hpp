// Quads for a component too small for patches: every triangle split into three quads.
#pragma once

#include "core/tri_mesh.hpp"
#include "extract/extract.hpp"

namespace isoquad {

// Each triangle (a, b, c) becomes the quads (a, m_ab, g, m_ca), (b, m_bc, g, m_ab) and
// (c, m_ca, g, m_bc), with m the edge midpoints, shared by the triangles on an edge, and g the
// centroid: a conforming quad mesh of the triangles' surface and topology, oriented as they are.
// Quad 3f + i is at corner i of triangle f, and its patch is f. Vertices: the mesh's vertices,
// then one per edge, then one per face.
QuadMesh split_triangles_into_quads(const TriMesh& mesh);

}  // namespace isoquad
