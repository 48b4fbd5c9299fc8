// Integer meta-edge lengths (paper §3.3 problem (*); DESIGN.md §5): min sum_e d(x_e, c_e)
// subject to equal sums on facing sides of every patch and integer x_e >= 1.
//
// The deviation d is the paper's |x - c| made relative and symmetric in the ratio: stretching
// by a factor k costs k - 1 (d = x/c - 1 for x >= c) and so does shrinking by k (d = c/x - 1,
// convex, taken piecewise linear between breakpoints). A relative |x - c|/c alone makes
// shrinking a long edge to 1 cost less than 1 whatever its length, so conflicting sides were
// settled by collapsing long meta-edges (quads spanning a whole leg); the symmetric cost settles
// them near the geometric mean.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "layout/layout.hpp"
#include "layout/milp.hpp"

namespace isoquad {

// Side (0..3) of every cycle item of every patch, corner 0 being the corner whose meta-vertex has
// the smallest id (so that charts do not depend on where a cycle happens to start).
std::vector<std::vector<uint8_t>> item_sides(const MetaMesh& meta,
                                             const std::vector<std::array<uint32_t, 4>>& corners);

// A x = 0: per patch, side 0 minus side 2 and side 1 minus side 3, as (meta-edge, +-1) terms.
using SideRow = std::vector<std::pair<uint32_t, int>>;
std::vector<SideRow> side_equations(const MetaMesh& meta,
                                    const std::vector<std::vector<uint8_t>>& sides);

// Exact feasibility (DESIGN.md §5.2): the homogeneous system has a solution with all x >= 1 iff
// its LP has one with all x > 0. `forced_zero` lists the meta-edges that are 0 in every
// nonnegative solution (the paper's "boundary inevitably of length 0", Figure 4).
struct Feasibility {
  bool feasible = false;
  std::vector<uint32_t> forced_zero;
  double seconds = 0;
};
Feasibility check_feasibility(uint32_t num_edges, const std::vector<SideRow>& rows);

// The same test again and again for side equations that differ from a base set in one patch's two
// rows (rows 2p and 2p + 1, as side_equations lays them out): one LP kept between tests, each
// test starting from the base optimum's basis (the greedy corner repair tries tens of them).
class FeasibilityLp {
 public:
  FeasibilityLp(uint32_t num_edges, const std::vector<SideRow>& rows);
  ~FeasibilityLp();
  // The test with patch p's rows replaced by `row0` and `row1`; the base is left as it was.
  Feasibility test(uint32_t p, const SideRow& row0, const SideRow& row1);
  // Makes the replacement part of the base.
  void accept(uint32_t p, const SideRow& row0, const SideRow& row1);

 private:
  void write(uint32_t p, const SideRow& row0, const SideRow& row1);
  uint32_t n_;
  std::vector<SideRow> rows_;
  std::unique_ptr<IncrementalLp> lp_;
  std::shared_ptr<const IncrementalLp::Basis> base_;
};

// The deviation cost: stretching at slope 1/max(c, 1) above c, and below c the segments of the
// shrinking cost from c downwards (lengths and slopes, slopes increasing: convex).
struct CostSegment {
  double length = 0, slope = 0;
};
double stretch_slope(double c);
std::vector<CostSegment> shrink_segments(double c);
// d(x, c): the piecewise-linear cost the program minimizes.
double length_cost(double x, double c);

// The length program itself: columns x_e (e < n), then per edge its stretch and shrink
// segments; row e ties x_e to c_e through them, then one row per side equation in the order of
// `rows` (row n + k for rows[k]), then one row per side minimum.
// A soft target on one patch side (the sum of x_e over `edges`, an edge listed twice counting
// twice), priced like a meta-edge's: `dimensions` follow the minimums as rows.
struct SideTarget {
  std::vector<uint32_t> edges;
  double target = 0;
  double weight = 1;  // times a meta-edge's price
};
MilpProblem length_problem(const std::vector<double>& target, const std::vector<SideRow>& rows,
                           bool bounded, bool integer,
                           const std::vector<SideMinimum>& minimums = {},
                           const std::vector<SideTarget>& dimensions = {});

// The LP relaxation of the length program with x eliminated: per edge e the columns
// [first[e], first[e + 1]) are its stretch (coefficient +1) and then its shrink segments (-1), so
// x_e = c_e + stretch - sum shrink, and x_e >= 1 is the segments' bounds. What is left are the
// side equations alone, one row each (row k for rows[k]), with right-hand side -sum sign c_e.
// Same optimum as length_problem's relaxation, with 2 rows per patch instead of that plus one
// per meta-edge: the corner refinement re-solves it tens of times, and each re-solve
// refactorizes the basis.
struct RelaxedLengths {
  MilpProblem lp;
  std::vector<uint32_t> first;  // num_edges + 1 entries
  std::vector<double> target;
  // The lengths of a solution of `lp`.
  std::vector<double> lengths(const std::vector<double>& solution) const;
  // The row of one side equation: its terms by column (an edge met twice adds up) and its
  // right-hand side.
  struct Row {
    std::vector<std::pair<uint32_t, double>> terms;
    double rhs = 0;
  };
  Row row(const SideRow& side) const;
};
RelaxedLengths relaxed_length_problem(const std::vector<double>& target,
                                      const std::vector<SideRow>& rows);

struct Lengths {
  std::vector<int64_t> x;
  double objective = 0;  // sum_e d(x_e, c_e) plus the side targets' d
  bool optimal = false;
  double seconds = 0;
  std::string solver;
};
// \pre the system is feasible.
// \throw Error(solver, E502) if CBC finds no solution in time.
Lengths solve_lengths(const std::vector<double>& target, const std::vector<SideRow>& rows,
                      double time_limit, const std::vector<SideMinimum>& minimums = {},
                      const std::vector<SideTarget>& dimensions = {});

}  // namespace isoquad
