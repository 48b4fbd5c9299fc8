// The min-cost-flow fast path for integer lengths (DESIGN.md §5.3). Every meta-edge appears in
// at most two side equations with coefficients +-1. If the rows can be signed so that every
// column becomes (+1, -1) (a 2-colouring of the row graph, Heller-Tompkins), the matrix is a
// network matrix: the ILP is a min-cost circulation whose LP optimum is integral, solved with
// LEMON's network simplex.
#pragma once

#include <optional>

#include "layout/quantize.hpp"

namespace isoquad {

// Row signs that make the system a network matrix, if there are any.
std::optional<std::vector<int>> network_signs(uint32_t num_edges, const std::vector<SideRow>& rows);

// The same optimum as solve_lengths (up to ties), or nothing if the system is not a network.
std::optional<Lengths> solve_lengths_flow(const std::vector<double>& target,
                                          const std::vector<SideRow>& rows);

}  // namespace isoquad
