// Parametrization (paper §3.2, §3.4; DESIGN.md §7): one seamless map (u, v) from the surface to
// the integer layout. Every patch maps into its W x H rectangle; across a seam the two charts
// agree up to the seam's transition (a quarter-turn rotation and an integer jump); meta-vertices
// sit on their lattice points. The map solves the paper's weighted-average equations with mean
// value weights; seam edges are stiffened only where triangles flip, and a seam is straightened
// exactly (locked) where stiffening is not enough. The result is certified injective.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/element_data.hpp"
#include "core/predicates.hpp"
#include "core/tri_mesh.hpp"
#include "layout/layout.hpp"

namespace isoquad {

enum class WeightKind {
  smvc,  // mean value weights symmetrized per face: SPD system (CHOLMOD), the default
  mvc,   // the paper's (Floater's) mean value weights: non-symmetric system (UMFPACK)
};

enum class RelaxMode {
  adaptive,   // stiffen seam edges near flips only, lock a seam where that is not enough
  bisection,  // the paper: one global seam weight, bisected down while no triangle flips
  locked,     // every seam straight: the exact limit of infinite seam weights
  none,       // seam weights 1, no stiffening (may flip: the paper's Figure 2, left)
};

struct ParamOptions {
  WeightKind weights = WeightKind::smvc;
  RelaxMode relax = RelaxMode::adaptive;
  uint32_t max_iterations = 12;    // adaptive solves before everything is locked
  double initial_stiffness = 100;  // seam weight of the first adaptive solve
  double growth = 3;               // stiffness factor per adaptive step
  double max_stiffness = 1e4;      // a seam edge reaching it gets its meta-edge locked
  uint32_t rings = 3;              // seam edges within this many face rings of a flip are stiffened
  // Stiffenings of a meta-edge before it is locked instead. 1: bunny00 needs 4 numeric
  // factorizations instead of 6 (elephant 4 instead of 5) for the same seam distortion (0.470
  // against 0.473); locking at the first flip (0) saves one more but leaves more folded quads.
  uint32_t max_raises = 1;
  uint32_t bisection_steps = 10;
};

// A map: per vertex its home chart and position there, and per face corner the uv in the face's
// own chart (the patch of the face). Meta-vertices have no home (kInvalid): they are fixed.
struct ParamMap {
  VertexData<uint32_t> home;
  VertexData<UV> position;
  FaceData<std::array<UV, 3>> uv;
};

// DESIGN.md §7.7: every face positively oriented (exact orient2d) and not degenerate, and every
// vertex's angle sum (measured face by face in the face's chart) equal to its expected total:
// 2 pi inside, pi on a mesh-boundary side, a_v pi/2 at a meta-vertex.
struct Certificate {
  uint32_t flipped = 0;     // orient2d <= 0
  uint32_t degenerate = 0;  // positive but below 1e-12 of the patch's mean face area
  uint32_t bad_angle_sums = 0;
  std::vector<uint32_t> bad_faces;     // flipped or degenerate, ascending
  std::vector<uint32_t> bad_vertices;  // wrong angle sum, ascending
  bool ok() const { return flipped == 0 && degenerate == 0 && bad_angle_sums == 0; }
};

struct ParamReport {
  std::string weights, relax;
  uint32_t symbolic = 0;                // symbolic factorizations (analyzePattern)
  uint32_t factorizations = 0;          // numeric factorizations
  uint32_t solves = 0;                  // right-hand sides solved (refinement steps included)
  uint32_t iterations = 0;              // relaxation rounds
  uint32_t unknowns = 0;                // free vertices
  uint32_t flipped_unstiffened = 0;     // flipped + degenerate faces with all seam weights 1
                                        // (bisection and none solve it; 0 for adaptive)
  uint32_t flipped_first = 0;           // the same in the first relaxed solve (adaptive: at
                                        // initial_stiffness)
  uint32_t flipped_final = 0;           // in the returned map (0 unless it is broken)
  std::vector<uint32_t> bad_per_solve;  // flipped + degenerate faces after each relaxed solve
  uint32_t locked_meta_edges = 0;  // locked in the returned map (features and boundary included)
  uint32_t stiffened_edges = 0;    // seam mesh edges with weight > 1 in the returned map
  uint32_t meta_edges = 0;
  bool fell_back_to_locked = false;  // relaxation gave up and returned the locked map
  double max_residual = 0;           // relative, after refinement
  double seam_angle_distortion = 0;  // mean |angle in uv - angle in 3D| (rad) near seams
  double setup_seconds = 0, analyze_seconds = 0, assemble_seconds = 0, factorize_seconds = 0,
         solve_seconds = 0, certify_seconds = 0, total_seconds = 0;
};

struct Param {
  ParamMap map;                    // the returned map (certified unless the report says not)
  ParamMap locked;                 // the locked map, always certified: extraction's fallback
  std::vector<char> locked_edges;  // per meta-edge: straight in `map`
  EdgeData<double> stiffness;      // per mesh edge: the seam weight lambda used in `map`
  Certificate certificate;         // of `map`
};

// \pre layout was solved on (mesh, labels, meta) and passed check_layout.
// \throw Error(solver, E551) when a factorization fails, Error(solver, E552) when a solve stays
//        inaccurate after refinement, Error(solver, E553) when even the locked map is not
//        injective (degenerate input triangles).
// `rank`: an elimination rank per vertex of `mesh` (param/ordering.hpp), or null (CHOLMOD orders).
Param parametrize(const TriMesh& mesh, const FaceData<uint32_t>& labels, const MetaMesh& meta,
                  const Layout& layout, const ParamOptions& options, ParamReport& report,
                  const std::vector<uint32_t>* rank = nullptr);

Certificate certify(const TriMesh& mesh, const FaceData<uint32_t>& labels, const MetaMesh& meta,
                    const Layout& layout, const ParamMap& map);

// Mean absolute difference (radians) between each face corner's angle in the map and on the
// surface, over the faces with mask[f] != 0 (all faces when mask is empty).
double mean_angle_distortion(const TriMesh& mesh, const ParamMap& map,
                             const std::vector<char>& mask = {});

// Faces within `rings` face rings of a seam (a mesh edge between two patches).
std::vector<char> faces_near_seams(const TriMesh& mesh, const FaceData<uint32_t>& labels,
                                   uint32_t rings);

}  // namespace isoquad
