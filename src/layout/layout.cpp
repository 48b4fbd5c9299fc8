#include "layout/layout.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <set>
#include <tuple>

#include <tbb/parallel_for.h>

#include "isoquad/error.hpp"
#include "layout/charts.hpp"
#include "layout/corners.hpp"
#include "layout/flow.hpp"
#include "layout/milp.hpp"
#include "layout/quantize.hpp"
#include "pipeline/sizing.hpp"
#include "seg/segment.hpp"

namespace isoquad {

namespace {

struct Feasible {
  CornerChoice corners;
  std::vector<std::vector<uint8_t>> sides;
  std::vector<SideRow> rows;
};

// A cheap first repair: patches along the forced-zero meta-edges try their next candidates,
// one at a time, in patch order; a change is kept when it shrinks the forced-zero set without
// leaving the valence bounds. Each try is one exact feasibility test (an LP, milliseconds),
// against a second for the feasibility-aware ILP that remains the fallback. The tests share one
// LP, each started from the current corners' optimal basis.
bool greedy_feasible(const MetaMesh& meta, const std::vector<std::vector<CornerCandidate>>& cands,
                     Feasible& f, std::vector<uint32_t> zero, LayoutReport& report) {
  const auto t0 = std::chrono::steady_clock::now();
  const uint32_t n = uint32_t(meta.edges.size());
  auto valences_ok = [&](const std::vector<std::array<uint32_t, 4>>& corners) {
    const std::vector<int> a = quarter_turns(meta, corners);
    for (uint32_t v = 0; v < a.size(); ++v) {
      const bool b = meta.vertices[v].on_boundary;
      if (a[v] < (b ? 1 : 3) || a[v] > (b ? 4 : 6)) return false;
    }
    return true;
  };
  uint32_t changed = 0;
  bool feasible = false;
  FeasibilityLp lp(n, f.rows);  // the trials differ from the current corners in one patch
  for (int round = 0; round < 3 && !feasible && !zero.empty(); ++round) {
    std::vector<uint32_t> patches;
    for (const uint32_t e : zero) {
      patches.push_back(meta.edges[e].left);
      if (meta.edges[e].right != kInvalid) patches.push_back(meta.edges[e].right);
    }
    std::sort(patches.begin(), patches.end());
    patches.erase(std::unique(patches.begin(), patches.end()), patches.end());
    bool progress = false;
    for (const uint32_t p : patches) {
      if (feasible) break;
      for (uint32_t k = 0; k < cands[p].size(); ++k) {
        const CornerCandidate& c = cands[p][k];
        if (c.items == f.corners.corners[p]) continue;
        auto corners = f.corners.corners;
        corners[p] = c.items;
        if (!valences_ok(corners)) continue;
        const auto rows = side_equations(meta, item_sides(meta, corners));
        const Feasibility t = lp.test(p, rows[2 * p], rows[2 * p + 1]);
        if (!t.feasible && t.forced_zero.size() >= zero.size()) continue;
        lp.accept(p, rows[2 * p], rows[2 * p + 1]);
        f.corners.corners = corners;
        if (p < f.corners.chosen.size()) f.corners.chosen[p] = k;
        zero = t.forced_zero;
        feasible = t.feasible;
        progress = true;
        ++changed;
        break;
      }
    }
    if (!progress) break;
  }
  report.corner_seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!feasible) return false;
  f.corners.quarter_turns = quarter_turns(meta, f.corners.corners);
  f.sides = item_sides(meta, f.corners.corners);
  f.rows = side_equations(meta, f.sides);
  report.repairs.push_back(
      fmt::format("corners of {} patches along them re-chosen one by one", changed));
  return true;
}

// Patch p's corners `items` with one of them moved to the neighbouring meta-vertex of the cycle
// over a meta-edge shorter than `unit` (its geodesic length), each at a price that grows with
// the length it moves over. The corners stay distinct and in their cyclic order.
std::vector<CornerCandidate> slid_corners(const MetaMesh& meta, uint32_t p,
                                          const std::array<uint32_t, 4>& items, double unit) {
  std::vector<CornerCandidate> out;
  const auto& cycle = meta.faces[p].cycle;
  const uint32_t m = uint32_t(cycle.size());
  if (m <= 4 || !(unit > 0)) return out;
  for (int k = 0; k < 4; ++k)
    for (const int step : {-1, 1}) {
      const uint32_t from = items[k];
      const uint32_t to = uint32_t((int64_t(from) + step + m) % m);
      // The edge passed over: item `from`'s forward, item `to`'s backward.
      const uint32_t edge = cycle[step > 0 ? from : to].edge;
      const double length = meta.edges[edge].geodesic / unit;
      if (!(length < 1)) continue;
      if (std::find(items.begin(), items.end(), to) != items.end()) continue;
      std::array<uint32_t, 4> moved = items;
      moved[k] = to;
      std::sort(moved.begin(), moved.end());
      // Same cyclic order: the moved corner keeps its neighbours (it passed none).
      out.push_back({moved, kPreferredCornersPenalty * (1 + length)});
    }
  return out;
}

// Corners whose side equations admit positive lengths: the plain choice if it is feasible, else
// the feasibility-aware ILP over the best candidates, then over many more. Empty if none is
// found; `zero` then holds the forced-zero meta-edges of the plain choice.
std::optional<Feasible> feasible_corners(const TriMesh& mesh, const FaceData<uint32_t>& labels,
                                         const MetaMesh& meta, const LayoutOptions& o, double unit,
                                         LayoutReport& report, std::vector<uint32_t>& zero) {
  if (o.given_corners) {
    const auto& given = *o.given_corners;
    const std::vector<char>* preferred = o.preferred_corners;
    // slide: each given corner may also move to a neighbouring meta-vertex of its patch over a
    // meta-edge shorter than a quad (one end of a trace that stopped a fraction of a quad from a
    // node or another end): an integer layout cannot keep such an edge, and where a strip closes
    // around a tube the side equations force it to length 0.
    auto attempt = [&](bool slide) -> std::optional<Feasible> {
      Feasible f;
      const bool choose =
          slide || std::find(given.begin(), given.end(), kFreeCorners) != given.end() ||
          (preferred && std::find(preferred->begin(), preferred->end(), 1) != preferred->end());
      if (choose) {
        // The free patches choose among their candidates, the preferred ones too at a price, the
        // others keep what they were given (or slide it, at a price), in one exact corner ILP
        // that also asks for positive lengths.
        auto cands =
            corner_candidates(mesh, labels, meta, o.angle_weight, 4 * o.candidates_per_patch, unit,
                              o.flat_corner_penalty, o.flat_crease_corner_penalty);
        for (uint32_t p = 0; p < given.size(); ++p) {
          if (given[p] == kFreeCorners) continue;
          std::vector<CornerCandidate> soft{CornerCandidate{given[p], 0.0}};
          if (preferred && (*preferred)[p])
            for (const CornerCandidate& c : cands[p])
              if (c.items != given[p]) soft.push_back({c.items, c.cost + kPreferredCornersPenalty});
          if (slide)
            for (const CornerCandidate& c : slid_corners(meta, p, given[p], unit))
              if (std::none_of(soft.begin(), soft.end(),
                               [&](const CornerCandidate& s) { return s.items == c.items; }))
                soft.push_back(c);
          cands[p] = std::move(soft);
        }
        try {
          f.corners = choose_corners(mesh, meta, cands, o, true);
        } catch (const Error& e) {
          if (e.code() != "E401") throw;
          return std::nullopt;
        }
        ++report.corner_rounds;
        report.corner_seconds += f.corners.seconds;
      } else {
        f.corners.corners = given;
        f.corners.chosen.assign(meta.faces.size(), 0);
      }
      f.corners.quarter_turns = quarter_turns(meta, f.corners.corners);
      f.sides = item_sides(meta, f.corners.corners);
      f.rows = side_equations(meta, f.sides);
      const Feasibility test = check_feasibility(uint32_t(meta.edges.size()), f.rows);
      report.corner_seconds += test.seconds;
      if (!test.feasible) return std::nullopt;
      return f;
    };
    // No insertion: it would renumber the cycles the given corners index.
    if (auto f = attempt(false)) return f;
    auto f = attempt(true);
    if (f) {
      uint32_t moved = 0;
      for (uint32_t p = 0; p < given.size(); ++p)
        moved += given[p] != kFreeCorners && f->corners.corners[p] != given[p] &&
                 !(preferred && (*preferred)[p]);
      report.repairs.push_back(fmt::format(
          "corners of {} traced patches slid over meta-edges shorter than a quad", moved));
    }
    return f;
  }
  for (const uint32_t keep :
       {o.candidates_per_patch, o.candidates_per_patch, 4 * o.candidates_per_patch}) {
    const bool exact = report.corner_rounds > 0;
    const auto cands = corner_candidates(mesh, labels, meta, o.angle_weight, keep, unit,
                                         o.flat_corner_penalty, o.flat_crease_corner_penalty);
    Feasible f;
    try {
      f.corners = choose_corners(mesh, meta, cands, o, exact);
    } catch (const Error& e) {
      if (e.code() != "E401") throw;
      ++report.corner_rounds;
      continue;
    }
    ++report.corner_rounds;
    report.corner_seconds += f.corners.seconds;
    f.sides = item_sides(meta, f.corners.corners);
    f.rows = side_equations(meta, f.sides);
    const Feasibility test = check_feasibility(uint32_t(meta.edges.size()), f.rows);
    report.corner_seconds += test.seconds;
    if (test.feasible) {
      if (exact)
        report.repairs.push_back(fmt::format(
            "corners re-chosen by the feasibility-aware ILP ({} candidates per patch)", keep));
      return f;
    }
    if (!exact) {
      zero = test.forced_zero;
      report.repairs.push_back(
          fmt::format("the best corners force {} meta-edges to length 0", zero.size()));
      if (greedy_feasible(meta, cands, f, test.forced_zero, report)) return f;
    }
  }
  return std::nullopt;
}

// DESIGN.md §5.4 step 2: a meta-vertex at the middle of each forced-zero meta-edge (that has a
// vertex inside) gives the patches an even side count to balance. Returns false if none fits.
bool insert_on_zero_edges(const TriMesh& mesh, const FaceData<uint32_t>& labels,
                          const EdgeData<char>& feature, MetaMesh& meta,
                          const std::vector<uint32_t>& zero, LayoutReport& report) {
  MetaMeshOptions again;
  again.forced = meta.inserted_vertices;
  uint32_t added = 0;
  for (uint32_t e : zero) {
    const MetaEdge& me = meta.edges[e];
    if (me.vertices.size() < 3) continue;
    again.forced.push_back(me.vertices[me.vertices.size() / 2]);
    ++added;
  }
  if (added == 0) return false;
  const uint32_t before = meta.inserted;
  meta = build_meta_mesh(mesh, labels, uint32_t(meta.faces.size()), feature, again);
  meta.inserted = before + added;
  measure_geodesic_lengths(mesh, labels, meta);
  report.repairs.push_back(
      fmt::format("inserted {} meta-vertices on forced-zero meta-edges", added));
  return true;
}

// Local improvement of the corners (beyond the paper): per patch, its four best candidates are
// tried in place of its corners, and the best is kept when the LP relaxation of the length
// program plus the corner and valence costs drops. The corner ILP sees the side lengths of each
// patch alone; this sees how the side equations of all patches interact. One sweep: on fandisk,
// bunny00, elephant, cactus, knot1 and anchor the four best candidates of one sweep gave 73-80%
// of the objective drop of eight candidates over two sweeps, at a quarter of the LP solves.
// The four trials of a patch run in parallel, each on its own LP (so each LP's warm starts, and
// the result, do not depend on thread timing); ties go to the better-ranked candidate.
void improve_corners(const TriMesh& mesh, const FaceData<uint32_t>& labels, const MetaMesh& meta,
                     const LayoutOptions& o, double unit, const std::vector<double>& targets,
                     Feasible& f, LayoutReport& report) {
  const auto t0 = std::chrono::steady_clock::now();
  const uint32_t np = uint32_t(meta.faces.size());
  const auto all = corner_candidates(mesh, labels, meta, o.angle_weight, 0, unit,
                                     o.flat_corner_penalty, o.flat_crease_corner_penalty);
  auto cost_of = [&](uint32_t p, const std::array<uint32_t, 4>& c) -> double {
    std::array<uint32_t, 4> s = c;
    std::sort(s.begin(), s.end());
    for (const CornerCandidate& k : all[p])
      if (k.items == s) return k.cost;
    return INFINITY;
  };
  std::vector<int> tau(meta.vertices.size());
  for (uint32_t v = 0; v < tau.size(); ++v) tau[v] = target_quarter_turns(mesh, meta, o, v);
  auto total = [&](const std::vector<std::array<uint32_t, 4>>& corners, double lp) -> double {
    double t = lp;
    for (uint32_t p = 0; p < np; ++p) t += cost_of(p, corners[p]);
    const std::vector<int> a = quarter_turns(meta, corners);
    for (uint32_t v = 0; v < a.size(); ++v) {
      const bool b = meta.vertices[v].on_boundary;
      if (a[v] < (b ? 1 : 3) || a[v] > (b ? 4 : 6)) return INFINITY;
      t += o.improve_valence_weight * std::abs(a[v] - tau[v]);
    }
    return t;
  };
  std::vector<std::array<uint32_t, 4>> corners = f.corners.corners;
  // One LP per trial slot, re-solved after each change: changing a patch's corners only
  // rewrites its two side rows. Each trial starts from the basis of the current corners' optimum,
  // which differs from the trial's only around the patch.
  constexpr uint32_t kSlots = 4;
  const RelaxedLengths relaxed = relaxed_length_problem(targets, f.rows);
  std::vector<std::unique_ptr<IncrementalLp>> lps(kSlots);
  std::vector<double> value(kSlots, INFINITY);
  // Patch p's two rows for corners c.
  auto patch_rows = [&](uint32_t p, const std::array<uint32_t, 4>& c) {
    std::array<uint32_t, 4> sorted = c;
    std::sort(sorted.begin(), sorted.end());
    const MetaFace& face = meta.faces[p];
    const uint32_t m = uint32_t(face.cycle.size());
    // Side of each item: corners split the cycle into four runs; which run is side 0 does not
    // matter for the rows (they are side 0 - side 2 and side 1 - side 3, up to sign).
    SideRow side[2];
    for (uint32_t k = 0; k < 4; ++k)
      for (uint32_t i = sorted[k]; i != sorted[(k + 1) % 4]; i = (i + 1) % m)
        side[k % 2].push_back({face.cycle[i].edge, k < 2 ? 1 : -1});
    return std::array<RelaxedLengths::Row, 2>{relaxed.row(side[0]), relaxed.row(side[1])};
  };
  auto set_rows = [&](IncrementalLp& lp, uint32_t p, const std::array<uint32_t, 4>& c) {
    const auto rows = patch_rows(p, c);
    for (uint32_t r = 0; r < 2; ++r) {
      for (const BoundaryItem& item : meta.faces[p].cycle)
        for (uint32_t j = relaxed.first[item.edge]; j < relaxed.first[item.edge + 1]; ++j)
          lp.set_coefficient(2 * p + r, j, 0);
      for (const auto& [j, v] : rows[r].terms) lp.set_coefficient(2 * p + r, j, v);
      lp.set_row_bounds(2 * p + r, rows[r].rhs, rows[r].rhs);
    }
  };
  // Exact pruning: a lower bound on a trial's LP optimum from Lagrangian duality. At the current
  // optimum's row prices y the dual function equals the optimum; a trial rewrites patch p's two
  // rows, and for any prices (u, w) on the new rows, with y kept on the others, the dual function
  // is still a lower bound. It is cheap: only the columns of p's meta-edges change. (u, w) is the
  // best of 0 and +-the old prices of p's rows in either order: on fandisk this prunes 31 of 89
  // trials, an exact optimization of (u, w) one more.
  std::vector<RelaxedLengths::Row> rows_now(relaxed.lp.rows.size());
  for (uint32_t r = 0; r < rows_now.size(); ++r) {
    const MilpProblem::Row& row = relaxed.lp.rows[r];
    for (std::size_t i = 0; i < row.columns.size(); ++i)
      rows_now[r].terms.push_back({row.columns[i], row.values[i]});
    rows_now[r].rhs = row.lo;
  }
  std::vector<double> y, reduced;  // current prices, and reduced costs c - A^T y
  double dual_value = 0;
  auto column_min = [&](uint32_t j, double d) {  // min of d x over column j's bounds
    if (std::fabs(d) <= 1e-9) return 0.0;        // within the dual tolerance
    const double bound = d > 0 ? relaxed.lp.col_lo[j] : relaxed.lp.col_hi[j];
    return std::isfinite(bound) ? d * bound : -INFINITY;
  };
  auto set_prices = [&](const std::vector<double>& prices) {
    y = prices;
    reduced = relaxed.lp.objective;
    dual_value = 0;
    for (uint32_t r = 0; r < rows_now.size(); ++r) {
      dual_value += y[r] * rows_now[r].rhs;
      for (const auto& [j, v] : rows_now[r].terms) reduced[j] -= y[r] * v;
    }
    for (uint32_t j = 0; j < reduced.size(); ++j) dual_value += column_min(j, reduced[j]);
  };
  auto lower_bound = [&](uint32_t p, const std::array<RelaxedLengths::Row, 2>& trial) {
    double rest = dual_value;  // the dual function without p's rows and columns
    std::vector<std::tuple<uint32_t, double, double, double>> terms;  // column, d, a, b
    for (uint32_t r = 2 * p; r < 2 * p + 2; ++r) {
      rest -= y[r] * rows_now[r].rhs;
      for (const auto& [j, v] : rows_now[r].terms) terms.push_back({j, y[r] * v, 0, 0});
    }
    for (uint32_t r = 0; r < 2; ++r)
      for (const auto& [j, v] : trial[r].terms)
        terms.push_back({j, 0, r == 0 ? v : 0, r == 1 ? v : 0});
    std::sort(terms.begin(), terms.end());
    std::vector<std::tuple<uint32_t, double, double, double>> cols;  // merged by column
    for (const auto& [j, d, a, b] : terms) {
      if (cols.empty() || std::get<0>(cols.back()) != j) {
        rest -= column_min(j, reduced[j]);
        cols.push_back({j, reduced[j], 0, 0});
      }
      std::get<1>(cols.back()) += d;
      std::get<2>(cols.back()) += a;
      std::get<3>(cols.back()) += b;
    }
    const double ya = y[2 * p], yb = y[2 * p + 1];
    double best_bound = -INFINITY;
    for (const double u : {0.0, ya, -ya, yb, -yb})
      for (const double w : {0.0, ya, -ya, yb, -yb}) {
        double bound = rest + u * trial[0].rhs + w * trial[1].rhs;
        for (const auto& [j, d, a, b] : cols) bound += column_min(j, d - u * a - w * b);
        best_bound = std::max(best_bound, bound);
      }
    return best_bound;
  };
  std::vector<std::vector<double>> prices(kSlots);
  auto lp_value = [&](uint32_t k) {
    const MilpResult r = lps[k]->solve();
    prices[k] = r.duals;
    return r.found() ? r.objective : INFINITY;
  };
  std::vector<std::shared_ptr<const IncrementalLp::Basis>> basis(kSlots);
  tbb::parallel_for(0u, kSlots, [&](uint32_t k) {
    lps[k] = std::make_unique<IncrementalLp>(relaxed.lp);
    value[k] = lp_value(k);
  });
  std::shared_ptr<const IncrementalLp::Basis> base = lps[0]->basis();
  double best = total(corners, value[0]);
  if (!std::isfinite(best)) return;
  set_prices(prices[0]);
  uint32_t changed = 0;
  for (uint32_t p = 0; p < np; ++p) {
    std::vector<std::array<uint32_t, 4>> trials;
    std::array<uint32_t, 4> current = corners[p];
    std::sort(current.begin(), current.end());
    for (uint32_t c = 0; c < std::min<uint32_t>(kSlots, uint32_t(all[p].size())); ++c) {
      if (all[p][c].items == current) continue;
      auto trial = corners;
      trial[p] = all[p][c].items;
      if (std::isfinite(total(trial, 0)) &&
          (!o.prune_corner_trials ||
           total(trial, lower_bound(p, patch_rows(p, all[p][c].items))) < best + 1e-6))
        trials.push_back(all[p][c].items);
    }
    tbb::parallel_for(0u, uint32_t(trials.size()), [&](uint32_t k) {
      set_rows(*lps[k], p, trials[k]);
      lps[k]->set_basis(*base);
      value[k] = lp_value(k);
      basis[k] = lps[k]->basis();
      set_rows(*lps[k], p, corners[p]);
    });
    int pick = -1;
    double pick_total = best - 1e-9;
    for (uint32_t k = 0; k < trials.size(); ++k) {
      auto trial = corners;
      trial[p] = trials[k];
      const double t = total(trial, value[k]);
      if (t < pick_total) pick_total = t, pick = int(k);
    }
    if (pick < 0) continue;
    best = pick_total;
    corners[p] = trials[pick];
    base = basis[pick];  // the optimal basis of the new corners, and its prices
    for (const auto& lp : lps) set_rows(*lp, p, corners[p]);
    const auto rows = patch_rows(p, corners[p]);
    rows_now[2 * p] = rows[0];
    rows_now[2 * p + 1] = rows[1];
    set_prices(prices[pick]);
    ++changed;
  }
  if (changed > 0) {
    f.corners.corners = corners;
    f.corners.quarter_turns = quarter_turns(meta, corners);
    f.sides = item_sides(meta, corners);
    f.rows = side_equations(meta, f.sides);
    report.repairs.push_back(
        fmt::format("corners of {} patches improved for the lengths", changed));
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  report.corner_seconds += seconds;
  report.refine_seconds += seconds;
}

}  // namespace

namespace {

std::vector<double> patch_areas(const TriMesh& mesh, const FaceData<uint32_t>& labels,
                                uint32_t num_patches) {
  std::vector<double> area(num_patches, 0.0);
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) area[labels[f]] += mesh.face_area(f);
  return area;
}

std::vector<SideTarget> area_dimensions(const MetaMesh& meta,
                                        const std::vector<std::vector<uint8_t>>& sides,
                                        const std::vector<double>& area, double h,
                                        double threshold) {
  std::vector<SideTarget> out;
  if (threshold <= 0) return out;
  for (uint32_t p = 0; p < meta.faces.size(); ++p) {
    const MetaFace& face = meta.faces[p];
    double length[4] = {0, 0, 0, 0};
    std::vector<uint32_t> edges[2];
    for (uint32_t i = 0; i < face.cycle.size(); ++i) {
      const uint8_t side = sides[p][i];
      length[side] += meta.edges[face.cycle[i].edge].geodesic;
      if (side < 2) edges[side].push_back(face.cycle[i].edge);
    }
    const double dim[2] = {0.5 * (length[0] + length[2]), 0.5 * (length[1] + length[3])};
    const int along = dim[0] >= dim[1] ? 0 : 1, across = 1 - along;
    if (dim[along] <= 0) continue;
    // The mean width across the longer dimension: area over its length.
    const double mean = area[p] / dim[along];
    if (mean <= threshold * dim[across]) continue;
    std::sort(edges[across].begin(), edges[across].end());
    // Weighed by the patch's length in quads: the width is that many rows' width, where a
    // meta-edge's target is one edge's (at the weight of one meta-edge, mech-holes-shark's lens,
    // sides of 1.6 and 0.2 quads and a mean width of 5.6, stayed 2 quads wide).
    out.push_back({std::move(edges[across]), mean / h, dim[along] / h});
  }
  return out;
}

}  // namespace

