// Dijkstra on the vertex graph and on the dual (face) graph of a TriMesh, restricted by
// predicates. The one shortest-path routine of segmentation and layout.
#pragma once

#include <functional>
#include <vector>

#include "core/tri_mesh.hpp"

namespace isoquad {

struct ShortestPaths {
  std::vector<double> distance;       // INFINITY where unreached
  std::vector<uint32_t> predecessor;  // kInvalid at sources and unreached
  std::vector<uint32_t> source;       // which source reached it
  // The path from a source to `target`, source first.
  std::vector<uint32_t> path_to(uint32_t target) const;
};

// Vertex Dijkstra with edge lengths in 3D. `allowed(v, e)` says whether vertex v may be entered
// through mesh edge e; `stop(v)` ends the search when v is settled.
ShortestPaths vertex_dijkstra(const TriMesh& mesh, const std::vector<uint32_t>& sources,
                              const std::function<bool(uint32_t, uint32_t)>& allowed,
                              const std::function<bool(uint32_t)>& stop = nullptr);

// vertex_dijkstra from a until b is settled, as the path from a to b (empty where b is not
// reached) and its `length`. The search's arrays live in `scratch`, reset only where it went:
// many short searches on a large mesh (one per seam) do not each fill arrays over all of it.
struct PathScratch {
  std::vector<double> distance;
  std::vector<uint32_t> predecessor, touched;
};
std::vector<uint32_t> vertex_path(const TriMesh& mesh, uint32_t a, uint32_t b,
                                  const std::function<bool(uint32_t, uint32_t)>& allowed,
                                  PathScratch& scratch, double& length);

// Face Dijkstra between centroids across edges where `crossable(halfedge)` holds.
ShortestPaths face_dijkstra(const TriMesh& mesh, const std::vector<uint32_t>& sources,
                            const std::function<bool(uint32_t)>& crossable);

// Shortest distance from a to b over the faces where `face_allowed` holds: mesh edges plus, for
// every pair of allowed faces sharing an edge whose unfolding is convex, the straight segment
// across both (cuts the staircase error of edge paths from ~10% to a few %).
double geodesic_distance(const TriMesh& mesh, uint32_t a, uint32_t b,
                         const std::function<bool(uint32_t)>& face_allowed);

}  // namespace isoquad
