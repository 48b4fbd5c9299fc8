// The repairs after extraction: tip splits, snapping corners onto tips, untangling folds,
// diagonal collapses.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "extract/collapse.hpp"
#include "extract/snap.hpp"
#include "extract/surface_walk.hpp"
#include "extract/untangle.hpp"
#include "metrics/quality.hpp"
#include "remesh_shape.hpp"
#include "shapes.hpp"

using namespace isoquad;
using namespace isoquad::test;

// A sphere with small bumps, each narrower than a quad: the quads cut most of them off. Tip
// snapping brings corners onto them: the farthest surface vertex comes closer, so does the
// two-sided distance as `isoquad quality` measures it, no quad folds or gets worse than a
// scaled Jacobian of 0.2 (against the surface or its own normal) that was better, the connectivity
// is the same, every corner stays on the surface, and the result does not depend on the run.
TEST(TipSplit, BumpsTheQuadsCutOffBecomeCorners) {
  // A sphere with bumps a third of an edge length high: the quads of one run cut them off; with
  // the farthest made meta-vertices the run again passes through them and is kept.
  PolyMesh bumpy = test::icosphere(4);
  for (std::size_t v = 0; v < bumpy.positions.size(); v += 97)
    bumpy.positions[v] = 1.12 * bumpy.positions[v];
  const Remeshed once = remesh_shape(bumpy, 0, 300, WeightKind::smvc, true, false, false);
  const Remeshed r = remesh_shape(bumpy, 0, 300, WeightKind::smvc, true, false, true);
  EXPECT_TRUE(once.run.tips.empty());
  ASSERT_FALSE(r.run.tips.empty());
  ASSERT_GE(r.run.tip_round_kept, 1u);
  EXPECT_EQ(r.run.seg.tip_split.split, r.run.tips.size());
  // The first round's tips (first in the list) are corners the quads pass through. A later
  // round's tip next to an earlier one may cut a wedge the disk repair merges again (the run
  // is kept for its distance); most stay corners.
  const uint32_t first_round = r.run.tip_rounds.at(1).tips;
  uint32_t corners = 0;
  for (uint32_t i = 0; i < r.run.tips.size(); ++i) {
    const uint32_t t = r.run.tips[i];
    if (r.run.seg.meta.vertex_meta_vertex[t] == kInvalid) {
      EXPECT_GE(i, first_round);
      continue;
    }
    ++corners;
    // The tip, farther than 0.3 h from the first run's quads, is at or next to a corner of
    // these (a singularity the untangler may move a little).
    const Vec3& p = r.prep.components[0].mesh.position(t);
    double nearest = INFINITY;
    for (const Vec3& x : r.run.quads.positions) nearest = std::min(nearest, norm(x - p));
    EXPECT_LT(nearest, 0.2 * r.run.layout.edge_length);
  }
  EXPECT_GE(corners, 0.9 * double(r.run.tips.size()));
  const SizeRound& first = r.run.tip_rounds.at(0).result;
  const SizeRound& kept = r.run.tip_rounds.at(r.run.tip_round_kept).result;
  EXPECT_LT(kept.distance, first.distance);
  EXPECT_LE(kept.folded, first.folded);
  const QualityReport q0 = measure_quality(once.quads, &bumpy);
  const QualityReport q1 = measure_quality(r.quads, &bumpy);
  EXPECT_TRUE(q1.pure_quad);
  EXPECT_TRUE(q1.same_topology);
  EXPECT_LE(q1.sj_surface_nonpositive, q0.sj_surface_nonpositive);
  EXPECT_LT(q1.hausdorff, q0.hausdorff);
}