// The integer lengths at edge length h, or (by_count) at the h, tuned from the one given (up to
// h_max), whose quad count comes nearest `wanted`; `layout` gets the lengths, targets and h of
// that solve.
Lengths tune_lengths(const MetaMesh& meta, const std::vector<std::vector<uint8_t>>& sides,
                     const std::vector<SideRow>& rows, const std::vector<SideMinimum>& minimums,
                     const std::vector<double>& area, bool by_count, double wanted,
                     const LayoutOptions& o, double h, Layout& layout, LayoutReport& report,
                     double h_max = INFINITY) {
  // Tune h so that the quad count lands near the request: area scales with 1/h^2.
  Lengths best;
  double best_h = h, best_miss = INFINITY;
  double h_small = 0, h_large = INFINITY;  // bracket: too many quads at h_small, too few at h_large
  for (int round = 0; round < (by_count ? 8 : 1); ++round) {
    std::vector<double> c(meta.edges.size());
    for (uint32_t e = 0; e < c.size(); ++e) c[e] = meta.edges[e].geodesic / h;
    const std::vector<SideTarget> dims =
        area_dimensions(meta, sides, area, h, o.area_dimension_threshold);
    std::optional<Lengths> flow;
    if (o.length_solver == LengthSolver::flow && minimums.empty() && dims.empty())
      flow = solve_lengths_flow(c, rows);
    Lengths l = flow ? *flow : solve_lengths(c, rows, o.time_limit, minimums, dims);
    ++report.size_rounds;
    report.length_seconds += l.seconds;
    layout.length = l.x;
    build_charts(meta, sides, layout);
    const double q = double(layout.quads());
    const double miss = std::fabs(q - wanted) / wanted;
    if (miss < best_miss) best_miss = miss, best = l, best_h = h;
    // The count is a step function of h (1,440 or 1,546 quads on fandisk, nothing between), so
    // 5% is accepted and the search ends once the bracket is too narrow to hold another step.
    if (!by_count || miss <= 0.05) break;
    (q > wanted ? h_small : h_large) = h;
    if (h_small > 0 && h_large < 1.003 * h_small) break;
    // Area scales with 1/h^2; once both sides are known, bisect (geometrically) inside them.
    const double next =
        std::min(h_max, h_small > 0 && h_large < INFINITY ? std::sqrt(h_small * h_large)
                                                          : h * std::sqrt(q / wanted));
    if (next == h) break;
    h = next;
  }
  layout.length = best.x;
  layout.objective = best.objective;
  layout.edge_length = best_h;
  layout.target.resize(meta.edges.size());
  for (uint32_t e = 0; e < meta.edges.size(); ++e)
    layout.target[e] = meta.edges[e].geodesic / best_h;
  return best;
}

