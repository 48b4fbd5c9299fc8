#include <gtest/gtest.h>
#include <map>

#include "core/transition.hpp"
#include "isoquad/error.hpp"
#include "layout/charts.hpp"
#include "layout/corners.hpp"
#include "layout/flow.hpp"
#include "layout/quantize.hpp"
#include "layout_checks.hpp"
#include "prep/prepare.hpp"
#include "seg/quad_split.hpp"
#include "seg/segment.hpp"
#include "shapes.hpp"

using namespace isoquad;

namespace {

struct Built {
  PreparedComponent component;
  SegmentResult seg;
};

Built segmented(const PolyMesh& m, uint32_t k) {
  PreparedMesh p = prepare(m);
  Built b{std::move(p.components.at(0)), {}};
  SegmentOptions o;
  o.vsa.patches = k;
  b.seg = segment(b.component.mesh, b.component.feature, o);
  return b;
}

}  // namespace

TEST(Transition, AlgebraIsExact) {
  const Transition a{1, {3, -2}}, b{3, {-5, 7}};
  const Lattice p{11, -4};
  EXPECT_EQ((a * b).apply(p), a.apply(b.apply(p)));
  EXPECT_EQ(a.inverse().apply(a.apply(p)), p);
  EXPECT_EQ(a * a.inverse(), Transition{});
  Transition quarter{1, {0, 0}}, full;
  for (int i = 0; i < 4; ++i) full = quarter * full;
  EXPECT_EQ(full, Transition{});
}

TEST(Feasibility, PaperFigure4ForcedZero) {
  // Patch 1 makes a and b facing; patch 2 makes b face a plus d: then d = 0 in every solution.
  const uint32_t a = 0, b = 1, d = 2, e = 3;
  const std::vector<SideRow> rows = {
      {{a, 1}, {b, -1}}, {{b, 1}, {a, -1}, {d, -1}}, {{e, 1}, {e, -1}}};
  const Feasibility f = check_feasibility(4, rows);
  EXPECT_FALSE(f.feasible);
  EXPECT_EQ(f.forced_zero, std::vector<uint32_t>{d});
  // With d on the other side of patch 2 as well, it is feasible, and the ILP finds the optimum.
  const std::vector<SideRow> fixed = {{{a, 1}, {b, -1}}, {{b, 1}, {d, 1}, {a, -1}, {e, -1}}};
  EXPECT_TRUE(check_feasibility(4, fixed).feasible);
  const std::vector<double> c = {3.2, 2.9, 1.4, 1.6};
  const Lengths l = solve_lengths(c, fixed, 10);
  EXPECT_TRUE(l.optimal);
  EXPECT_EQ(l.x[a], l.x[b]);
  EXPECT_EQ(l.x[d], l.x[e]);
  // The optimum by enumeration (a = b and d = e are the only freedom): 3 and 2, since stretching
  // 1.4 and 1.6 to 2 costs less than shrinking them to 1.
  double best = INFINITY;
  std::vector<int64_t> arg;
  for (int64_t ab = 1; ab <= 8; ++ab)
    for (int64_t de = 1; de <= 8; ++de) {
      const double cost = length_cost(double(ab), c[a]) + length_cost(double(ab), c[b]) +
                          length_cost(double(de), c[d]) + length_cost(double(de), c[e]);
      if (cost < best - 1e-12) best = cost, arg = {ab, ab, de, de};
    }
  EXPECT_EQ(l.x, arg);
  EXPECT_EQ(arg, (std::vector<int64_t>{3, 3, 2, 2}));
  EXPECT_NEAR(l.objective, best, 1e-9);
}