TEST(Snap, MovesCornersOntoTipsTheQuadsCutOff) {
  PolyMesh bumpy = test::icosphere(4);
  for (std::size_t v = 0; v < bumpy.positions.size(); v += 97)
    bumpy.positions[v] = 1.12 * bumpy.positions[v];
  const Remeshed r = remesh_shape(bumpy, 0, 300, WeightKind::smvc, true, false);
  ASSERT_EQ(r.run.snap_report.tips, 0u);  // not run
  const TriMesh& base = r.prep.components[0].mesh;
  QuadMesh q = r.run.quads, again = r.run.quads;
  SnapOptions so;
  so.edge_length = r.run.layout.edge_length;
  SnapReport report, report2;
  snap_tips(q, base, r.run.seg.refined.mesh, r.run.seg.meta, so, report);
  snap_tips(again, base, r.run.seg.refined.mesh, r.run.seg.meta, so, report2);
  EXPECT_GE(report.tips, 10u);
  EXPECT_GT(report.snapped, 0u);
  EXPECT_LT(2 * report.left, report.tips);  // 61 tips, 24 left when this was written
  EXPECT_LT(report.farthest_after, report.farthest_before);

  const PolyMesh reference = component_as_poly(base);
  const QualityReport before = measure_quality(as_poly(r.run.quads), &reference);
  const QualityReport after = measure_quality(as_poly(q), &reference);
  EXPECT_LT(after.hausdorff, before.hausdorff);
  EXPECT_LT(after.mean_distance, 0.95 * before.mean_distance);
  EXPECT_LE(after.sj_surface_nonpositive, before.sj_surface_nonpositive);
  EXPECT_TRUE(after.same_topology || !before.same_topology);
  const std::vector<double> sj0 = surface_scaled_jacobians(as_poly(r.run.quads), reference);
  const std::vector<double> sj1 = surface_scaled_jacobians(as_poly(q), reference);
  for (std::size_t f = 0; f < sj0.size(); ++f) {
    EXPECT_GE(sj1[f], std::min(sj0[f], 0.2) - 1e-9);
    auto own = [&](const QuadMesh& m) {
      const auto& c = m.quads[f];
      return quad_scaled_jacobian(
          {m.positions[c[0]], m.positions[c[1]], m.positions[c[2]], m.positions[c[3]]});
    };
    EXPECT_GE(own(q), std::min(own(r.run.quads), 0.2) - 1e-9);
  }
  EXPECT_EQ(q.quads, r.run.quads.quads);
  uint32_t moved = 0;
  for (std::size_t v = 0; v < q.positions.size(); ++v) {
    EXPECT_LT(norm(position_of(base, q.surface[v]) - q.positions[v]), 1e-12);
    EXPECT_EQ(q.positions[v], again.positions[v]);
    moved += !(q.positions[v] == r.run.quads.positions[v]);
  }
  EXPECT_GT(moved, 0u);
  EXPECT_LE(moved, report.snapped);
}

// Folds put in by hand (a free vertex pushed past its neighbour along the surface, in several
// places) are found and undone: quads fold against the surface before and none does after;
// every vertex stays on the surface and within a few quads of where it was, and the result
// does not depend on the run.
TEST(Untangle, UndoesFoldsAgainstTheSurface) {
  const Remeshed r = remesh_shape(test::torus(48, 20), 0, 600, WeightKind::smvc, false);
  const TriMesh& base = r.prep.components[0].mesh;
  QuadMesh q = r.run.quads;
  auto free_vertex = [&](uint32_t v) {
    return q.vertex_meta_vertex[v] == kInvalid && q.vertex_meta_edge[v] == kInvalid;
  };
  uint32_t swaps = 0;
  std::vector<char> touched(q.positions.size(), 0);
  for (const auto& quad : q.quads) {
    const uint32_t a = quad[0], b = quad[1];
    if (swaps == 5 || !free_vertex(a) || !free_vertex(b) || touched[a] || touched[b]) continue;
    for (const auto& other : q.quads)
      for (const uint32_t v : other)
        if (v == a || v == b)
          for (const uint32_t w : other) touched[w] = 1;
    q.surface[a] = project_locally(base, q.surface[b].face,
                                   q.positions[a] + 1.3 * (q.positions[b] - q.positions[a]));
    q.positions[a] = position_of(base, q.surface[a]);
    ++swaps;
  }
  ASSERT_EQ(swaps, 5u);
  const PolyMesh reference = component_as_poly(base);
  auto surface_folds = [&](const QuadMesh& m) {
    PolyMesh p;
    p.positions = m.positions;
    for (const auto& f : m.quads) p.add_face({f[0], f[1], f[2], f[3]});
    return measure_quality(p, &reference).sj_surface_nonpositive;
  };
  const uint32_t before = surface_folds(q);
  EXPECT_GE(before, 5u);
  const QuadMesh start = q;

  QuadMesh again = q;
  UntangleReport report, report2;
  UntangleOptions uo;
  uo.edge_length = r.run.layout.edge_length;
  untangle_quads(q, base, r.run.seg.refined.mesh, r.run.seg.meta, uo, report);
  untangle_quads(again, base, r.run.seg.refined.mesh, r.run.seg.meta, uo, report2);
  EXPECT_EQ(report.folded_before, before);
  EXPECT_EQ(report.folded_after, 0u);
  EXPECT_EQ(surface_folds(q), 0u);
  EXPECT_GT(report.min_after, 0);
  EXPECT_GT(report.moves, 0u);
  for (std::size_t v = 0; v < q.positions.size(); ++v) {
    EXPECT_LT(norm(position_of(base, q.surface[v]) - q.positions[v]), 1e-12);
    EXPECT_EQ(q.positions[v], again.positions[v]);
    EXPECT_LE(norm(q.positions[v] - start.positions[v]), uo.reach * uo.edge_length);
  }
}

