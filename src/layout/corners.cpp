#include "layout/corners.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "isoquad/error.hpp"
#include "layout/milp.hpp"
#include "seg/patch_topology.hpp"

namespace isoquad {

namespace {
constexpr double kPi = std::numbers::pi;
}

std::vector<int> quarter_turns(const MetaMesh& meta,
                               const std::vector<std::array<uint32_t, 4>>& corners) {
  std::vector<int> a(meta.vertices.size(), 0);
  for (uint32_t p = 0; p < meta.faces.size(); ++p) {
    const MetaFace& f = meta.faces[p];
    for (uint32_t i = 0; i < f.cycle.size(); ++i) {
      const bool corner = std::find(corners[p].begin(), corners[p].end(), i) != corners[p].end();
      a[f.start_vertex(i, meta.edges)] += corner ? 1 : 2;
    }
  }
  return a;
}

int regular_quarter_turns(const TriMesh& mesh, const MetaMesh& meta, uint32_t mv) {
  const MetaVertex& v = meta.vertices[mv];
  if (!v.on_boundary) return 4;
  const FaceData<uint32_t> none(mesh.num_faces(), 0);
  const double theta = patch_angle(mesh, none, v.vertex, kInvalid);
  return std::clamp(int(std::lround(theta / (kPi / 2))), 1, 3);
}

int target_quarter_turns(const TriMesh& mesh, const MetaMesh& meta, const LayoutOptions& o,
                         uint32_t mv) {
  const bool boundary = meta.vertices[mv].on_boundary;
  const std::vector<int>* field = o.field_quarter_turns;
  if (field && mv < field->size() && (*field)[mv] > 0)
    return std::clamp((*field)[mv], boundary ? 1 : 3, boundary ? 4 : 6);
  return regular_quarter_turns(mesh, meta, mv);
}

std::vector<std::vector<CornerCandidate>> corner_candidates(
    const TriMesh& mesh, const FaceData<uint32_t>& labels, const MetaMesh& meta, double beta,
    uint32_t keep, double unit, double flat_corner, double flat_crease_corner) {
  std::vector<std::vector<CornerCandidate>> out(meta.faces.size());
  for (uint32_t p = 0; p < meta.faces.size(); ++p) {
    const MetaFace& f = meta.faces[p];
    const uint32_t m = uint32_t(f.cycle.size());
    std::vector<double> len(m), theta(m);
    std::vector<char> flat_crease(m, 0);  // a straight crease runs through the item's start
    double theta_sum = 0;
    for (uint32_t i = 0; i < m; ++i) {
      len[i] = meta.edges[f.cycle[i].edge].geodesic;
      theta[i] = patch_angle(mesh, labels, meta.vertices[f.start_vertex(i, meta.edges)].vertex, p);
      theta_sum += theta[i];
      flat_crease[i] = meta.edges[f.cycle[i].edge].feature &&
                       meta.edges[f.cycle[(i + m - 1) % m].edge].feature && theta[i] > 5 * kPi / 6;
    }
    // Discrete Gauss-Bonnet: rescale so that the angles sum as in a flat m-gon, (m - 2) pi.
    for (double& t : theta) t *= (m - 2) * kPi / std::max(theta_sum, 1e-12);
    // Corner positions: all items, or the 12 that turn most on big patches.
    std::vector<uint32_t> allowed(m);
    for (uint32_t i = 0; i < m; ++i) allowed[i] = i;
    if (m > 16) {
      std::stable_sort(allowed.begin(), allowed.end(), [&](uint32_t a, uint32_t b) {
        return std::fabs(theta[a] - kPi) > std::fabs(theta[b] - kPi);
      });
      allowed.resize(12);
      std::sort(allowed.begin(), allowed.end());
    }
    std::vector<double> prefix(m + 1, 0);
    for (uint32_t i = 0; i < m; ++i) prefix[i + 1] = prefix[i] + len[i];
    auto side = [&](uint32_t a, uint32_t b) {  // items a .. b-1, cyclic
      return b > a ? prefix[b] - prefix[a] : prefix[m] - prefix[a] + prefix[b];
    };
    const uint32_t n = uint32_t(allowed.size());
    std::vector<CornerCandidate>& cands = out[p];
    for (uint32_t a = 0; a < n; ++a)
      for (uint32_t b = a + 1; b < n; ++b)
        for (uint32_t c = b + 1; c < n; ++c)
          for (uint32_t d = c + 1; d < n; ++d) {
            const std::array<uint32_t, 4> it = {allowed[a], allowed[b], allowed[c], allowed[d]};
            const double l0 = side(it[0], it[1]), l1 = side(it[1], it[2]), l2 = side(it[2], it[3]),
                         l3 = side(it[3], it[0]);
            // Facing sides should be equally long.
            auto mismatch = [&](double a, double b) {
              if (unit <= 0) return std::pow((a - b) / std::max(a + b, 1e-300), 2);
              a = std::max(a / unit, 1.0), b = std::max(b / unit, 1.0);
              return 0.5 * (std::sqrt(std::max(a, b) / std::min(a, b)) - 1);
            };
            const double e_len = mismatch(l0, l2) + mismatch(l1, l3);
            double e_ang = 0;
            for (uint32_t i = 0; i < m; ++i) {
              const bool corner = std::find(it.begin(), it.end(), i) != it.end();
              e_ang += std::pow((theta[i] - (corner ? kPi / 2 : kPi)) / (kPi / 2), 2);
              if (corner && theta[i] > 5 * kPi / 6) e_ang += flat_corner;
              if (corner && flat_crease[i]) e_ang += flat_crease_corner;
            }
            cands.push_back({it, e_len + beta * e_ang});
          }
    std::stable_sort(cands.begin(), cands.end(), [](auto& x, auto& y) { return x.cost < y.cost; });
    if (keep > 0 && cands.size() > keep) cands.resize(keep);
  }
  return out;
}

namespace {

// One ILP; `soft` replaces the hard valence bounds by penalized slacks.
// `feasible`: 0 plain, 1 feasibility-aware with the full objective, 2 feasibility only.
MilpResult corner_ilp(const TriMesh& mesh, const MetaMesh& meta,
                      const std::vector<std::vector<CornerCandidate>>& cands,
                      const LayoutOptions& o, int feasible, bool soft,
                      std::vector<std::vector<uint32_t>>& column) {
  MilpProblem lp;
  column.assign(cands.size(), {});
  for (uint32_t p = 0; p < cands.size(); ++p) {
    MilpProblem::Row one;
    for (const CornerCandidate& c : cands[p]) {
      column[p].push_back(lp.add_column(c.cost, 0, 1, true));
      one.columns.push_back(column[p].back());
      one.values.push_back(1);
    }
    one.lo = one.hi = 1;
    lp.add_row(std::move(one));
  }
  // a_v as a linear expression of the candidate choices.
  std::vector<MilpProblem::Row> a(meta.vertices.size());
  for (uint32_t p = 0; p < cands.size(); ++p) {
    const MetaFace& f = meta.faces[p];
    for (uint32_t i = 0; i < f.cycle.size(); ++i) {
      const uint32_t v = f.start_vertex(i, meta.edges);
      for (uint32_t c = 0; c < cands[p].size(); ++c) {
        const bool corner = std::find(cands[p][c].items.begin(), cands[p][c].items.end(), i) !=
                            cands[p][c].items.end();
        a[v].columns.push_back(column[p][c]);
        a[v].values.push_back(corner ? 1 : 2);
      }
    }
  }
  for (uint32_t v = 0; v < meta.vertices.size(); ++v) {
    const double tau = target_quarter_turns(mesh, meta, o, v);
    const bool boundary = meta.vertices[v].on_boundary;
    const uint32_t d = lp.add_column(o.valence_weight, 0, MilpProblem::kInf, false);
    MilpProblem::Row above = a[v], below = a[v];  // d >= |a - tau|
    above.columns.push_back(d), above.values.push_back(-1), above.hi = tau;
    below.columns.push_back(d), below.values.push_back(1), below.lo = tau;
    lp.add_row(std::move(above));
    lp.add_row(std::move(below));
    // Valence 2 (or less) inside and 0 on the boundary are degenerate; above 6 (4) is wasteful.
    MilpProblem::Row bounds = a[v];
    bounds.lo = boundary ? 1 : 3;
    bounds.hi = boundary ? 4 : 6;
    if (soft) {
      const uint32_t up = lp.add_column(10 * o.valence_weight, 0, MilpProblem::kInf, false);
      const uint32_t down = lp.add_column(10 * o.valence_weight, 0, MilpProblem::kInf, false);
      bounds.columns.insert(bounds.columns.end(), {up, down});
      bounds.values.insert(bounds.values.end(), {-1, 1});
    }
    lp.add_row(std::move(bounds));
  }
  if (feasible) {
    // Lengths are homogeneous, so [1, U] loses nothing but ratios above U.
    constexpr double kU = 100;
    std::vector<uint32_t> x(meta.edges.size());
    for (uint32_t e = 0; e < x.size(); ++e) x[e] = lp.add_column(0, 1, kU, false);
    for (uint32_t p = 0; p < cands.size(); ++p) {
      const MetaFace& f = meta.faces[p];
      const uint32_t m = uint32_t(f.cycle.size());
      const double big = kU * m;
      for (uint32_t c = 0; c < cands[p].size(); ++c) {
        const auto& it = cands[p][c].items;
        MilpProblem::Row pair[2];
        for (uint32_t k = 0; k < 4; ++k)
          for (uint32_t i = it[k]; i != it[(k + 1) % 4]; i = (i + 1) % m) {
            pair[k % 2].columns.push_back(x[f.cycle[i].edge]);
            pair[k % 2].values.push_back(k < 2 ? 1 : -1);
          }
        for (auto& row : pair) {  // -M (1 - y) <= side difference <= M (1 - y)
          MilpProblem::Row up = row, down = row;
          up.columns.push_back(column[p][c]), up.values.push_back(big), up.hi = big;
          down.columns.push_back(column[p][c]), down.values.push_back(-big), down.lo = -big;
          lp.add_row(std::move(up));
          lp.add_row(std::move(down));
        }
      }
    }
  }
  if (feasible == 2) {  // any feasible choice: a pure feasibility problem, found fast
    std::fill(lp.objective.begin(), lp.objective.end(), 0.0);
    return solve_milp(lp, o.time_limit, 0, kOptimalNodeLimit);
  }
  // The feasibility-aware program is a repair: a choice within 5% of the best, found within 200
  // branch-and-bound nodes (a bound on effort that does not depend on the machine's speed), is
  // good enough; the feasibility-only choice is the fallback.
  if (feasible) return solve_milp(lp, o.time_limit, 0.05, 200);
  return solve_milp(lp, o.time_limit, 0, kOptimalNodeLimit);
}

}  // namespace

CornerChoice choose_corners(const TriMesh& mesh, const MetaMesh& meta,
                            const std::vector<std::vector<CornerCandidate>>& cands,
                            const LayoutOptions& o, bool require_feasible) {
  CornerChoice r;
  const uint32_t n = uint32_t(cands.size());
  r.chosen.assign(n, 0);
  if (o.corners == CornerMode::global || require_feasible) {
    std::vector<std::vector<uint32_t>> column;
    MilpResult res;
    if (require_feasible) {
      // First any feasible choice (fast), then the best one if CBC finds it in time.
      const MilpResult any = corner_ilp(mesh, meta, cands, o, 2, true, column);
      r.seconds += any.seconds;
      if (any.found()) {
        res = corner_ilp(mesh, meta, cands, o, 1, true, column);
        r.seconds += res.seconds;
        if (!res.found()) res = any;
        r.softened = true;
      }
    } else {
      res = corner_ilp(mesh, meta, cands, o, 0, false, column);
      r.seconds += res.seconds;
      if (!res.found()) {
        res = corner_ilp(mesh, meta, cands, o, 0, true, column);
        r.seconds += res.seconds;
        r.softened = true;
      }
    }
    if (!res.found())
      throw Error(ErrorKind::layout, "E401",
                  require_feasible
                      ? "no choice among the corner candidates admits positive meta-edge lengths"
                      : "no corner assignment found");
    for (uint32_t p = 0; p < n; ++p)
      for (uint32_t c = 0; c < column[p].size(); ++c)
        if (res.x[column[p][c]] > 0.5) r.chosen[p] = c;
  }  // local: the best candidate of each patch (index 0), the paper's choice
  r.corners.resize(n);
  for (uint32_t p = 0; p < n; ++p) {
    r.corners[p] = cands[p][r.chosen[p]].items;
    r.cost += cands[p][r.chosen[p]].cost;
  }
  r.quarter_turns = quarter_turns(meta, r.corners);
  return r;
}

}  // namespace isoquad