TEST(Feasibility, IncrementalTestsAgreeWithTheFullTest) {
  // Figure 4 (d forced to 0) as patches 0 and 1, and a patch 2 that balances e with itself.
  const uint32_t a = 0, b = 1, d = 2, e = 3;
  const std::vector<SideRow> base = {
      {{a, 1}, {b, -1}}, {{e, 1}, {e, -1}}, {{b, 1}, {a, -1}, {d, -1}}, {{e, 1}, {e, -1}}};
  FeasibilityLp lp(4, base);
  const SideRow fixed0 = {{b, 1}, {d, 1}, {a, -1}, {e, -1}}, fixed1 = {};
  for (int repeat = 0; repeat < 2; ++repeat) {  // a test leaves the base as it was
    const Feasibility t = lp.test(1, fixed0, fixed1);
    auto rows = base;
    rows[2] = fixed0, rows[3] = fixed1;
    EXPECT_EQ(t.forced_zero, check_feasibility(4, rows).forced_zero);
    EXPECT_TRUE(t.feasible);
    const Feasibility same = lp.test(1, base[2], base[3]);
    EXPECT_EQ(same.forced_zero, check_feasibility(4, base).forced_zero);
    EXPECT_EQ(same.forced_zero, std::vector<uint32_t>{d});
  }
  // Accepted, the fix is the base: putting the old rows back is a test against it.
  lp.accept(1, fixed0, fixed1);
  EXPECT_EQ(lp.test(1, base[2], base[3]).forced_zero, std::vector<uint32_t>{d});
  EXPECT_TRUE(lp.test(0, base[0], base[1]).feasible);
}

TEST(LengthProgram, RelaxationWithoutLengthColumnsHasTheSameOptimum) {
  // Figure 4's repaired rows, and a patch whose two sides share an edge (it cancels in its row).
  const std::vector<SideRow> fixed = {{{0, 1}, {1, -1}}, {{1, 1}, {2, 1}, {0, -1}, {3, -1}}};
  const std::vector<SideRow> shared = {{{0, 1}, {1, 1}, {1, -1}, {2, -1}}, {{3, 1}, {0, -1}}};
  for (const auto& rows : {fixed, shared})
    for (const std::vector<double>& c : std::vector<std::vector<double>>{
             {3.2, 2.9, 1.4, 1.6}, {0.3, 7.5, 12.25, 0.8}, {20, 1, 1, 5.5}}) {
      const MilpResult full = solve_lp(length_problem(c, rows, false, false));
      const RelaxedLengths relaxed = relaxed_length_problem(c, rows);
      const MilpResult r = solve_lp(relaxed.lp);
      ASSERT_TRUE(full.found() && r.found());
      EXPECT_EQ(relaxed.lp.rows.size(), rows.size());
      EXPECT_NEAR(r.objective, full.objective, 1e-9);
      const std::vector<double> x = relaxed.lengths(r.x);
      double cost = 0;
      for (uint32_t e = 0; e < c.size(); ++e) {
        EXPECT_GE(x[e], 1 - 1e-9);
        cost += length_cost(x[e], c[e]);
      }
      EXPECT_NEAR(cost, r.objective, 1e-9);  // the segments fill in order: the cost is convex
      for (const SideRow& row : rows) {
        double sum = 0;
        for (const auto& [e, sign] : row) sum += sign * x[e];
        EXPECT_NEAR(sum, 0, 1e-9);
      }
    }
}

// The integer program prices every integer length as length_cost does (up to one constant per
// edge), and its relaxation is the chord between the two integers around c instead of the kink
// at c: with x_e free, the relaxed optimum of a single edge is an integer.
TEST(LengthProgram, IntegerFormPricesEveryIntegerLikeTheCost) {
  for (const double c : {0.4, 1.0, 1.7, 2.5, 3.0, 7.3, 12.9, 40.2}) {
    auto cost_at = [&](double x) {
      MilpProblem p = length_problem({c}, {}, false, true);
      p.col_lo[0] = p.col_hi[0] = x;
      p.integer.assign(p.integer.size(), 0);
      const MilpResult r = solve_lp(p);
      EXPECT_TRUE(r.found());
      return r.objective;
    };
    const double base = std::max(1.0, std::floor(c));
    const double at_base = cost_at(base);
    for (int x = 1; x < int(3 * c) + 3; ++x)
      EXPECT_NEAR(cost_at(x) - at_base, length_cost(x, c) - length_cost(base, c), 1e-9)
          << "c " << c << " x " << x;
    MilpProblem free = length_problem({c}, {}, false, true);
    free.integer.assign(free.integer.size(), 0);
    const MilpResult r = solve_lp(free);
    ASSERT_TRUE(r.found());
    EXPECT_NEAR(r.x[0], std::round(r.x[0]), 1e-9) << "c " << c;
  }
}