namespace {

// A roof z = -1.5 |x| over [-2, 2]^2 (ridge along the y axis), triangulated in steps of 0.25, and
// a 3 x 3 grid of quads on it, its outer vertices at (-1.5 + i, -1.5 + j) and its inner four
// moved so that quad 4 (the middle one) bends across the ridge: every corner of every quad has
// a scaled Jacobian above 0.1 against the surface normal, but quad 4 has a reflex corner
// against its own (Newell) normal.
struct RoofCase {
  TriMesh base;
  QuadMesh quads;
};
RoofCase roof_case() {
  auto lift = [](double x, double y) { return Vec3{x, y, -1.5 * std::fabs(x)}; };
  std::vector<Vec3> p;
  std::vector<Tri> t;
  constexpr uint32_t n = 16;
  for (uint32_t j = 0; j <= n; ++j)
    for (uint32_t i = 0; i <= n; ++i) p.push_back(lift(-2 + 0.25 * i, -2 + 0.25 * j));
  for (uint32_t j = 0; j < n; ++j)
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t v = j * (n + 1) + i;
      t.push_back({v, v + 1, v + n + 2});
      t.push_back({v, v + n + 2, v + n + 1});
    }
  RoofCase c{TriMesh(std::move(p), std::move(t)), {}};
  const std::map<std::pair<int, int>, std::pair<double, double>> inner = {{{1, 1}, {0.06, -0.6}},
                                                                          {{2, 1}, {0.52, -0.17}},
                                                                          {{1, 2}, {-0.19, 0.53}},
                                                                          {{2, 2}, {-0.08, 0.46}}};
  QuadMesh& q = c.quads;
  for (int j = 0; j <= 3; ++j)
    for (int i = 0; i <= 3; ++i) {
      const auto it = inner.find({i, j});
      const auto [x, y] = it != inner.end() ? it->second : std::pair(-1.5 + i, -1.5 + j);
      const uint32_t cell = uint32_t((y + 2) / 0.25) * n + uint32_t((x + 2) / 0.25);
      q.surface.push_back(project_locally(c.base, 2 * cell, lift(x, y)));
      q.positions.push_back(position_of(c.base, q.surface.back()));
    }
  q.vertex_meta_vertex.assign(16, kInvalid);
  q.vertex_meta_edge.assign(16, kInvalid);
  q.placed.assign(16, QuadMesh::Placed::direct);
  for (uint32_t j = 0; j < 3; ++j)
    for (uint32_t i = 0; i < 3; ++i) {
      const uint32_t v = j * 4 + i;
      q.quads.push_back({v, v + 1, v + 5, v + 4});
      q.quad_patch.push_back(0);
    }
  return c;
}

}  // namespace

