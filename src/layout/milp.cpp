#include "layout/milp.hpp"

#include <CbcModel.hpp>
#include <CbcSolver.hpp>
#include <ClpSimplex.hpp>
#include <CoinPackedMatrix.hpp>
#include <OsiClpSolverInterface.hpp>
#include <chrono>
#include <iterator>
#include <string>

namespace isoquad {

uint32_t MilpProblem::add_column(double cost, double lo, double hi, bool is_integer) {
  objective.push_back(cost);
  col_lo.push_back(lo);
  col_hi.push_back(hi);
  integer.push_back(is_integer);
  return uint32_t(objective.size() - 1);
}

namespace {

double clamp_inf(double v) {
  if (v == MilpProblem::kInf) return COIN_DBL_MAX;
  if (v == -MilpProblem::kInf) return -COIN_DBL_MAX;
  return v;
}

void load(OsiClpSolverInterface& solver, const MilpProblem& p) {
  CoinPackedMatrix matrix(false, 0, 0);
  matrix.setDimensions(0, int(p.objective.size()));
  std::vector<double> row_lo, row_hi;
  for (const auto& r : p.rows) {
    std::vector<int> cols(r.columns.begin(), r.columns.end());
    matrix.appendRow(int(cols.size()), cols.data(), r.values.data());
    row_lo.push_back(clamp_inf(r.lo));
    row_hi.push_back(clamp_inf(r.hi));
  }
  std::vector<double> lo(p.col_lo.size()), hi(p.col_hi.size());
  for (std::size_t i = 0; i < lo.size(); ++i)
    lo[i] = clamp_inf(p.col_lo[i]), hi[i] = clamp_inf(p.col_hi[i]);
  solver.loadProblem(matrix, lo.data(), hi.data(), p.objective.data(), row_lo.data(),
                     row_hi.data());
  solver.messageHandler()->setLogLevel(0);
  solver.getModelPtr()->setLogLevel(0);
}

double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

MilpResult solve_milp(const MilpProblem& p, double time_limit, double relative_gap,
                      int node_limit) {
  const auto t0 = std::chrono::steady_clock::now();
  OsiClpSolverInterface solver;
  load(solver, p);
  for (std::size_t i = 0; i < p.integer.size(); ++i)
    if (p.integer[i]) solver.setInteger(int(i));
  // CBC's standard driver (preprocessing, cut generators, primal heuristics): a bare
  // branchAndBound() has none of them and needs seconds where the driver needs milliseconds.
  CbcModel model(solver);
  CbcSolverUsefulData data;
  CbcMain0(model, data);
  model.setLogLevel(0);
  model.messageHandler()->setLogLevel(0);
  const std::string seconds = std::to_string(time_limit);
  const std::string gap = std::to_string(relative_gap);
  const std::string nodes = std::to_string(node_limit > 0 ? node_limit : 2147483647);
  const char* argv[] = {"isoquad",     "-log",        "0",         "-sec",      seconds.c_str(),
                        "-threads",    "0",           "-ratioGap", gap.c_str(), "-maxNodes",
                        nodes.c_str(), "-preprocess", "off",       "-solve",    "-quit"};
  CbcMain1(
      int(std::size(argv)), argv, model, [](CbcModel*, int) { return 0; }, data);
  MilpResult r;
  r.seconds = since(t0);
  const double* best = model.bestSolution();
  if (best) {
    r.x.assign(best, best + p.objective.size());
    r.objective = model.getObjValue();
    r.status = model.isProvenOptimal() && relative_gap == 0 ? MilpResult::Status::optimal
                                                            : MilpResult::Status::feasible;
  } else {
    r.status =
        model.isProvenInfeasible() ? MilpResult::Status::infeasible : MilpResult::Status::failed;
  }
  return r;
}

MilpResult solve_lp(const MilpProblem& p) {
  const auto t0 = std::chrono::steady_clock::now();
  OsiClpSolverInterface solver;
  load(solver, p);
  solver.initialSolve();
  MilpResult r;
  r.seconds = since(t0);
  if (solver.isProvenOptimal()) {
    r.x.assign(solver.getColSolution(), solver.getColSolution() + p.objective.size());
    r.objective = solver.getObjValue();
    r.status = MilpResult::Status::optimal;
  } else {
    r.status = solver.isProvenPrimalInfeasible() ? MilpResult::Status::infeasible
                                                 : MilpResult::Status::failed;
  }
  return r;
}

struct IncrementalLp::Basis {
  std::unique_ptr<CoinWarmStart> warm;
};

struct IncrementalLp::Impl {
  OsiClpSolverInterface solver;
  std::size_t columns = 0;
  bool solved = false;
};

IncrementalLp::IncrementalLp(const MilpProblem& p) : impl_(std::make_unique<Impl>()) {
  load(impl_->solver, p);
  impl_->columns = p.objective.size();
  // Room at the end of each column: set_coefficient on a new entry otherwise reallocates and
  // copies the whole column-ordered matrix.
  impl_->solver.getModelPtr()->matrix()->setExtraGap(2.0);
}

IncrementalLp::~IncrementalLp() = default;

void IncrementalLp::set_row_bounds(uint32_t row, double lo, double hi) {
  impl_->solver.setRowBounds(int(row), clamp_inf(lo), clamp_inf(hi));
}

std::shared_ptr<const IncrementalLp::Basis> IncrementalLp::basis() const {
  auto b = std::make_shared<Basis>();
  b->warm.reset(impl_->solver.getWarmStart());
  return b;
}

void IncrementalLp::set_basis(const Basis& basis) { impl_->solver.setWarmStart(basis.warm.get()); }

void IncrementalLp::set_coefficient(uint32_t row, uint32_t column, double value) {
  impl_->solver.getModelPtr()->modifyCoefficient(int(row), int(column), value, true);
}

MilpResult IncrementalLp::solve() {
  const auto t0 = std::chrono::steady_clock::now();
  OsiClpSolverInterface& solver = impl_->solver;
  if (impl_->solved)
    solver.resolve();
  else
    solver.initialSolve();
  impl_->solved = true;
  MilpResult r;
  r.seconds = since(t0);
  if (solver.isProvenOptimal()) {
    r.x.assign(solver.getColSolution(), solver.getColSolution() + impl_->columns);
    r.duals.assign(solver.getRowPrice(), solver.getRowPrice() + solver.getNumRows());
    r.objective = solver.getObjValue();
    r.status = MilpResult::Status::optimal;
  } else {
    r.status = solver.isProvenPrimalInfeasible() ? MilpResult::Status::infeasible
                                                 : MilpResult::Status::failed;
  }
  return r;
}

}  // namespace isoquad