// A lens: one patch with long sides 0 and 2 (20) and short ends 1 and 3 (1), but a mean width
// of 10 by its area. Alone the ends stay 1; with the width's soft target the optimum of
// 2 (k - 1) + d(k, 10) is k = 2 (cost 2 + 4 = 6, against 9 at 1 and 4 + 2.33 at 3).
TEST(LengthProgram, WidthTargetWidensALens) {
  const std::vector<SideRow> rows = {{{0, 1}, {2, -1}}, {{1, 1}, {3, -1}}};
  const std::vector<double> c = {20, 1, 20, 1};
  const Lengths plain = solve_lengths(c, rows, 10);
  EXPECT_EQ(plain.x, (std::vector<int64_t>{20, 1, 20, 1}));
  EXPECT_NEAR(plain.objective, 0.0, 1e-9);
  const Lengths wide = solve_lengths(c, rows, 10, {}, {SideTarget{{1}, 10}});
  EXPECT_TRUE(wide.optimal);
  EXPECT_EQ(wide.x, (std::vector<int64_t>{20, 2, 20, 2}));
  EXPECT_NEAR(wide.objective, 2 * length_cost(2, 1) + length_cost(2, 10), 1e-9);
  EXPECT_NEAR(wide.objective, 6.0, 1e-9);
  // Weighed 10 times (a patch 10 rows long): 2 (k - 1) + 10 d(k, 10) is least at k = 8
  // (14 + 2.5; at 7, 12 + 4.58; at 9, 16 + 1.25), d linear between its breakpoints 10, 8, 6.
  const Lengths wider = solve_lengths(c, rows, 10, {}, {SideTarget{{1}, 10, 10}});
  EXPECT_EQ(wider.x, (std::vector<int64_t>{20, 8, 20, 8}));
  EXPECT_NEAR(wider.objective, 16.5, 1e-9);
}

TEST(LengthCost, SymmetricInTheRatioAndConvex) {
  for (const double c : {1.0, 2.5, 7.0, 15.3, 40.0}) {
    EXPECT_EQ(length_cost(c, c), 0.0);
    EXPECT_NEAR(length_cost(2 * c, c), c >= 1 ? 1.0 : 2 * c - c, 1e-12);  // stretched by 2
    // Shrinking by an integer factor lands on a breakpoint when c / k is an integer.
    if (c == 40.0) {
      EXPECT_NEAR(length_cost(20, c), 1.0, 1e-12);
      EXPECT_NEAR(length_cost(10, c), 3.0, 1e-12);
      EXPECT_NEAR(length_cost(5, c), 7.0, 1e-12);
    }
    // Convex over the integers: second differences are never negative.
    for (int x = 2; x < int(3 * c) + 3; ++x)
      EXPECT_GE(length_cost(x + 1, c) - 2 * length_cost(x, c) + length_cost(x - 1, c), -1e-12)
          << "c " << c << " x " << x;
  }
  // Collapsing a long edge is no longer cheap: 15.3 -> 1 costs about as much as 1 -> 15.3.
  EXPECT_GT(length_cost(1, 15.3), 10.0);
}