// The repair's measure is the output's validity: a quad bent across a ridge that every corner's
// surface normal accepts, but with a reflex corner in its own plane, is made convex, by moves
// along the surface.
TEST(Untangle, MakesQuadsConvexThatTheSurfaceNormalAccepts) {
  RoofCase c = roof_case();
  const PolyMesh reference = component_as_poly(c.base);
  auto own = [](const QuadMesh& m) {
    std::vector<double> sj;
    for (const auto& f : m.quads)
      sj.push_back(quad_scaled_jacobian(
          {m.positions[f[0]], m.positions[f[1]], m.positions[f[2]], m.positions[f[3]]}));
    return sj;
  };
  for (std::size_t v = 0; v < c.quads.positions.size(); ++v) {
    const Vec3& x = c.quads.positions[v];
    ASSERT_NEAR(x.z, -1.5 * std::fabs(x.x), 1e-12);  // on the surface
  }
  const std::vector<double> surface_before = surface_scaled_jacobians(as_poly(c.quads), reference);
  const std::vector<double> own_before = own(c.quads);
  // The case: the surface normal sees no quad below the untangler's target; the own normal sees
  // one, the middle quad, not valid.
  for (const double s : surface_before) EXPECT_GT(s, 0.1);
  for (std::size_t f = 0; f < own_before.size(); ++f)
    EXPECT_EQ(own_before[f] <= kMinValidScaledJacobian, f == 4) << f << ": " << own_before[f];
  EXPECT_LT(own_before[4], -0.2);

  const QuadMesh start = c.quads;
  const MetaMesh meta;
  UntangleOptions uo;
  uo.edge_length = 1;
  UntangleReport report, report2;
  QuadMesh again = c.quads;
  untangle_quads(c.quads, c.base, c.base, meta, uo, report);
  untangle_quads(again, c.base, c.base, meta, uo, report2);
  EXPECT_EQ(report.folded_before, 1u);  // the reflex quad counts as folded
  EXPECT_EQ(report.folded_after, 0u);
  EXPECT_EQ(report.nonpositive, 0u);
  EXPECT_EQ(report.degenerate, 0u);
  EXPECT_GT(report.moves, 0u);
  EXPECT_EQ(report.collapsed, 0u);  // moved, not removed
  ASSERT_EQ(c.quads.quads, start.quads);
  const std::vector<double> own_after = own(c.quads);
  const std::vector<double> surface_after = surface_scaled_jacobians(as_poly(c.quads), reference);
  for (std::size_t f = 0; f < own_after.size(); ++f) {
    EXPECT_GT(own_after[f], kMinValidScaledJacobian) << f;
    EXPECT_GT(surface_after[f], kMinValidScaledJacobian) << f;
  }
  EXPECT_GT(own_after[4], 0.05);  // convex with a margin, not only just above the threshold
  for (std::size_t v = 0; v < c.quads.positions.size(); ++v) {
    EXPECT_LT(norm(position_of(c.base, c.quads.surface[v]) - c.quads.positions[v]), 1e-12);
    EXPECT_EQ(c.quads.positions[v], again.positions[v]);  // deterministic
    EXPECT_LE(norm(c.quads.positions[v] - start.positions[v]), uo.reach * uo.edge_length);
  }
}

namespace {

// An n x n grid of unit squares in the plane z = 0, vertex (i, j) at index j (n + 1) + i, quad
// (i, j) at index j n + i with corners (i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1).
QuadMesh grid_quads(uint32_t n) {
  QuadMesh q;
  for (uint32_t j = 0; j <= n; ++j)
    for (uint32_t i = 0; i <= n; ++i) q.positions.push_back({double(i), double(j), 0});
  const uint32_t nv = uint32_t(q.positions.size());
  q.surface.assign(nv, SurfacePoint{});
  q.vertex_meta_vertex.assign(nv, kInvalid);
  q.vertex_meta_edge.assign(nv, kInvalid);
  q.placed.assign(nv, QuadMesh::Placed::direct);
  for (uint32_t j = 0; j < n; ++j)
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t v = j * (n + 1) + i;
      q.quads.push_back({v, v + 1, v + n + 2, v + n + 1});
      q.quad_patch.push_back(0);
    }
  return q;
}

// Inner vertices of grid_quads(n) may move, boundary ones not.
std::vector<char> inner_vertices(uint32_t n) {
  std::vector<char> m((n + 1) * (n + 1), 0);
  for (uint32_t j = 1; j < n; ++j)
    for (uint32_t i = 1; i < n; ++i) m[j * (n + 1) + i] = 1;
  return m;
}

void expect_same_manifold(const QuadMesh& after, const QuadMesh& before) {
  bool em = false, vm = false, ori = false;
  const Topology t = topology_of(as_poly(after), &em, &vm, &ori, nullptr, nullptr);
  const Topology t0 = topology_of(as_poly(before), nullptr, nullptr, nullptr, nullptr, nullptr);
  EXPECT_TRUE(em);
  EXPECT_TRUE(vm);
  EXPECT_TRUE(ori);
  EXPECT_EQ(t.euler, t0.euler);
  EXPECT_EQ(t.components, t0.components);
  EXPECT_EQ(t.boundary_loops, t0.boundary_loops);
  EXPECT_EQ(after.quad_patch.size(), after.quads.size());
  EXPECT_EQ(after.surface.size(), after.positions.size());
  EXPECT_EQ(after.vertex_meta_vertex.size(), after.positions.size());
  std::vector<char> used(after.positions.size(), 0);
  for (const auto& f : after.quads)
    for (const uint32_t v : f) used[v] = 1;
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0);  // no vertex left over
}

}  // namespace

