// A small mixed-integer / linear program and its solution by COIN-OR CBC (integer) or Clp
// (continuous). The only place that talks to the solvers; everything else builds a MilpProblem.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace isoquad {

struct MilpProblem {
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  struct Row {
    std::vector<uint32_t> columns;
    std::vector<double> values;
    double lo = -kInf, hi = kInf;
  };
  std::vector<double> objective;  // minimized
  std::vector<double> col_lo, col_hi;
  std::vector<char> integer;
  std::vector<Row> rows;

  uint32_t add_column(double cost, double lo, double hi, bool is_integer);
  void add_row(Row row) { rows.push_back(std::move(row)); }
};

struct MilpResult {
  enum class Status { optimal, feasible, infeasible, failed };
  Status status = Status::failed;
  std::vector<double> x;
  std::vector<double> duals;  // row prices y (reduced costs c - A^T y); IncrementalLp only
  double objective = 0;
  double seconds = 0;
  bool found() const { return status == Status::optimal || status == Status::feasible; }
};

// Branch and bound with CBC; stops once within `relative_gap` of the bound (0: proven optimal)
// or after `node_limit` nodes (0: none). Single thread, so deterministic unless `time_limit`
// (a safety net, in seconds) is reached: callers that need a bounded effort use the node limit.
// CBC's integer preprocessing is off: on the layout's small programs it costs more than it
// saves, and on the big-M rows of the feasibility-aware corner programs its probing takes
// seconds where the search itself takes tenths (docs/benchmarks.md, BM_FieldLayout).
// The node bound of a solve that is to be optimal: reached, the best solution found is taken.
constexpr int kOptimalNodeLimit = 20000;
MilpResult solve_milp(const MilpProblem& problem, double time_limit = 10.0,
                      double relative_gap = 0.0, int node_limit = 0);
// The LP relaxation with Clp (integrality ignored).
MilpResult solve_lp(const MilpProblem& problem);

// An LP solved again and again after changing a few coefficients: Clp keeps its basis, so each
// re-solve starts from the last optimum (a few pivots instead of a solve from scratch).
class IncrementalLp {
 public:
  explicit IncrementalLp(const MilpProblem& problem);  // integrality ignored
  ~IncrementalLp();
  IncrementalLp(const IncrementalLp&) = delete;
  IncrementalLp& operator=(const IncrementalLp&) = delete;
  void set_coefficient(uint32_t row, uint32_t column, double value);
  void set_row_bounds(uint32_t row, double lo, double hi);
  MilpResult solve();
  // The current basis, and a basis (of this LP or of one with the same rows and columns) for
  // the next solve to start from.
  struct Basis;
  std::shared_ptr<const Basis> basis() const;
  void set_basis(const Basis& basis);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace isoquad