TEST(Layout, CubeIsSixSquareGrids) {
  const int n = 6;
  Built b = segmented(test::subdivided_cube(n), 6);
  ASSERT_EQ(b.seg.num_patches, 6u);
  LayoutOptions o;
  o.edge_length =
      b.component.mesh.bounding_box().diagonal() / std::sqrt(3.0) / 5;  // 5 quads per cube edge
  LayoutReport report;
  const Layout l =
      solve_layout(b.seg.refined.mesh, b.seg.labels, b.seg.feature, b.seg.meta, o, report);
  test::expect_valid_layout(b.seg.meta, l);
  EXPECT_TRUE(report.repairs.empty());
  EXPECT_EQ(l.quads(), 6 * 25);
  for (const Chart& c : l.charts) {
    EXPECT_EQ(c.width, 5);
    EXPECT_EQ(c.height, 5);
  }
  for (int a : l.quarter_turns) EXPECT_EQ(a, 3);  // every cube corner: three 90-degree corners
  EXPECT_NEAR(l.objective, 0.0, 1e-9);
}

// A request below what the patches allow (every meta-edge at least one quad long): an icosphere
// in 24 patches asked for 20 quads. The layout aims at kFloorMargin times the floor instead of
// growing h until every meta-edge is one quad long, so the meta-edges keep their lengths.
TEST(Layout, RequestBelowTheFloorIsRaisedNotChased) {
  Built b = segmented(test::icosphere(3), 24);
  ASSERT_GE(b.seg.num_patches, 20u);
  LayoutOptions o;
  o.quads = 20;
  LayoutReport report;
  const Layout l =
      solve_layout(b.seg.refined.mesh, b.seg.labels, b.seg.feature, b.seg.meta, o, report);
  test::expect_valid_layout(b.seg.meta, l);
  // At least one quad per patch, so the floor is above the request.
  EXPECT_GT(l.quads_aim, 4 * o.quads);
  EXPECT_NEAR(double(l.quads()), l.quads_aim, 0.25 * l.quads_aim);
  const std::vector<double> ratio = l.length_ratios();
  ASSERT_FALSE(ratio.empty());
  EXPECT_GT(ratio[ratio.size() / 2], 0.67);
  EXPECT_LT(ratio[ratio.size() / 2], 1.5);
  // Above the floor the request stands.
  o.quads = 8 * l.quads_aim;
  MetaMesh meta = b.seg.meta;
  const Layout fine =
      solve_layout(b.seg.refined.mesh, b.seg.labels, b.seg.feature, meta, o, report);
  EXPECT_EQ(fine.quads_aim, o.quads);
  EXPECT_NEAR(double(fine.quads()), o.quads, 0.1 * o.quads);
}

TEST(Layout, PlateGetsItsSize) {
  Built b = segmented(test::grid_plate(30, 20), 1);
  ASSERT_EQ(b.seg.num_patches, 1u);
  const Box3 box = b.component.mesh.bounding_box();
  LayoutOptions o;
  o.edge_length = (box.hi.x - box.lo.x) / 12;  // the plate is a unit square: 12 x 12 quads
  LayoutReport report;
  const Layout l =
      solve_layout(b.seg.refined.mesh, b.seg.labels, b.seg.feature, b.seg.meta, o, report);
  test::expect_valid_layout(b.seg.meta, l);
  const Chart& c = l.charts[0];
  EXPECT_EQ(c.width, 12);
  EXPECT_EQ(c.height, 12);
  EXPECT_NEAR(l.objective, 0.0, 1e-9);
  for (int a : l.quarter_turns) EXPECT_EQ(a, 1);  // the plate's corners
}