std::vector<uint32_t> misfit_patches(const MetaMesh& meta, const Layout& layout, double ratio) {
  std::vector<uint32_t> out;
  for (uint32_t p = 0; p < meta.faces.size(); ++p) {
    double side[4] = {0, 0, 0, 0};
    const Chart& chart = layout.charts[p];
    for (uint32_t i = 0; i < meta.faces[p].cycle.size(); ++i)
      side[chart.item_side[i]] += layout.target[meta.faces[p].cycle[i].edge];
    for (int d = 0; d < 2; ++d) {
      const double longer = std::max(side[d], side[d + 2]);
      const double shorter = std::min(side[d], side[d + 2]);
      if (longer - shorter >= 3 && longer > ratio * std::max(shorter, 0.5)) {
        out.push_back(p);
        break;
      }
    }
  }
  return out;
}

std::vector<double> Layout::length_ratios() const {
  std::vector<double> ratio;
  for (uint32_t e = 0; e < length.size(); ++e)
    if (target[e] > 0) ratio.push_back(double(length[e]) / target[e]);
  std::sort(ratio.begin(), ratio.end());
  return ratio;
}

Layout solve_layout(const TriMesh& mesh, const FaceData<uint32_t>& labels,
                    const EdgeData<char>& feature, MetaMesh& meta, const LayoutOptions& o,
                    LayoutReport& report) {
  const bool by_count = o.edge_length <= 0;
  const double wanted =
      o.quads > 0 ? o.quads : default_quad_count(mesh.num_faces(), o.default_share);
  double h = by_count ? edge_length_for_quads(mesh, wanted) : o.edge_length;
  std::optional<Feasible> f;
  for (int insertion = 0; insertion < 4 && !f; ++insertion) {
    std::vector<uint32_t> zero;
    f = feasible_corners(mesh, labels, meta, o, h, report, zero);
    if (!f && !insert_on_zero_edges(mesh, labels, feature, meta, zero, report)) break;
  }
  if (!f)
    throw Error(ErrorKind::layout, "E402",
                "no corner assignment or meta-vertex insertion makes the integer lengths feasible");

  if (o.improve_corners && !o.given_corners) {
    std::vector<double> targets(meta.edges.size());
    for (uint32_t e = 0; e < targets.size(); ++e) targets[e] = meta.edges[e].geodesic / h;
    improve_corners(mesh, labels, meta, o, h, targets, *f, report);
  }
  Layout layout;
  layout.quarter_turns = f->corners.quarter_turns;
  uint32_t tiny = 0;
  for (const MetaEdge& e : meta.edges) tiny += e.geodesic / h < 0.5;
  // Traced layouts have short meta-edges wherever a trace stops near a node: the traces were
  // made at this h, so it is not too large for them.
  if (!o.given_corners && 4 * tiny > meta.edges.size())
    throw Error(ErrorKind::layout, "E501",
                fmt::format("target edge length too large: {} of {} meta-edges are shorter than "
                            "half of it; use a smaller --edge-length, more --quads or fewer "
                            "--patches",
                            tiny, meta.edges.size()));
  // Pre-tune h on the LP relaxation (milliseconds per round), so that the integer program
  // usually runs once: the relaxed quad count sum W H follows the integer one closely.
  double aim = wanted;
  if (by_count) {
    const auto relaxed_quads = [&](double at_h) -> std::optional<double> {
      std::vector<double> c(meta.edges.size());
      for (uint32_t e = 0; e < c.size(); ++e) c[e] = meta.edges[e].geodesic / at_h;
      const RelaxedLengths relaxed = relaxed_length_problem(c, f->rows);
      const MilpResult r = solve_lp(relaxed.lp);
      report.length_seconds += r.seconds;
      if (!r.found()) return std::nullopt;
      const std::vector<double> x = relaxed.lengths(r.x);
      double q = 0;
      for (uint32_t p = 0; p < meta.faces.size(); ++p) {
        double side[2] = {0, 0};
        for (uint32_t i = 0; i < meta.faces[p].cycle.size(); ++i)
          if (f->sides[p][i] < 2) side[f->sides[p][i]] += x[meta.faces[p].cycle[i].edge];
        q += side[0] * side[1];
      }
      return q;
    };
    // x >= 1 puts a floor under the count (every meta-edge one quad long, h infinite). Below
    // kFloorMargin times that floor, the request is raised to it: h then stays near where the
    // long meta-edges keep their lengths. Chasing the request instead grew h until the count
    // stalled (the elephant's default 1,000 quads: h 4.5 times the area estimate for 1,430
    // quads, the median meta-edge 4.5 times its length).
    if (const auto floor = relaxed_quads(INFINITY)) aim = std::max(wanted, kFloorMargin * *floor);
    // The search stays within a factor 4 of the area estimate.
    const double h0 = h;
    double lo_h = 0, hi_h = INFINITY;
    if (aim != wanted) h = h0 * std::sqrt(wanted / aim);
    for (int round = 0; round < 12; ++round) {
      const auto q = relaxed_quads(h);
      if (!q || std::fabs(*q - aim) <= 0.005 * aim) break;
      (*q > aim ? lo_h : hi_h) = h;
      h = lo_h > 0 && hi_h < INFINITY ? std::sqrt(lo_h * hi_h) : h * std::sqrt(*q / aim);
      h = std::clamp(h, h0 / 4, h0 * 4);
    }
  }
  layout.quads_aim = aim;
  const Lengths best = tune_lengths(meta, f->sides, f->rows, {},
                                    patch_areas(mesh, labels, uint32_t(meta.faces.size())),
                                    by_count, aim, o, h, layout, report);
  report.length_solver = best.solver;
  report.length_optimal = best.optimal;
  build_charts(meta, f->sides, layout);
  check_layout(mesh, labels, meta, layout);
  return layout;
}

