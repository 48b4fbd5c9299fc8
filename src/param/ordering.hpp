// A fill-reducing elimination order for the parametrization system, computed on the mesh's
// vertex graph (METIS nested dissection through CHOLMOD) rather than on the system's matrix:
// the system has two unknowns per vertex, so the graph is half the size, and it depends on the
// mesh alone, so it can be computed while the segmentation runs and reused by every later
// solve (fold rounds, corner retries). SuiteSparse stays in the .cpp.
#pragma once

#include <cstdint>
#include <vector>

#include "core/tri_mesh.hpp"

namespace isoquad {

// Meshes from this many vertices on are ordered by nested dissection; below it AMD on the
// system itself is cheaper than the dissection and factors as fast.
constexpr uint32_t kNestedDissectionVertices = 30000;

// The rank of every vertex in a nested dissection order of the vertex graph (rank 0 is
// eliminated first). Deterministic.
// \throw Error(solver, E551) if METIS fails.
std::vector<uint32_t> nested_dissection_ranks(const TriMesh& mesh);

// Ranks for a mesh refined from the ordered one (RefinedMesh: the first `base_ranks.size()`
// vertices are the base mesh's): a new vertex goes right after its highest-ranked neighbour
// (earlier, it could join two parts that a separator keeps apart), ties by id. Returns a
// permutation rank of all of `refined`'s vertices.
std::vector<uint32_t> extend_ranks(const TriMesh& refined, const std::vector<uint32_t>& base_ranks);

}  // namespace isoquad