// Held patch sides: the plate's width held to 15 gives 15 x 12 (its facing side follows); then
// thickening the plate grows its least stretched dimension (the height, 12 for 12) by one and
// keeps the width's minimum.
TEST(Layout, HeldSidesAreMetExactlyAndThickeningGrowsTheSqueezedSide) {
  Built b = segmented(test::grid_plate(30, 20), 1);
  ASSERT_EQ(b.seg.num_patches, 1u);
  const Box3 box = b.component.mesh.bounding_box();
  LayoutOptions o;
  o.edge_length = (box.hi.x - box.lo.x) / 12;
  LayoutReport report;
  const Layout l =
      solve_layout(b.seg.refined.mesh, b.seg.labels, b.seg.feature, b.seg.meta, o, report);
  ASSERT_EQ(l.charts[0].width, 12);
  ASSERT_EQ(l.charts[0].height, 12);
  std::vector<SideMinimum> held(1);
  const MetaFace& face = b.seg.meta.faces[0];
  for (uint32_t i = 0; i < face.cycle.size(); ++i)
    if (l.charts[0].item_side[i] == 0) held[0].edges.push_back(face.cycle[i].edge);
  std::sort(held[0].edges.begin(), held[0].edges.end());
  held[0].at_least = 15;
  const std::optional<Layout> wide =
      relayout_lengths(b.seg.refined.mesh, b.seg.labels, b.seg.meta, l, held, o, report);
  ASSERT_TRUE(wide.has_value());
  test::expect_valid_layout(b.seg.meta, *wide);
  EXPECT_EQ(wide->charts[0].width, 15);
  EXPECT_EQ(wide->charts[0].height, 12);
  EXPECT_EQ(wide->edge_length, l.edge_length);
  EXPECT_NEAR(wide->objective, 2 * 3.0 / 12, 1e-6);  // sides 0 and 2 stretched 12 -> 15

  thicken_patches(b.seg.meta, *wide, {0}, held);
  ASSERT_EQ(held.size(), 2u);
  EXPECT_EQ(held[0].at_least, 15);
  EXPECT_EQ(held[1].at_least, 13);
  const std::optional<Layout> thick =
      relayout_lengths(b.seg.refined.mesh, b.seg.labels, b.seg.meta, *wide, held, o, report);
  ASSERT_TRUE(thick.has_value());
  test::expect_valid_layout(b.seg.meta, *thick);
  EXPECT_EQ(thick->charts[0].width, 15);
  EXPECT_EQ(thick->charts[0].height, 13);
  // Thickening a patch squeezed in both directions grows both.
  Layout squeezed = *thick;
  for (double& c : squeezed.target) c *= 2;
  std::vector<SideMinimum> both;
  thicken_patches(b.seg.meta, squeezed, {0}, both);
  ASSERT_EQ(both.size(), 2u);
  EXPECT_EQ(both[0].at_least + both[1].at_least, 15 + 1 + 13 + 1);
}

TEST(Layout, TorusQuadrantsAreRegular) {
  const int nu = 48, nv = 24;
  PreparedMesh p = prepare(test::torus(nu, nv));
  const PreparedComponent& c = p.components[0];
  FaceData<uint32_t> labels(c.mesh.num_faces());
  for (uint32_t f = 0; f < c.mesh.num_faces(); ++f) {
    const int i = int(c.input_face[f] / 2) / nv, j = int(c.input_face[f] / 2) % nv;
    labels[f] = (i < nu / 2 ? 0 : 1) + (j < nv / 2 ? 0 : 2);
  }
  MetaMesh mm = build_meta_mesh(c.mesh, labels, 4, c.feature);
  measure_geodesic_lengths(c.mesh, labels, mm);
  LayoutOptions o;
  o.quads = 400;
  LayoutReport report;
  const Layout l = solve_layout(c.mesh, labels, c.feature, mm, o, report);
  test::expect_valid_layout(mm, l);
  for (int a : l.quarter_turns) EXPECT_EQ(a, 4);  // no singularity on a torus
  // Two meta-edges join each pair of neighbouring patches, with different jumps.
  std::map<std::pair<uint32_t, uint32_t>, std::vector<Transition>> between;
  for (uint32_t e = 0; e < mm.edges.size(); ++e) {
    const auto key = mm.edges[e].left < mm.edges[e].right
                         ? std::pair(mm.edges[e].left, mm.edges[e].right)
                         : std::pair(mm.edges[e].right, mm.edges[e].left);
    between[key].push_back(mm.edges[e].left < mm.edges[e].right ? l.transition[e]
                                                                : l.transition[e].inverse());
  }
  for (const auto& [pair, ts] : between) {
    ASSERT_EQ(ts.size(), 2u);
    EXPECT_EQ(ts[0].k, ts[1].k);
    EXPECT_NE(ts[0].t, ts[1].t);
  }
  EXPECT_NEAR(double(l.quads()), 400, 40);
}

