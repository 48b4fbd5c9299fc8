// Charts and transitions (DESIGN.md §6): each patch is walked CCW from corner 0 at (0,0) along
// the directions (1,0), (0,1), (-1,0), (0,-1); the walk must close. Each interior meta-edge then
// gets the transition from its left chart to its right chart. All checks are exact.
#pragma once

#include "layout/layout.hpp"

namespace isoquad {

// Fills layout.charts and layout.transition from corners, sides and lengths.
// \throw Error(internal, E700) if a walk does not close or a transition is inconsistent.
void build_charts(const MetaMesh& meta, const std::vector<std::vector<uint8_t>>& sides,
                  Layout& layout);

// Endpoint consistency of every transition, closure and uniqueness of lattice points per chart,
// holonomy around every interior meta-vertex (a rotation about it by -(a_v - 4) quarter turns,
// the identity where regular) and the quarter-turn Euler identity
// sum_interior (4 - a_v) + sum_boundary (2 - a_v) = 4 chi.
// \throw Error(internal, E700) naming the first violation.
void check_layout(const TriMesh& mesh, const FaceData<uint32_t>& labels, const MetaMesh& meta,
                  const Layout& layout);

}  // namespace isoquad
