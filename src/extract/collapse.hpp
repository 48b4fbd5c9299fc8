// Diagonal collapse of quads that stay folded (beyond the paper). Some folds cannot be moved
// out: a patch corner on a straight crease gives its quad a 180-degree corner between two
// vertices that may only slide along that crease, and a quad crushed to a sliver between
// pinned vertices has nowhere to go. Such a quad is removed by merging two opposite corners
// (quad-mesh cleaning, as in Tarini et al. 2010, "Practical quad mesh simplification"): the
// corner that may move goes to the other one, the quad disappears, and its two pairs of edges
// become one edge each. Pure quad, the Euler characteristic and the boundary stay; a neighbour
// left with two quads (a doublet) is dissolved by merging them.
#pragma once

#include <cstdint>
#include <vector>

#include "extract/extract.hpp"

namespace isoquad {

struct CollapseRequest {
  uint32_t quad;
  int worst;  // the corner (0-3) whose scaled Jacobian is lowest
};

struct CollapseReport {
  uint32_t collapsed = 0;  // quads removed by a diagonal collapse
  uint32_t doublets = 0;   // quads removed with a valence-2 vertex left by a collapse
  uint32_t refused = 0;    // requests no allowed diagonal could serve
};

// Collapses a diagonal of each requested quad: the one through its worst corner if allowed,
// else the other. A diagonal is allowed when at least one end may move (`movable`); the other
// end stays where it is (of two movable ends, the worst corner goes). It must keep the mesh
// manifold: the ends share no face but the quad and no neighbour but its two other corners,
// and the merged edges keep at least one face each; the merged corner's valence stays at 6 or
// below. The removed corner must lie within
// `max_offset` of the quads that take its place (and a dissolved doublet's vertex within it of
// the merged quad), so that no tip of the surface is cut off. Requests whose neighbourhoods overlap
// one already served wait for the next call. Deleted quads and vertices are removed; `movable` is
// renumbered with the vertices. Deterministic (requests in order).
void collapse_diagonals(QuadMesh& qm, std::vector<char>& movable,
                        const std::vector<CollapseRequest>& requests, double max_offset,
                        CollapseReport& report);

}  // namespace isoquad