TEST(Collapse, RemovesAQuadByItsDiagonalAndKeepsAManifoldOfTheSameTopology) {
  const QuadMesh start = grid_quads(4);  // 25 vertices, 16 quads
  QuadMesh q = start;
  std::vector<char> movable = inner_vertices(4);
  CollapseReport r;
  // Quad (1, 1): corners 6 (1,1), 7, 12 (2,2), 11; its worst corner 6 goes to 12.
  collapse_diagonals(q, movable, {{5, 0}}, 0.5, r);
  EXPECT_EQ(r.collapsed, 1u);
  EXPECT_EQ(r.doublets, 0u);
  EXPECT_EQ(r.refused, 0u);
  EXPECT_EQ(q.quads.size(), 15u);
  EXPECT_EQ(q.positions.size(), 24u);
  EXPECT_EQ(movable.size(), 24u);
  expect_same_manifold(q, start);
  auto has_vertex_at = [&](const QuadMesh& m, Vec3 p) {
    return std::any_of(m.positions.begin(), m.positions.end(),
                       [&](const Vec3& x) { return norm(x - p) < 1e-12; });
  };
  EXPECT_FALSE(has_vertex_at(q, {1, 1, 0}));
  EXPECT_TRUE(has_vertex_at(q, {2, 2, 0}));

  // (2, 1) now has three quads; merging (3, 1) into the boundary vertex (2, 0) across quad
  // (2, 0) leaves it with two, a doublet, which is dissolved: two more quads go.
  const QuadMesh once = q;
  const auto index_at = [&](Vec3 p) {
    for (uint32_t v = 0; v < q.positions.size(); ++v)
      if (norm(q.positions[v] - p) < 1e-12) return v;
    return kInvalid;
  };
  const uint32_t a = index_at({2, 0, 0}), c = index_at({3, 1, 0});
  uint32_t quad = kInvalid;
  int corner = -1;
  for (uint32_t f = 0; f < q.quads.size(); ++f)
    for (int k = 0; k < 4; ++k)
      if (q.quads[f][k] == c && q.quads[f][(k + 2) % 4] == a) quad = f, corner = k;
  ASSERT_NE(quad, kInvalid);
  CollapseReport r2;
  collapse_diagonals(q, movable, {{quad, corner}}, 0.5, r2);
  EXPECT_EQ(r2.collapsed, 1u);
  EXPECT_EQ(r2.doublets, 1u);
  EXPECT_EQ(q.quads.size(), 13u);
  EXPECT_EQ(q.positions.size(), 22u);
  expect_same_manifold(q, once);
  EXPECT_FALSE(has_vertex_at(q, {2, 1, 0}));
}

TEST(Collapse, RefusesDiagonalsBetweenFixedCornersAndOnesThatCutOffATip) {
  const QuadMesh start = grid_quads(4);
  QuadMesh q = start;
  std::vector<char> fixed(25, 0);
  CollapseReport r;
  collapse_diagonals(q, fixed, {{5, 0}}, 0.5, r);
  EXPECT_EQ(r.collapsed, 0u);
  EXPECT_EQ(r.refused, 1u);
  EXPECT_EQ(q.quads, start.quads);

  // Only the tip (1, 1, 2) may move; merging it away would leave it 2 above the new quads.
  q.positions[6].z = 2;
  std::vector<char> tip(25, 0);
  tip[6] = 1;
  CollapseReport r2;
  collapse_diagonals(q, tip, {{5, 0}}, 0.5, r2);
  EXPECT_EQ(r2.collapsed, 0u);
  EXPECT_EQ(r2.refused, 1u);
  EXPECT_EQ(q.quads.size(), 16u);
  CollapseReport r3;
  collapse_diagonals(q, tip, {{5, 0}}, 3.0, r3);  // a looser bound lets it go
  EXPECT_EQ(r3.collapsed, 1u);
  EXPECT_EQ(q.quads.size(), 15u);
}