void thicken_patches(const MetaMesh& meta, const Layout& layout,
                     const std::vector<uint32_t>& patches, std::vector<SideMinimum>& minimums) {
  for (const uint32_t p : patches) {
    const Chart& chart = layout.charts.at(p);
    const MetaFace& face = meta.faces[p];
    // Per dimension: the edges of its first side, its length and the targets of both sides.
    std::vector<uint32_t> edges[2];
    double target[2] = {0, 0};
    for (uint32_t i = 0; i < face.cycle.size(); ++i) {
      const uint8_t side = chart.item_side[i];
      const uint32_t e = face.cycle[i].edge;
      if (side < 2) edges[side].push_back(e);
      target[side % 2] += 0.5 * layout.target[e];
    }
    const int64_t length[2] = {chart.width, chart.height};
    double shrink[2];
    for (int d = 0; d < 2; ++d) shrink[d] = target[d] / double(length[d]);
    const int most = shrink[1] > shrink[0] ? 1 : 0;
    for (int d = 0; d < 2; ++d) {
      if (d != most && shrink[d] < 1) continue;
      std::sort(edges[d].begin(), edges[d].end());
      auto same = std::find_if(minimums.begin(), minimums.end(),
                               [&](const SideMinimum& m) { return m.edges == edges[d]; });
      if (same == minimums.end()) {
        minimums.push_back({edges[d], 0});
        same = minimums.end() - 1;
      }
      same->at_least = std::max(same->at_least, length[d] + 1);
    }
  }
}