TEST(Corners, LocalModeIsThePapersChoice) {
  Built b = segmented(test::icosphere(3), 12);
  const auto cands = corner_candidates(b.seg.refined.mesh, b.seg.labels, b.seg.meta, 0.5, 8);
  LayoutOptions o;
  o.corners = CornerMode::local;
  const CornerChoice local = choose_corners(b.seg.refined.mesh, b.seg.meta, cands, o);
  for (uint32_t p = 0; p < cands.size(); ++p)
    EXPECT_EQ(local.chosen[p], 0u);  // each patch's best candidate
  o.corners = CornerMode::global;
  const CornerChoice global = choose_corners(b.seg.refined.mesh, b.seg.meta, cands, o);
  // The global choice pays at most the candidates' cost for fewer singular quarter turns.
  auto singular = [&](const CornerChoice& c) {
    int s = 0;
    for (uint32_t v = 0; v < c.quarter_turns.size(); ++v) s += std::abs(c.quarter_turns[v] - 4);
    return s;
  };
  EXPECT_LE(singular(global), singular(local));
  EXPECT_GE(global.cost, local.cost - 1e-12);
  for (int a : global.quarter_turns) EXPECT_GE(a, 3);
}

// A patch corner above 150 degrees costs `flat_corner` more on the angle term (times beta), and
// the corner ILP then takes fewer of them. On a plate cut into patches, the T-junctions on the
// straight outer boundary are flat corners for the patches on either side.
namespace {
// Per patch, per candidate (by its items), how many times `step` its priced cost exceeds its
// plain one; each must be a whole number (keep = 0 lists every candidate of both).
std::vector<std::map<std::array<uint32_t, 4>, int>> price_steps(
    const std::vector<std::vector<CornerCandidate>>& plain,
    const std::vector<std::vector<CornerCandidate>>& priced, double step) {
  EXPECT_EQ(plain.size(), priced.size());
  std::vector<std::map<std::array<uint32_t, 4>, int>> out(plain.size());
  for (uint32_t p = 0; p < plain.size() && p < priced.size(); ++p) {
    EXPECT_EQ(plain[p].size(), priced[p].size());
    std::map<std::array<uint32_t, 4>, double> cost;
    for (const CornerCandidate& c : plain[p]) cost[c.items] = c.cost;
    for (const CornerCandidate& c : priced[p]) {
      EXPECT_TRUE(cost.count(c.items));
      const double steps = (c.cost - cost[c.items]) / step;
      EXPECT_NEAR(steps, std::round(steps), 1e-9);
      EXPECT_GE(steps, -1e-9);
      out[p][c.items] = int(std::lround(steps));
    }
  }
  return out;
}
}  // namespace

