// The steps of prepare(), in the order it runs them. Internal to src/prep.
#pragma once

#include <vector>

#include "prep/prepare.hpp"

namespace isoquad::prep {

// A directed edge as a hash key, for the halfedge maps of the steps that change triangles.
inline uint64_t edge_key(uint32_t from, uint32_t to) { return uint64_t(from) << 32 | to; }

// Triangles over a working vertex set that remembers where everything came from.
struct Soup {
  std::vector<Vec3> positions;         // per working vertex
  std::vector<uint32_t> vertex_input;  // working vertex -> input vertex
  std::vector<Tri> tris;
  std::vector<uint32_t> tri_input;  // triangle -> input face
};

// Input vertex -> representative input vertex (itself if not welded). Only vertices on the
// soup's boundary are welded unless `all`; `eps` is an absolute distance (0: exact duplicates).
std::vector<uint32_t> weld_map(const PolyMesh& soup, bool all, double eps, uint32_t& welded);

// What a weld may change: the Euler characteristic of the soup's faces (polygons; those that
// collapse left out) and its boundary loops, counted as connected sets of boundary edges.
struct WeldTopology {
  int64_t euler = 0;
  uint32_t boundary_loops = 0;
  bool operator==(const WeldTopology&) const = default;
};
WeldTopology weld_topology(const PolyMesh& soup, const std::vector<uint32_t>& weld);

// Applies the weld, drops faces that collapse, triangulates polygons, drops unused vertices.
Soup triangulate(const PolyMesh& soup, const std::vector<uint32_t>& weld, InputReport& report);

void drop_duplicate_faces(Soup& soup, InputReport& report);

// Non-manifold edges (rejected, or detached with options.repair) and non-manifold vertices
// (always split, one copy per fan). Afterwards every edge has one or two faces and every vertex
// one fan.
void make_manifold(Soup& soup, const PrepOptions& options, InputReport& report);

struct SoupComponent {
  std::vector<uint32_t> tris;
  bool orientable = true;
  uint32_t conflict_a = 0, conflict_b = 0;  // input vertices of an edge where orientation conflicts
};
// Splits into components and orients each consistently (outward when closed).
std::vector<SoupComponent> orient_components(Soup& soup, InputReport& report);

// Counts V, E, F and boundary loops of a component straight from its triangles.
ComponentReport combinatorial_topology(const Soup& soup, const std::vector<uint32_t>& tris);

// Delaunay flips of needles inside flat regions: an edge between two triangles, one of them
// with an angle under 10 degrees, is replaced by the other diagonal of their quad when that is
// Delaunay (the angles opposite the edge sum to more than pi), the quad is convex and its two
// diagonals pass within `tolerance` of each other (the most the flip can move the surface).
// CAD exports triangulate each planar face as fans of needles across it, and segments,
// patches and quads then follow the needles. Returns the number of flips; the vertices stay,
// so the surface does too (within `tolerance`).
// The flatness flip_flat_edges asks of prepared components (unit bounding-box diagonal): planar
// faces of CAD exports, written in single precision, are flat to about that.
constexpr double kFlatTolerance = 1e-7;
uint32_t flip_flat_edges(const std::vector<Vec3>& positions, std::vector<Tri>& tris,
                         double tolerance);

// A triangle of a prepared component (unit bounding-box diagonal) with less area than this has
// zero area as far as the later stages can tell.
constexpr double kZeroArea = 1e-14;

struct ZeroAreaRepair {
  // Needle edges collapsed (two triangles each inside, one on the boundary).
  uint32_t collapsed = 0;
  uint32_t flipped = 0;  // cap edges flipped
  uint32_t dropped = 0;  // caps on the boundary removed
  // Zero-area triangles left (where no change keeps the topology).
  uint32_t left = 0;
  double moved = 0;  // the longest edge collapsed: how far the surface moved at most
};
// Removes zero-area triangles without changing the topology (degenerate.cpp); the vertex and
// triangle input maps follow.
ZeroAreaRepair repair_zero_area(std::vector<Vec3>& positions, std::vector<Tri>& tris,
                                std::vector<uint32_t>& vertex_input,
                                std::vector<uint32_t>& tri_input);

EdgeData<char> mark_features(const TriMesh& mesh, double feature_angle_deg);

}  // namespace isoquad::prep
