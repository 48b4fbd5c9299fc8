#include "layout/quantize.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>

#include "isoquad/error.hpp"
#include "layout/milp.hpp"

namespace isoquad {

std::vector<std::vector<uint8_t>> item_sides(const MetaMesh& meta,
                                             const std::vector<std::array<uint32_t, 4>>& corners) {
  std::vector<std::vector<uint8_t>> sides(meta.faces.size());
  for (uint32_t p = 0; p < meta.faces.size(); ++p) {
    const MetaFace& f = meta.faces[p];
    const auto& c = corners[p];
    uint32_t first = 0;  // corner whose meta-vertex id is smallest
    for (uint32_t k = 1; k < 4; ++k)
      if (f.start_vertex(c[k], meta.edges) < f.start_vertex(c[first], meta.edges)) first = k;
    sides[p].assign(f.cycle.size(), 0);
    for (uint32_t k = 0; k < 4; ++k) {
      const uint32_t from = c[(first + k) % 4], to = c[(first + k + 1) % 4];
      for (uint32_t i = from; i != to; i = (i + 1) % uint32_t(f.cycle.size()))
        sides[p][i] = uint8_t(k);
    }
  }
  return sides;
}

std::vector<SideRow> side_equations(const MetaMesh& meta,
                                    const std::vector<std::vector<uint8_t>>& sides) {
  std::vector<SideRow> rows;
  for (uint32_t p = 0; p < meta.faces.size(); ++p) {
    SideRow r[2];
    for (uint32_t i = 0; i < meta.faces[p].cycle.size(); ++i) {
      const uint8_t s = sides[p][i];
      r[s % 2].push_back({meta.faces[p].cycle[i].edge, s < 2 ? 1 : -1});
    }
    rows.push_back(std::move(r[0]));
    rows.push_back(std::move(r[1]));
  }
  return rows;
}

namespace {

// The maximal support in one LP: lengths x >= 0 satisfying the side equations and an indicator
// 0 <= t_e <= min(x_e, 1), maximizing the sum of t. The equations are homogeneous, so any
// solution scales: the optimum is the size of the largest support, with t_e = 1 on it (a sum of
// rounds each maximizing the edges not yet positive needed 2-4 LPs).
MilpProblem support_lp(uint32_t n, const std::vector<SideRow>& rows) {
  MilpProblem lp;
  for (uint32_t e = 0; e < n; ++e) lp.add_column(0, 0, MilpProblem::kInf, false);  // x
  for (uint32_t e = 0; e < n; ++e) lp.add_column(-1, 0, 1, false);                 // t
  for (const SideRow& r : rows) {
    MilpProblem::Row row;
    for (const auto& [e, sign] : r) row.columns.push_back(e), row.values.push_back(sign);
    row.lo = row.hi = 0;
    lp.add_row(std::move(row));
  }
  for (uint32_t e = 0; e < n; ++e) lp.add_row({{e, n + e}, {-1.0, 1.0}, -MilpProblem::kInf, 0});
  return lp;
}

Feasibility support_of(uint32_t n, const MilpResult& r) {
  Feasibility f;
  f.seconds = r.seconds;
  for (uint32_t e = 0; e < n; ++e)
    if (!r.found() || r.x[n + e] < 0.5) f.forced_zero.push_back(e);
  f.feasible = f.forced_zero.empty();
  return f;
}

}  // namespace

Feasibility check_feasibility(uint32_t n, const std::vector<SideRow>& rows) {
  return support_of(n, solve_lp(support_lp(n, rows)));
}

FeasibilityLp::FeasibilityLp(uint32_t n, const std::vector<SideRow>& rows)
    : n_(n), rows_(rows), lp_(std::make_unique<IncrementalLp>(support_lp(n, rows))) {
  lp_->solve();
  base_ = lp_->basis();
}

FeasibilityLp::~FeasibilityLp() = default;

void FeasibilityLp::write(uint32_t p, const SideRow& row0, const SideRow& row1) {
  // Clear what the rows held, then set the sums of the new terms (an edge may be met twice).
  for (uint32_t r = 0; r < 2; ++r) {
    for (const auto& [e, sign] : rows_[2 * p + r]) lp_->set_coefficient(2 * p + r, e, 0);
    std::vector<std::pair<uint32_t, int>> terms = r == 0 ? row0 : row1;
    std::sort(terms.begin(), terms.end());
    for (std::size_t i = 0; i < terms.size();) {
      const uint32_t e = terms[i].first;
      int sum = 0;
      for (; i < terms.size() && terms[i].first == e; ++i) sum += terms[i].second;
      lp_->set_coefficient(2 * p + r, e, sum);
    }
  }
}

Feasibility FeasibilityLp::test(uint32_t p, const SideRow& row0, const SideRow& row1) {
  write(p, row0, row1);
  lp_->set_basis(*base_);
  const Feasibility f = support_of(n_, lp_->solve());
  // Back to the base rows (their coefficients; the basis is reset before the next test).
  const SideRow old0 = rows_[2 * p], old1 = rows_[2 * p + 1];
  rows_[2 * p] = row0, rows_[2 * p + 1] = row1;
  write(p, old0, old1);
  rows_[2 * p] = old0, rows_[2 * p + 1] = old1;
  return f;
}

void FeasibilityLp::accept(uint32_t p, const SideRow& row0, const SideRow& row1) {
  write(p, row0, row1);
  rows_[2 * p] = row0, rows_[2 * p + 1] = row1;
  lp_->set_basis(*base_);
  lp_->solve();
  base_ = lp_->basis();
}

double stretch_slope(double c) { return 1.0 / std::max(c, 1.0); }

std::vector<CostSegment> shrink_segments(double c) {
  // Breakpoints: floor(c), then c/r for growing ratios r, floored, down to 1; the cost at a
  // breakpoint b is c/b - 1 exactly, linear in between (integer breakpoints, so the program and
  // the min-cost flow, which sees only integer lengths, price every integer alike).
  std::vector<CostSegment> out;
  if (c <= 1) return out;
  std::vector<double> b = {std::floor(c)};
  for (const double r : {1.25, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0, 24.0, 32.0, 64.0}) {
    const double x = std::max(1.0, std::floor(c / r));
    if (x < b.back()) b.push_back(x);
  }
  if (b.back() > 1) b.push_back(1);
  double x = c, cost = 0;
  for (const double next : b) {
    if (next >= x) continue;
    const double next_cost = c / next - 1;
    out.push_back({x - next, (next_cost - cost) / (x - next)});
    x = next;
    cost = next_cost;
  }
  return out;
}

double length_cost(double x, double c) {
  if (x >= c) return (x - c) * stretch_slope(c);
  double at = c, cost = 0;
  for (const CostSegment& s : shrink_segments(c)) {
    const double step = std::min(s.length, at - x);
    cost += step * s.slope;
    at -= step;
    if (at <= x) break;
  }
  return cost;
}

namespace {

// Ties `row` (the terms of a length: one x_e or a side's sum) to the target c through its
// deviation columns, added to `ilp`. For integer lengths the breakpoint at c is replaced by
// floor(c) and floor(c) + 1, which prices every integer the same:
// length - up - stretch + sum shrink_j = floor(c), the first unit up priced at
// d(floor + 1) - d(floor), and the shrink segments from floor(c) down. The relaxation is then
// tight between the two integers around c (the chord instead of the kink at c), and CBC needs
// fewer cuts and nodes.
void add_soft_target(MilpProblem& ilp, MilpProblem::Row row, double c, bool integer,
                     double weight = 1) {
  const std::vector<CostSegment> shrink = shrink_segments(c);
  const double base = std::floor(c);
  const bool chord = integer && c > 1 && base != c && !shrink.empty();
  row.lo = row.hi = chord ? base : c;
  if (chord) {
    row.columns.push_back(
        ilp.add_column(weight * (length_cost(base + 1, c) - length_cost(base, c)), 0, 1, false));
    row.values.push_back(-1);
  }
  row.columns.push_back(ilp.add_column(weight * stretch_slope(c), 0, MilpProblem::kInf, false));
  row.values.push_back(-1);
  for (std::size_t k = chord ? 1 : 0; k < shrink.size(); ++k) {  // shrink[0]: c to floor
    row.columns.push_back(ilp.add_column(weight * shrink[k].slope, 0, shrink[k].length, false));
    row.values.push_back(1);
  }
  ilp.add_row(std::move(row));
}

MilpProblem::Row side_sum(const std::vector<uint32_t>& edges) {
  MilpProblem::Row row;
  for (const uint32_t e : edges) row.columns.push_back(e), row.values.push_back(1);
  return row;
}

}  // namespace

MilpProblem length_problem(const std::vector<double>& c, const std::vector<SideRow>& rows,
                           bool bounded, bool integer, const std::vector<SideMinimum>& minimums,
                           const std::vector<SideTarget>& dimensions) {
  const uint32_t n = uint32_t(c.size());
  MilpProblem ilp;
  for (uint32_t e = 0; e < n; ++e)  // x_e; the bound keeps the search small, dropped if it bites
    ilp.add_column(0, 1, bounded ? std::max(4 * c[e], c[e] + 20) : MilpProblem::kInf, integer);
  for (uint32_t e = 0; e < n; ++e) add_soft_target(ilp, {{e}, {1}}, c[e], integer);
  for (const SideRow& r : rows) {
    MilpProblem::Row row;
    for (const auto& [e, sign] : r) row.columns.push_back(e), row.values.push_back(sign);
    row.lo = row.hi = 0;
    ilp.add_row(std::move(row));
  }
  for (const SideMinimum& m : minimums) {
    MilpProblem::Row row = side_sum(m.edges);
    row.lo = double(m.at_least);
    ilp.add_row(std::move(row));
  }
  for (const SideTarget& d : dimensions)
    add_soft_target(ilp, side_sum(d.edges), d.target, integer, d.weight);
  return ilp;
}

RelaxedLengths relaxed_length_problem(const std::vector<double>& c,
                                      const std::vector<SideRow>& rows) {
  const uint32_t n = uint32_t(c.size());
  RelaxedLengths r;
  r.target = c;
  for (uint32_t e = 0; e < n; ++e) {
    r.first.push_back(
        r.lp.add_column(stretch_slope(c[e]), std::max(0.0, 1 - c[e]), MilpProblem::kInf, false));
    for (const CostSegment& s : shrink_segments(c[e])) r.lp.add_column(s.slope, 0, s.length, false);
  }
  r.first.push_back(uint32_t(r.lp.objective.size()));
  for (const SideRow& side : rows) {
    const RelaxedLengths::Row image = r.row(side);
    MilpProblem::Row row;
    for (const auto& [j, v] : image.terms) row.columns.push_back(j), row.values.push_back(v);
    row.lo = row.hi = image.rhs;
    r.lp.add_row(std::move(row));
  }
  return r;
}

RelaxedLengths::Row RelaxedLengths::row(const SideRow& side) const {
  Row r;
  for (const auto& [e, sign] : side) {
    for (uint32_t j = first[e]; j < first[e + 1]; ++j)
      r.terms.push_back({j, j == first[e] ? sign : -sign});
    r.rhs -= sign * target[e];
  }
  std::sort(r.terms.begin(), r.terms.end());
  std::size_t out = 0;
  for (std::size_t i = 0; i < r.terms.size(); ++i)
    if (out > 0 && r.terms[out - 1].first == r.terms[i].first)
      r.terms[out - 1].second += r.terms[i].second;
    else
      r.terms[out++] = r.terms[i];
  r.terms.resize(out);
  return r;
}

std::vector<double> RelaxedLengths::lengths(const std::vector<double>& solution) const {
  std::vector<double> x(target.size());
  for (uint32_t e = 0; e < x.size(); ++e) {
    x[e] = target[e] + solution[first[e]];
    for (uint32_t j = first[e] + 1; j < first[e + 1]; ++j) x[e] -= solution[j];
  }
  return x;
}

namespace {

MilpResult length_ilp(const std::vector<double>& c, const std::vector<SideRow>& rows,
                      double time_limit, bool bounded, const std::vector<SideMinimum>& minimums,
                      const std::vector<SideTarget>& dimensions) {
  return solve_milp(length_problem(c, rows, bounded, true, minimums, dimensions), time_limit, 0,
                    kOptimalNodeLimit);
}

}  // namespace

Lengths solve_lengths(const std::vector<double>& c, const std::vector<SideRow>& rows,
                      double time_limit, const std::vector<SideMinimum>& minimums,
                      const std::vector<SideTarget>& dimensions) {
  const uint32_t n = uint32_t(c.size());
  MilpResult res = length_ilp(c, rows, time_limit, true, minimums, dimensions);
  if (!res.found()) res = length_ilp(c, rows, time_limit, false, minimums, dimensions);
  if (!res.found())
    throw Error(ErrorKind::solver, "E502",
                fmt::format("the integer length program found no solution in {} s", time_limit));
  Lengths out;
  out.solver = "cbc";
  out.seconds = res.seconds;
  out.optimal = res.status == MilpResult::Status::optimal;
  out.x.resize(n);
  for (uint32_t e = 0; e < n; ++e) {
    out.x[e] = std::llround(res.x[e]);
    out.objective += length_cost(double(out.x[e]), c[e]);
  }
  for (const SideTarget& d : dimensions) {
    int64_t sum = 0;
    for (const uint32_t e : d.edges) sum += out.x[e];
    out.objective += d.weight * length_cost(double(sum), d.target);
  }
  return out;
}

}  // namespace isoquad