std::optional<Layout> relayout_lengths(const TriMesh& mesh, const FaceData<uint32_t>& labels,
                                       const MetaMesh& meta, const Layout& base,
                                       const std::vector<SideMinimum>& minimums,
                                       const LayoutOptions& o, LayoutReport& report) {
  std::vector<std::vector<uint8_t>> sides(base.charts.size());
  for (uint32_t p = 0; p < sides.size(); ++p) sides[p] = base.charts[p].item_side;
  const std::vector<SideRow> rows = side_equations(meta, sides);
  Layout layout;
  layout.quarter_turns = base.quarter_turns;
  const bool by_count = o.edge_length <= 0;
  const double wanted =
      std::max(o.quads > 0 ? o.quads : default_quad_count(mesh.num_faces(), o.default_share),
               base.quads_aim);
  layout.quads_aim = wanted;
  // The held sides add quads; a slightly larger h takes some back elsewhere, but not so much
  // that the rest of the mesh coarsens (with every patch four-sided on fandisk, an unbounded h
  // grew 3x in two rounds while the count stayed up).
  const double h_max = kRelayoutMaxGrowth * base.edge_length;
  const Lengths l = tune_lengths(meta, sides, rows, minimums,
                                 patch_areas(mesh, labels, uint32_t(meta.faces.size())), by_count,
                                 wanted, o, base.edge_length, layout, report, h_max);
  if (by_count && double(layout.quads()) > kRelayoutMaxQuads * wanted) return std::nullopt;
  report.length_solver = l.solver;
  report.length_optimal = l.optimal;
  build_charts(meta, sides, layout);
  check_layout(mesh, labels, meta, layout);
  return layout;
}

}  // namespace isoquad
