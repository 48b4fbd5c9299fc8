// Corner assignment (paper §3.3; DESIGN.md §4): four meta-vertices of every patch become the
// rectangle's corners. Candidates per patch are scored by the paper's facing-side length
// difference plus an angle term; a small ILP then picks one candidate per patch so that the
// quad valence at each meta-vertex (its quarter turns a_v) stays near regular.
#pragma once

#include <array>
#include <vector>

#include "layout/layout.hpp"

namespace isoquad {

struct CornerCandidate {
  std::array<uint32_t, 4> items;  // cycle item indices, increasing
  double cost = 0;
};

struct CornerChoice {
  std::vector<std::array<uint32_t, 4>> corners;  // per patch
  std::vector<uint32_t> chosen;                  // candidate index per patch
  std::vector<int> quarter_turns;                // a_v per meta-vertex
  double cost = 0;
  double seconds = 0;
  bool softened = false;  // the valence bounds had to be relaxed
};

// Per patch, the best `keep` candidates (all of them for keep == 0), best first. With a target
// quad edge `unit` > 0, facing sides a and b (in units, at least 1) cost a quarter of what
// settling them alone costs the length program (quantize.hpp, 2 (sqrt(max/min) - 1)):
// unbounded, so that a side of a tenth of a unit never faces one of forty, yet light enough to
// leave room to the angle and valence terms; with unit == 0 the paper's scale-free
// ((a - b)/(a + b))^2. `flat_corner` is added to the angle term for each corner at a surface
// angle above 150 degrees, where the quad at the corner must open to that angle;
// `flat_crease_corner` too where the patch boundary runs along a crease on both sides of the
// corner (measured before the Gauss-Bonnet rescaling): crease vertices only slide along their
// crease, so nothing after the layout can close that angle.
std::vector<std::vector<CornerCandidate>> corner_candidates(const TriMesh& mesh,
                                                            const FaceData<uint32_t>& labels,
                                                            const MetaMesh& meta,
                                                            double angle_weight, uint32_t keep,
                                                            double unit = 0, double flat_corner = 0,
                                                            double flat_crease_corner = 0);

// Picks one candidate per patch. With `require_feasible`, the ILP also carries continuous
// meta-edge lengths in [1, 100] and, for the chosen candidate of each patch only (big-M), its
// two facing-side equations: whatever it returns admits positive lengths (DESIGN.md §5.4,
// corner re-assignment, done exactly instead of by trial and no-good cuts).
// \throw Error(layout, E401) when no choice exists.
CornerChoice choose_corners(const TriMesh& mesh, const MetaMesh& meta,
                            const std::vector<std::vector<CornerCandidate>>& candidates,
                            const LayoutOptions& options, bool require_feasible = false);

// Quarter turns per meta-vertex for given corners (1 where a patch has a corner, 2 elsewhere).
std::vector<int> quarter_turns(const MetaMesh& meta,
                               const std::vector<std::array<uint32_t, 4>>& corners);

// The regular value of a_v: 4 inside, the mesh angle in quarter turns (1..3) on the boundary.
int regular_quarter_turns(const TriMesh& mesh, const MetaMesh& meta, uint32_t mv);
// The quarter turns the corner program aims at meta-vertex mv: the field's
// (LayoutOptions::field_quarter_turns) where it is given, else regular_quarter_turns; within
// the program's valence bounds (3..6 inside, 1..4 on the boundary).
int target_quarter_turns(const TriMesh& mesh, const MetaMesh& meta, const LayoutOptions& o,
                         uint32_t mv);

}  // namespace isoquad