TEST(Corners, FlatCornerPenaltyPricesCornersAboveOneHundredFiftyDegrees) {
  Built b = segmented(test::grid_plate(24, 24), 10);
  const TriMesh& mesh = b.seg.refined.mesh;
  const double beta = 0.5, price = 2;
  const auto plain = corner_candidates(mesh, b.seg.labels, b.seg.meta, beta, 0, 0, 0);
  const auto priced = corner_candidates(mesh, b.seg.labels, b.seg.meta, beta, 0, 0, price);
  ASSERT_EQ(plain.size(), priced.size());
  // Flat corners of each candidate, from the cost difference (keep = 0: every candidate, in
  // cost order, so they are matched by their items).
  const auto flat = price_steps(plain, priced, beta * price);
  uint32_t priced_candidates = 0;
  for (const auto& patch : flat)
    for (const auto& [items, steps] : patch) {
      EXPECT_LE(steps, 4);
      priced_candidates += steps > 0;
    }
  EXPECT_GT(priced_candidates, 0u);
  auto flat_corners = [&](const auto& cands, const LayoutOptions& o) {
    const CornerChoice ch = choose_corners(mesh, b.seg.meta, cands, o);
    int n = 0;
    for (uint32_t p = 0; p < cands.size(); ++p) n += flat[p].at(cands[p][ch.chosen[p]].items);
    return n;
  };
  const int with = flat_corners(priced, LayoutOptions{}),
            without = flat_corners(plain, LayoutOptions{});
  EXPECT_LT(with, without);  // 1 against 2
}

// The crease price applies exactly where the patch boundary runs along a crease on both sides
// of a corner at a flat place: on a cube in 14 patches, corners in the middle of a cube edge.
// Every priced corner has two feature meta-edges; cube corners (90 degrees) and corners on
// smooth seams are never priced.
TEST(Corners, FlatCreaseCornerPenaltyPricesOnlyCornersOnStraightCreases) {
  Built b = segmented(test::subdivided_cube(8), 14);
  const TriMesh& mesh = b.seg.refined.mesh;
  const MetaMesh& meta = b.seg.meta;
  const double beta = 0.5, price = 2;
  const auto plain = corner_candidates(mesh, b.seg.labels, meta, beta, 0, 0, 0, 0);
  const auto priced = corner_candidates(mesh, b.seg.labels, meta, beta, 0, 0, 0, price);
  ASSERT_EQ(plain.size(), priced.size());
  const Box3 box = mesh.bounding_box();
  auto cube_corner = [&](uint32_t v) {
    const Vec3 x = mesh.position(v);
    const double lo[3] = {box.lo.x, box.lo.y, box.lo.z}, hi[3] = {box.hi.x, box.hi.y, box.hi.z},
                 at[3] = {x.x, x.y, x.z};
    for (int k = 0; k < 3; ++k)
      if (std::fabs(at[k] - lo[k]) > 1e-9 && std::fabs(at[k] - hi[k]) > 1e-9) return false;
    return true;
  };
  const auto steps = price_steps(plain, priced, beta * price);
  uint32_t priced_candidates = 0;
  for (uint32_t p = 0; p < steps.size(); ++p) {
    const MetaFace& f = meta.faces[p];
    const uint32_t m = uint32_t(f.cycle.size());
    for (const auto& [items, n] : steps[p]) {
      // At most the corners whose both meta-edges are creases.
      int on_creases = 0;
      for (const uint32_t i : items)
        on_creases += meta.edges[f.cycle[i].edge].feature &&
                      meta.edges[f.cycle[(i + m - 1) % m].edge].feature &&
                      !cube_corner(meta.vertices[f.start_vertex(i, meta.edges)].vertex);
      EXPECT_LE(n, on_creases);
      priced_candidates += n > 0;
    }
  }
  EXPECT_GT(priced_candidates, 0u);
}

namespace {
// Facing-side equations of a real segmentation with its chosen corners.
std::vector<SideRow> rows_of(const SegmentResult& seg, const TriMesh& mesh) {
  const auto cands = corner_candidates(mesh, seg.labels, seg.meta, 0.5, 8);
  const CornerChoice ch = choose_corners(mesh, seg.meta, cands, LayoutOptions{});
  return side_equations(seg.meta, item_sides(seg.meta, ch.corners));
}
}  // namespace

