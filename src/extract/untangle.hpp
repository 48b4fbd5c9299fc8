// Fold repair after extraction (beyond the paper). The map is certified bijective, so the
// lattice points land on the surface in the right order, but a quad joins its four corners by
// straight edges: where the map stretches strongly within one quad (near a corner whose surface
// angle is far from 90 degrees, across a thin rim) the quad can fold against the surface, and
// where it bends across a ridge it can have a reflex corner in its own plane. A corner counts
// by the lower of its scaled Jacobians against the surface normal and against the quad's own
// (Newell) normal, the measure of the output's validity (metrics/quality.hpp). Each corner of
// a quad below `target` is moved to the best of a few trial positions in its tangent plane,
// put back onto the surface by a local walk: a move is taken if the squared shortfall of its
// quads' corners below `target` drops (one energy over the whole mesh, so the sweeps end).
// Vertices on creases and the mesh boundary slide along them; meta-vertices where creases or
// the boundary meet stay; other meta-vertices (singularities) move like any vertex. A move
// must keep the vertex's original surface point close to its quads (`fidelity`), so tips are
// not cut off. Deterministic (fixed visiting order and trial positions).
// Quads the sweeps leave folded then lose a diagonal (extract/collapse.hpp) and the sweeps run
// again, for `collapse_rounds` rounds; the mesh with the fewest folds is kept. A quad still
// folded there whose widest corner (at least 150 degrees) is at a vertex held to a crease or
// the boundary is then split in five, an inner quad and four around it, so that the vertex has
// two quads on that side; the new vertices are free, the sweeps place them, and the split is
// kept if fewer quads fold. The reach and
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
#include <utility>
#include <vector>

#include "extract/extract.hpp"
#include "layout/meta_mesh.hpp"
#include "metrics/aabb_tree.hpp"

namespace isoquad {

// Where collapses follow (collapse_rounds > 0), a quad counts as folded at a scaled Jacobian
// (the lower of surface and own normal, as the untangler measures it) at or below this, not only at
// or below 0: a corner of exactly 180 degrees (a patch corner on a straight crease) reads 0 give or
// take rounding, +3e-16 here and -1e-16 in `isoquad quality` after the output's scaling, and is
// degenerate either way. Before (the pipeline's fold rounds), only quads at or below 0: counting
// these there too cost folded quads on the corpus (cow 2 -> 3 at 1,500 quads and 2 -> 4 at the
// default size).
constexpr double kFoldedAtOrBelow = 1e-3;

struct UntangleOptions {
  double target = 0.1;             // quads whose scaled Jacobian is below this are worked on
  uint32_t max_rounds = 30;        // sweeps over their corners
  bool slide = true;               // crease and boundary vertices may slide along them
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
  // Quads still folded at a crease or boundary vertex they open to about 180 degrees are split
  // in five (untangle.cpp split_crease_corners), after the collapses.
  bool split_crease_corners = true;
};

struct UntangleReport {
  // Quads with scaled Jacobian (the lower of surface and own normal) <= 0, or <=
  // kFoldedAtOrBelow where collapses follow.
  uint32_t folded_before = 0, folded_after = 0;
  std::vector<uint32_t> folded;          // those left at the end, in order
  double min_before = 1, min_after = 1;  // smallest scaled Jacobian
  uint32_t rounds = 0, moves = 0;
  uint32_t collapsed = 0, doublets = 0;  // quads removed by diagonal collapses, and doublets
  uint32_t refused = 0;                  // folded quads no diagonal could be collapsed in
  uint32_t split = 0;                    // quads split in five at a 180-degree crease corner
  uint32_t nonpositive = 0;              // at the end: quads with scaled Jacobian <= 0
  uint32_t degenerate = 0;               // and <= kFoldedAtOrBelow (those included)
  double seconds = 0;
};

// How repairs compare: fewer quads at or below 0 first, then fewer degenerate ones.
inline std::pair<uint32_t, uint32_t> fold_score(const UntangleReport& r) {
  return {r.nonpositive, r.degenerate};
}

// `base` is the surface the quads' SurfacePoints refer to; `base_tree`, if given, the tree of its
// faces in order (face_triangles), built here otherwise.
// `seams` is the mesh whose vertices the meta-edges list (`base` with its dividing edges split).
void untangle_quads(QuadMesh& quads, const TriMesh& base, const TriMesh& seams,
                    const MetaMesh& meta, const UntangleOptions& options, UntangleReport& report,
                    const AabbTree* base_tree = nullptr);

}  // namespace isoquad
