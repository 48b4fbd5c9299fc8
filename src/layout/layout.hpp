// Layout (paper §3.3 and §5; DESIGN.md §4-6): every patch becomes a W x H rectangle with its
// meta-vertices on lattice points. Four meta-vertices per patch are chosen as corners, every
// meta-edge gets an integer length (an ILP), and each meta-edge gets the transition (rotation
// by k quarter turns and an integer jump) from its left chart to its right chart.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/transition.hpp"
#include "layout/meta_mesh.hpp"

namespace isoquad {

struct Chart {
  std::array<uint32_t, 4> corners{};  // cycle item indices of corners 0..3 (CCW), corner 0 at (0,0)
  int64_t width = 0, height = 0;
  std::vector<Lattice> item_position;  // lattice point of each cycle item's start (its meta-vertex)
  std::vector<uint8_t> item_side;      // side 0..3 of each cycle item
};

struct Layout {
  std::vector<Chart> charts;           // one per patch
  std::vector<int> quarter_turns;      // a_v per meta-vertex: number of quads at it (x 90 deg)
  std::vector<double> target;          // c_e per meta-edge (geodesic length / h)
  std::vector<int64_t> length;         // x_e per meta-edge
  std::vector<Transition> transition;  // per meta-edge, left chart -> right chart
  double edge_length = 0;              // h used (mesh units)
  double objective = 0;  // sum_e d(x_e, c_e), plus the lens widths' weighted d (quantize.hpp)
  double quads_aim = 0;  // the count h was tuned for: the request, or more (kFloorMargin)
  int64_t quads() const;
  // x_e / c_e over the meta-edges with a positive target, sorted.
  std::vector<double> length_ratios() const;
};

// Where the request is below this many times the fewest quads the patches allow (every
// meta-edge one quad long), the layout aims at that many instead.
constexpr double kFloorMargin = 1.25;

enum class CornerMode { global, local };
enum class LengthSolver { cbc, flow };  // flow: LEMON when the system is a network, else CBC

struct LayoutOptions {
  double edge_length = 0;  // target h (mesh units); 0: from `quads`
  double quads = 0;        // target quad count; the size is tuned to land within 10%
  // With neither: the default count on the layout's surface, for a component that covers this
  // share of the input's area (pipeline/sizing.hpp default_quad_count).
  double default_share = 1;
  CornerMode corners = CornerMode::global;
  LengthSolver length_solver = LengthSolver::cbc;
  double angle_weight = 0.5;    // beta in the corner cost (0: paper's length-only cost)
  double valence_weight = 0.5;  // mu: penalty per quarter turn of singularity
  // Added to the angle term (before beta) for a patch corner at a surface angle above 150
  // degrees. 0 by default: the remesh pipeline sets it when it re-chooses the corners of a
  // mesh whose quads still fold (pipeline.cpp).
  double flat_corner_penalty = 0;
  // The same for a corner on a straight crease only (the patch boundary a crease on both sides):
  // there the quad's 180-degree corner cannot be moved away. Also set by the pipeline's retry.
  double flat_crease_corner_penalty = 0;
  uint32_t candidates_per_patch = 8;
  // Improve the corners patch by patch against the LP relaxation of the length program: about
  // half the length objective on organic and CAD meshes (corpus at 1,500 quads: quads folded
  // against the surface 149 -> 79 after untangling), at 50-250 ms of extra layout time.
  bool improve_corners = true;
  // Its price per quarter turn of singularity against the relaxed length objective (a sum of
  // relative deviations over all meta-edges). At the corner ILP's 0.5 the refinement traded
  // singularities for lengths freely (corpus at 1,500 quads: irregular vertices 351 without the
  // refinement, 616 with it); at 2, 458, with fewer folded quads than at 0.5.
  double improve_valence_weight = 2;
  // Skip refinement trials whose Lagrangian bound shows they cannot win. Exact: off only to
  // check that the same corners come out.
  bool prune_corner_trials = true;
  // A patch whose mean width across its longer dimension (its area over that dimension's
  // length) is more than this many times its shorter sides (a lens pinched at two corners) gets
  // a soft target on that width in the length program, priced like a meta-edge's times the
  // patch's length in quads, so it is not laid out one or two quads thick. 0: off. Corpus with
  // it (at 3, then 2): mech-holes-shark 7.1 -> 1.7% Hausdorff at 1,500 quads and 7.3 -> 2.5% at
  // the default size, knot1 2.35 -> 1.25% at the default size; at 2 rather than 3, folded quads
  // 5 -> 5 at 1,500 quads and 6 -> 3 at the default size (the armadillo's Hausdorff there
  // 0.93 -> 1.28%). At 1.5 or 2 with one meta-edge's weight it had cost folds (9 -> 12).
  double area_dimension_threshold = 2;
  // Seconds per ILP: a safety net only. Every solve's effort is bounded by nodes (a bound that
  // does not depend on the machine), so the output does not depend on the machine's load; this
  // is reached only by a program far harder than a layout's.
  double time_limit = 120;
  // Per patch, its corners as MetaFace::cycle indices (increasing), taken as they are: no
  // refinement, and candidates and the corner ILP only for the patches given kFreeCorners (the
  // field-aligned layout knows the others). If they do not admit positive lengths, the layout
  // fails with E402.
  const std::vector<std::array<uint32_t, 4>>* given_corners = nullptr;
  // Per patch of given_corners, nonzero where its corners are a preference only: the corner ILP
  // may give it another of its candidates, at kPreferredCornersPenalty more than their own cost
  // (the field-aligned layout's corners read from angles rather than from the traces' rules).
  const std::vector<char>* preferred_corners = nullptr;
  // Per meta-vertex, the quarter turns (quads) the cross field puts there: 4 - 4I inside (5 at a
  // -1/4 singularity, 3 at a +1/4 one), 2 - 4I on the boundary. The corner program's valence
  // term measures from these instead of from regular valences, so that a free patch's corners
  // keep the field's singularities where the field put them rather than trading one for a
  // corner the geometry does not have. 0 (or past the end, for meta-vertices the layout
  // inserts): regular.
  const std::vector<int>* field_quarter_turns = nullptr;
};

// What leaving a patch's preferred corners costs in the corner ILP: a fifth of a quarter turn of
// singularity (LayoutOptions::valence_weight), so that the preference breaks ties between
// candidates but buys no irregular vertex. Corpus at 1,500 quads (field layout): at 4, bunny00
// had 146 irregular vertices; at 0.1, 110 and a better mean scaled Jacobian (0.879 -> 0.885).
inline constexpr double kPreferredCornersPenalty = 0.1;

// In LayoutOptions::given_corners: a patch whose corners the corner program chooses.
inline constexpr std::array<uint32_t, 4> kFreeCorners{kInvalid, kInvalid, kInvalid, kInvalid};

struct LayoutReport {
  std::vector<std::string> repairs;  // what was done to make the layout feasible
  uint32_t corner_rounds = 0;        // corner ILPs solved (no-good cuts add rounds)
  uint32_t size_rounds = 0;          // length ILPs solved while tuning the size
  double corner_seconds = 0, length_seconds = 0;
  double refine_seconds = 0;  // the corner refinement's part of corner_seconds
  std::string length_solver;  // "cbc" or "flow"
  bool length_optimal = false;
};

// A lower bound on one patch side: the sum of x_e over `edges` (an edge listed twice counts
// twice) is at least `at_least`.
struct SideMinimum {
  std::vector<uint32_t> edges;
  int64_t at_least = 0;
};

// Chooses corners, tests feasibility and repairs (re-choosing corners with no-good cuts, then
// inserting meta-vertices on forced-zero meta-edges, which rebuilds `meta`), solves the integer
// lengths (tuning h to land near options.quads), and builds the charts and transitions.
// \throw Error(layout, E501) when the target size is far too coarse for the patches,
//        Error(layout, E402) when no repair makes the layout feasible.
Layout solve_layout(const TriMesh& mesh, const FaceData<uint32_t>& labels,
                    const EdgeData<char>& feature, MetaMesh& meta, const LayoutOptions& options,
                    LayoutReport& report);

// Patches whose rectangle cannot follow their shape: in one direction one side's target (the sum
// of its meta-edges' targets) is more than `ratio` times the facing side's and at least 3 quads
// longer (an L- or T-shaped patch, a leg strip with a piece of shoulder). The length program
// then stretches one side and crushes the other, and the map crowds quads into slivers there
// (the mushroom at 3,000 quads: a patch whose facing sides' targets are 9.5 times apart).
std::vector<uint32_t> misfit_patches(const MetaMesh& meta, const Layout& layout, double ratio = 3);

// More quads across the given patches (those whose quads folded against the surface: a patch
// one or two quads across a tip, or squeezed in a strip, has too few lattice lines to follow
// the surface). For each patch, its dimension (width: sides 0 and 2, height: 1 and 3) shrunk
// most against its targets, and the other too where it is shrunk as well, is held to one more
// than now; a minimum already in `minimums` for that side is raised instead of repeated.
void thicken_patches(const MetaMesh& meta, const Layout& layout,
                     const std::vector<uint32_t>& patches, std::vector<SideMinimum>& minimums);

// `layout` again with the same corners, its integer lengths re-solved (CBC) with `minimums`
// held; the charts and transitions follow. When sized by a quad count, the edge length may grow
// up to kRelayoutMaxGrowth times to stay near the count, and nothing is returned if the count
// still exceeds the request by a factor kRelayoutMaxQuads.
// \throw Error(solver, E502) if CBC finds no solution in time.
constexpr double kRelayoutMaxGrowth = 1.15, kRelayoutMaxQuads = 1.1;
std::optional<Layout> relayout_lengths(const TriMesh& mesh, const FaceData<uint32_t>& labels,
                                       const MetaMesh& meta, const Layout& layout,
                                       const std::vector<SideMinimum>& minimums,
                                       const LayoutOptions& options, LayoutReport& report);

}  // namespace isoquad