TEST(Flow, ReachesCbcOptimumOnNetworkLayouts) {
  // The cube (8 valence-3 corners) is balanced; so is a plate; the 2x2 torus too.
  for (const PolyMesh& m : {test::subdivided_cube(6), test::grid_plate(20, 12)}) {
    Built b = segmented(m, m.num_faces() > 300 ? 6 : 1);
    const auto rows = rows_of(b.seg, b.seg.refined.mesh);
    ASSERT_TRUE(network_signs(uint32_t(b.seg.meta.edges.size()), rows).has_value());
    for (double scale : {2.5, 7.3, 19.9}) {  // several sizes, fractional targets
      std::vector<double> c;
      for (const MetaEdge& e : b.seg.meta.edges)
        c.push_back(e.geodesic * scale / b.seg.meta.edges[0].geodesic);
      const Lengths cbc = solve_lengths(c, rows, 10);
      const auto flow = solve_lengths_flow(c, rows);
      ASSERT_TRUE(flow.has_value());
      EXPECT_NEAR(flow->objective, cbc.objective, 1e-6) << "scale " << scale;
      for (const SideRow& r : rows) {
        int64_t sum = 0;
        for (const auto& [e, s] : r) sum += s * flow->x[e];
        EXPECT_EQ(sum, 0);
      }
    }
  }
}

TEST(Flow, RejectsRotationalLayouts) {
  // An odd cycle of sign constraints: rows {a - b}, {b - c}, {c + a}... a + c = 0 with a = b = c.
  const std::vector<SideRow> rows = {{{0, 1}, {1, -1}}, {{1, 1}, {2, -1}}, {{2, 1}, {0, 1}}};
  EXPECT_FALSE(network_signs(3, rows).has_value());
  EXPECT_FALSE(solve_lengths_flow({1, 1, 1}, rows).has_value());
}

// The paper's last-resort repair (§5): after the split every patch is a disk with exactly four
// meta-vertices (a Catmull-Clark step of the meta-mesh: one patch per side of each old one), the
// meta-mesh keeps the surface's Euler characteristic, and every layout is feasible, here on a
// sphere, a plate with a hole (mesh boundary) and a torus with 8 patches (genus 1; the greedy
// paths before the convex-map rays blocked each other there).
TEST(QuadSplit, EveryPatchFourSidedAndTheLayoutFeasible) {
  for (const auto& [mesh, k] :
       {std::pair{test::icosphere(3), 8u}, std::pair{test::plate_with_hole(16), 4u},
        std::pair{test::torus(40, 16), 8u}}) {
    Built b = segmented(mesh, k);
    SCOPED_TRACE(mesh.num_faces());
    uint32_t sides = 0;
    for (const MetaFace& f : b.seg.meta.faces) sides += uint32_t(f.cycle.size());
    QuadSplitReport report;
    try {
      split_patches_into_quads(b.seg, report);
    } catch (const Error& e) {
      ADD_FAILURE() << e.what();
      continue;
    }
    EXPECT_GT(report.patches_after, report.patches_before);
    EXPECT_LE(report.patches_after, sides);  // one per side, fewer where inserted ones merged
    EXPECT_EQ(b.seg.num_patches, report.patches_after);
    for (const MetaFace& f : b.seg.meta.faces) EXPECT_EQ(f.cycle.size(), 4u);
    EXPECT_EQ(b.seg.meta.euler(), b.seg.refined.mesh.euler_characteristic());
    check_meta_mesh(b.seg.refined.mesh, b.seg.labels, b.seg.meta);
    LayoutOptions o;
    o.quads = 40 * report.patches_after;
    LayoutReport lr;
    const Layout l =
        solve_layout(b.seg.refined.mesh, b.seg.labels, b.seg.feature, b.seg.meta, o, lr);
    test::expect_valid_layout(b.seg.meta, l);
    EXPECT_TRUE(lr.length_optimal);
  }
}
