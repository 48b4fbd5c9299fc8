// Fold repair after extraction (beyond the paper). The map is certified bijective, so the
// lattice points land on the surface in the right order, but a quad joins its four corners by
// straight edges: where the map stretches strongly within one quad (near a corner whose surface
// angle is far from 90 degrees, across a thin rim) the quad can fold against the surface. Each
// corner of a quad whose scaled Jacobian against the surface normal is below `target` is moved
// to the best of a few trial positions in its tangent plane, put back onto the surface by a
// local walk: a move is taken if the squared shortfall of its quads' corners below `target`
// drops (one energy over the whole mesh, so the sweeps end).
// Vertices on creases and the mesh boundary slide along them; meta-vertices where creases or
// the boundary meet stay; other meta-vertices (singularities) move like any vertex. A move
// must keep the vertex's original surface point close to its quads (`fidelity`), so tips are
// not cut off. Deterministic (fixed visiting order and trial positions).
// Quads the sweeps leave folded then lose a diagonal (extract/collapse.hpp) and the sweeps run
// again, for `collapse_rounds` rounds; the mesh with the fewest folds is kept. The reach and
// fidelity bounds stay measured from where the first call found each vertex (QuadMesh::mapped).
// The pipeline runs them once, after its fold rounds (pipeline.cpp). Corpus at 1,500 quads,
// after the rounds: 19 folded quads -> 10 with the collapses (cow 8 -> 6, mech-holes-shark 4 -> 0,
// fandisk 1 -> 0); knot1's slivers at the default size only moved (25 -> 19, irregular vertices
// 14 -> 91), which the pipeline's second choice of corners then replaces.
//
// Corpus at 1,500 quads, quads folded against the surface after untangling: 149 moving free
// vertices only (817 without untangling); 52 with singularities moving and crease vertices
// sliding; 39 when a move need only lower the shortfall (before, it also had to keep the worst
// corner around the vertex from dropping; at the default size 108 -> 61). Under that earlier
// rule, letting singularities move without the fidelity bound gave 45 but took the cow's horn
// tips off (Hausdorff distance 3.4% -> 5.7% of the diagonal); without the reach bound a vertex
// at the end of a stretched quad on anchor (default size) was dragged 40% of the diagonal along
// it (Hausdorff 14%; 2.1% with the bound).
#pragma once

#include <cstdint>
#include <vector>

#include "extract/extract.hpp"
#include "layout/meta_mesh.hpp"

namespace isoquad {

struct UntangleOptions {
  double target = 0.1;       // quads whose surface scaled Jacobian is below this are worked on
  uint32_t max_rounds = 30;  // sweeps over their corners
  bool slide = true;         // crease and boundary vertices may slide along them
  bool move_singularities = true;  // meta-vertices off creases and the boundary may move
  double edge_length = 0;          // the target quad edge h (mesh units): the unit of the two below
  double reach = 3;                // no vertex moves farther than this from where the map put it
  // A singularity or crease vertex must keep its original surface point within this distance of
  // its quads, so that the mesh glides along the surface instead of cutting off tips.
  double fidelity = 0.15;
  double short_edge = 0.2;  // quads with an edge shorter than this count as worse shaped
  // Rounds of diagonal collapses (extract/collapse.hpp) for quads the sweeps leave folded.
  uint32_t collapse_rounds = 3;
  double collapse_offset = 0.25;  // how far (in h) a removed corner may be from the new quads
};

struct UntangleReport {
  uint32_t folded_before = 0, folded_after = 0;  // quads with surface scaled Jacobian <= 0
  std::vector<uint32_t> folded;                  // those left at the end, in order
  double min_before = 1, min_after = 1;          // smallest surface scaled Jacobian
  uint32_t rounds = 0, moves = 0;
  uint32_t collapsed = 0, doublets = 0;  // quads removed by diagonal collapses, and doublets
  uint32_t refused = 0;                  // folded quads no diagonal could be collapsed in
  double seconds = 0;
};

// `base` is the surface the quads' SurfacePoints refer to.
// `seams` is the mesh whose vertices the meta-edges list (`base` with its dividing edges split).
void untangle_quads(QuadMesh& quads, const TriMesh& base, const TriMesh& seams,
                    const MetaMesh& meta, const UntangleOptions& options, UntangleReport& report);

}  // namespace isoquad
