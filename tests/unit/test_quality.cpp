// The quality measures, on small quad meshes whose values are known: flips, non-manifold edges
// and distance, the scaled Jacobian and the surface normal it is taken against, the spatial
// index's queries, and the measures a layout is judged by (issue 32): quads not valid against
// their own normal, aspect ratio, area spread, feature coverage.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include <array>
#include <random>
#include "corpus.hpp"
#include "extract/snap.hpp"
#include "io/read_mesh.hpp"
#include "io/report_json.hpp"
#include "isoquad/error.hpp"
#include "metrics/aabb_tree.hpp"
#include "metrics/feature_coverage.hpp"
#include "metrics/quality.hpp"
#include "prep/prepare.hpp"
#include "shapes.hpp"

using namespace isoquad;

namespace {

// One row of quads between y = 0 and y = 1, the i-th from xs[i] to xs[i + 1].
PolyMesh strip(const std::vector<double>& xs) {
  PolyMesh m;
  for (const double x : xs) {
    m.positions.push_back({x, 0, 0});
    m.positions.push_back({x, 1, 0});
  }
  for (uint32_t i = 0; i + 1 < xs.size(); ++i) m.add_face({2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1});
  return m;
}

PolyMesh shifted(PolyMesh m, Vec3 by) {
  for (Vec3& p : m.positions) p += by;
  return m;
}

}  // namespace

// A quad is not valid at scaled Jacobian <= 0.001 against its own normal: a corner of exactly
// 180 degrees (0 up to rounding, of either sign) counts, a corner of sin^-1(0.002) does not.
TEST(QualityMeasures, InvalidQuadsAgainstTheirOwnNormal) {
  EXPECT_EQ(measure_quality(strip({0, 1, 2, 3}), nullptr).sj_invalid, 0u);
  PolyMesh flat;
  flat.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {1, 1, 0}};
  flat.add_face({0, 1, 2, 3});  // the corner at (1, 0) is straight
  QualityReport q = measure_quality(flat, nullptr);
  EXPECT_EQ(q.sj_invalid, 1u);
  EXPECT_EQ(q.sj_nonpositive, 1u);  // exactly 0 here
  // A straight corner a third of the way along an edge whose points are not exactly collinear in
  // floating point: its scaled Jacobian is rounding noise, and it still counts.
  const Vec3 a{0.1, 0.7, 0.3}, b{2.3, 1.9, 0.3};
  PolyMesh noisy;
  noisy.positions = {a, a + (1.0 / 3.0) * (b - a), b, {1.1, 2.9, 0.3}};
  noisy.add_face({0, 1, 2, 3});
  q = measure_quality(noisy, nullptr);
  EXPECT_LT(std::fabs(q.sj_min), 1e-12);
  EXPECT_EQ(q.sj_invalid, 1u);
  // Rhombi with corners of sin^-1(0.0005) and sin^-1(0.002): the first is not valid, the second is.
  auto rhombus = [](double s) {
    const double c = std::sqrt(1 - s * s);
    return std::array<Vec3, 4>{Vec3{0, 0, 0}, {1, 0, 0}, {1 + c, s, 0}, {c, s, 0}};
  };
  EXPECT_NEAR(quad_scaled_jacobian(rhombus(0.0005)), 0.0005, 1e-12);
  PolyMesh two;
  for (const double s : {0.0005, 0.002}) {
    const auto r = rhombus(s);
    const auto base = uint32_t(two.positions.size());
    for (const Vec3& p : r) two.positions.push_back(p + Vec3{0, 0, 10 * s});
    two.add_face({base, base + 1, base + 2, base + 3});
  }
  q = measure_quality(two, nullptr);
  EXPECT_EQ(q.sj_invalid, 1u);
  EXPECT_EQ(q.sj_nonpositive, 0u);
}

// Aspect ratio: the mean lengths of opposite sides, larger over smaller.
TEST(QualityMeasures, AspectRatioOfOppositeSides) {
  EXPECT_EQ(quad_aspect_ratio({Vec3{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}}), 2.0);
  EXPECT_EQ(quad_aspect_ratio({Vec3{0, 0, 0}, {1, 0, 0}, {1, 3, 0}, {0, 3, 0}}), 3.0);
  // A trapezoid: bases 4 and 2 (mean 3), legs sqrt(2).
  EXPECT_NEAR(quad_aspect_ratio({Vec3{0, 0, 0}, {4, 0, 0}, {3, 1, 0}, {1, 1, 0}}),
              3 / std::sqrt(2.0), 1e-15);
  EXPECT_EQ(quad_aspect_ratio({Vec3{0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {0, 0, 0}}), INFINITY);
  // The 2 x 1 rectangle is at 2, not above it.
  QualityReport q = measure_quality(strip({0, 2}), nullptr);
  EXPECT_EQ(q.aspect_mean, 2.0);
  EXPECT_EQ(q.aspect_p95, 2.0);
  EXPECT_EQ(q.aspect_above_2, 0.0);
  // 18 unit squares and two 3 x 1 rectangles: mean 1.2, the 95th percentile (the 19th of 20) 3,
  // 10% above 2; areas 18 x 1 and 2 x 3: mean 1.2, standard deviation 0.6.
  std::vector<double> xs;
  for (int i = 0; i <= 18; ++i) xs.push_back(i);
  xs.push_back(21);
  xs.push_back(24);
  q = measure_quality(strip(xs), nullptr);
  EXPECT_NEAR(q.aspect_mean, 1.2, 1e-15);
  EXPECT_EQ(q.aspect_p95, 3.0);
  EXPECT_NEAR(q.aspect_above_2, 10.0, 1e-12);
  EXPECT_NEAR(q.area_cv, 0.5, 1e-15);
  // With one rectangle, the 19th of 20 is a square.
  xs.pop_back();
  xs.pop_back();
  xs.push_back(19);
  xs.push_back(22);
  EXPECT_EQ(measure_quality(strip(xs), nullptr).aspect_p95, 1.0);
}

// Area coefficient of variation: 0 on a grid of equal squares, also bent over the cube's edges.
TEST(QualityMeasures, AreaVariationOfEqualQuadsIsZero) {
  const QualityReport grid = measure_quality(strip({0, 1, 2, 3, 4, 5}), nullptr);
  EXPECT_EQ(grid.area_cv, 0.0);
  EXPECT_EQ(grid.aspect_mean, 1.0);
  EXPECT_EQ(measure_quality(test::cube_quads(), nullptr).area_cv, 0.0);
  // Non-planar quads have their vector area: a unit square folded by 90 degrees along its
  // diagonal has |(1, 1, 0) x (-1, 1, 1)| / 2 = sqrt(3) / 2.
  PolyMesh bent;
  bent.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 1}};
  bent.add_face({0, 1, 2, 3});
  bent.positions.push_back({5, 0, 0});
  bent.positions.push_back({6, 0, 0});
  bent.positions.push_back({6, 1, 0});
  bent.positions.push_back({5, 1, 0});
  bent.add_face({4, 5, 6, 7});  // area 1
  const double half = std::sqrt(3.0) / 2;
  const double mean = (half + 1) / 2;
  EXPECT_NEAR(measure_quality(bent, nullptr).area_cv, (1 - mean) / mean, 1e-15);
}

// The cube's 12 edges (of its triangulation, the reference) against quad meshes of the cube.
// Tolerance: 0.1 x the quads' mean edge length, 1.
TEST(QualityMeasures, FeatureCoverageOfTheCubesEdges) {
  const PolyMesh reference = test::subdivided_cube(2);
  const auto features = feature_edges(reference, 60);
  EXPECT_EQ(features.size(), 24u);  // each edge in two halves; the face diagonals are flat
  EXPECT_TRUE(feature_edges(reference, 100).empty());  // the cube's dihedral angles are 90
  EXPECT_TRUE(feature_edges(reference, 0).empty());

  // The cube's own quads run along every feature edge.
  QualityReport q = measure_quality(test::cube_quads(), &reference);
  EXPECT_EQ(q.feature_angle_deg, 60.0);
  EXPECT_NEAR(q.feature_length, 12.0, 1e-15);
  EXPECT_EQ(q.feature_coverage, 1.0);
  // Shifted by 0.05 along x, every feature point is within 0.1 of a quad edge.
  q = measure_quality(shifted(test::cube_quads(), {0.05, 0, 0}), &reference);
  EXPECT_EQ(q.feature_coverage, 1.0);
  // Shifted by 0.5: the four edges along x are covered from x = 0.4 on (0.6 each), the four at
  // x = 1 within 0.1 of their ends (0.2 each), those at x = 0 not at all: 3.2 of 12.
  q = measure_quality(shifted(test::cube_quads(), {0.5, 0, 0}), &reference);
  EXPECT_NEAR(q.feature_length, 12.0, 1e-15);
  EXPECT_NEAR(q.feature_coverage, 3.2 / 12, 1e-12);
  // Far away: nothing.
  q = measure_quality(shifted(test::cube_quads(), {3, 3, 3}), &reference);
  EXPECT_EQ(q.feature_coverage, 0.0);
  // With a larger feature angle there are no features, and the coverage is 1 by definition.
  QualityOptions wide;
  wide.feature_angle_deg = 120;
  q = measure_quality(shifted(test::cube_quads(), {0.5, 0, 0}), &reference, wide);
  EXPECT_EQ(q.feature_length, 0.0);
  EXPECT_EQ(q.feature_coverage, 1.0);
  // A flat plate has none either (its boundary is not a feature).
  EXPECT_TRUE(feature_edges(test::grid_plate(4, 4), 60).empty());
}

// The same measures at the ends of the double range (measured at a power-of-two scale, lengths
// scaled back), and in the JSON under their names.
TEST(QualityMeasures, ScaleInvariantAndInTheJson) {
  const PolyMesh reference = test::subdivided_cube(2);
  const PolyMesh quads = shifted(test::cube_quads(), {0.5, 0, 0});
  const QualityReport q = measure_quality(quads, &reference);
  for (const int e : {-1000, 1000}) {
    PolyMesh qs = quads, rs = reference;
    for (Vec3& p : qs.positions) p = ldexp(p, e);
    for (Vec3& p : rs.positions) p = ldexp(p, e);
    const QualityReport s = measure_quality(qs, &rs);
    EXPECT_EQ(s.sj_invalid, q.sj_invalid) << e;
    EXPECT_EQ(s.aspect_mean, q.aspect_mean) << e;
    EXPECT_EQ(s.area_cv, q.area_cv) << e;
    EXPECT_EQ(s.feature_coverage, q.feature_coverage) << e;
    EXPECT_EQ(s.feature_length, std::ldexp(q.feature_length, e)) << e;
    EXPECT_NEAR(s.hausdorff, q.hausdorff, kMaxDistanceRelativeError * q.hausdorff) << e;
  }
  const nlohmann::json j = q;
  EXPECT_EQ(j["scaled_jacobian"]["at_most_0.001"], q.sj_invalid);
  EXPECT_EQ(j["aspect_ratio"]["mean"], q.aspect_mean);
  EXPECT_EQ(j["aspect_ratio"]["p95"], q.aspect_p95);
  EXPECT_EQ(j["aspect_ratio"]["percent_above_2"], q.aspect_above_2);
  EXPECT_EQ(j["area"]["cv"], q.area_cv);
  EXPECT_EQ(j["feature_coverage"]["covered"], q.feature_coverage);
  EXPECT_EQ(j["feature_coverage"]["length"], q.feature_length);
  EXPECT_EQ(j["feature_coverage"]["angle_deg"], 60.0);
  EXPECT_FALSE(nlohmann::json(measure_quality(quads, nullptr)).contains("feature_coverage"));
}

// The Hausdorff distance is found within kMaxDistanceRelativeError, wherever it is reached, with
// few samples or none: an equilateral triangle of side 1 against three tiny triangles at its
// corners (pointing away from it) is farthest at its centre, 1 / sqrt(3) from each corner, where
// no vertex, edge midpoint or likely sample lies; the corners are at distance 0 the other way.
TEST(QualityMeasures, HausdorffDistanceFoundWhereNoSampleIs) {
  const Vec3 c[3] = {{0, 0, 0}, {1, 0, 0}, {0.5, std::sqrt(0.75), 0}};
  const Vec3 centre = (1.0 / 3) * (c[0] + c[1] + c[2]);
  std::vector<std::array<Vec3, 3>> tips;
  for (const Vec3& p : c) {
    const Vec3 out = p - centre;
    tips.push_back({p, p + 1e-3 * out + Vec3{0, 0, 1e-3}, p + 1e-3 * out - Vec3{0, 0, 1e-3}});
  }
  const AabbTree tree(tips);
  const double exact = 1 / std::sqrt(3.0);
  for (const uint32_t samples : {0u, 10u, 1000u}) {
    const SurfaceDistance d = surface_distance({{c[0], c[1], c[2]}}, tree, samples, 1);
    EXPECT_LE(d.max, exact * (1 + 1e-12)) << samples;
    EXPECT_GE(d.max, exact * (1 - kMaxDistanceRelativeError)) << samples;
    EXPECT_FALSE(d.on_b);
    EXPECT_LT(norm(d.at - centre), 0.05) << samples;
  }
}

TEST(Quality, DetectsFlipsNonManifoldEdgesAndDistance) {
  PolyMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0}};
  m.add_face({0, 1, 2, 3});
  m.add_face({1, 4, 5, 2});
  QualityReport q = measure_quality(m, &m);
  EXPECT_TRUE(q.pure_quad);
  EXPECT_TRUE(q.edge_manifold && q.vertex_manifold && q.oriented);
  EXPECT_EQ(q.topology.euler, 1);
  EXPECT_EQ(q.topology.boundary_loops, 1u);
  EXPECT_NEAR(q.sj_min, 1.0, 1e-12);
  EXPECT_NEAR(q.hausdorff, 0.0, 1e-12);
  // A bow-tie quad: its corners alternate orientation.
  PolyMesh bow = m;
  bow.positions[2] = {1, 1, 0};
  bow.positions[5] = {1.5, -1, 0};
  bow.positions[4] = {2, 1, 0};
  q = measure_quality(bow, nullptr);
  EXPECT_EQ(q.sj_nonpositive, 1u);
  // A third face on edge 1-2: not manifold.
  PolyMesh fin = m;
  fin.positions.push_back({1, 0, 1});
  fin.positions.push_back({1, 1, 1});
  fin.add_face({1, 2, 7, 6});
  q = measure_quality(fin, nullptr);
  EXPECT_FALSE(q.edge_manifold);
  // A copy shifted by 0.1 along z: one-sided distances 0.1 everywhere.
  PolyMesh shifted = m;
  for (Vec3& p : shifted.positions) p.z += 0.1;
  q = measure_quality(shifted, &m);
  EXPECT_NEAR(q.hausdorff * std::sqrt(5.0), 0.1, 1e-9);  // diagonal of 2 x 1 x 0 box
  EXPECT_NEAR(q.mean_distance * std::sqrt(5.0), 0.1, 1e-9);
  // One corner lifted by 0.3: the farthest point is that corner, on the quads' side.
  PolyMesh lifted = m;
  lifted.positions[4].z = 0.3;
  q = measure_quality(lifted, &m);
  EXPECT_FALSE(q.hausdorff_on_input);
  EXPECT_LT(norm(q.hausdorff_at - lifted.positions[4]), 1e-12);
  EXPECT_NEAR(q.hausdorff * std::sqrt(5.0), 0.3, 1e-9);
}

// One quad's scaled Jacobian against its own normal, as the report's per-quad value: 1 for a
// square, sqrt(2)/2 at the 45-degree corners of a rhombus, negative at the reflex corner of a
// dart, 0 where an edge has length 0.
TEST(Quality, QuadScaledJacobian) {
  EXPECT_NEAR(quad_scaled_jacobian({Vec3{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}), 1.0, 1e-12);
  EXPECT_NEAR(quad_scaled_jacobian({Vec3{0, 0, 0}, {1, 0, 0}, {2, 1, 0}, {1, 1, 0}}),
              std::sqrt(0.5), 1e-12);
  EXPECT_LT(quad_scaled_jacobian({Vec3{0, 0, 0}, {2, 0, 0}, {0.5, 0.5, 0}, {0, 2, 0}}), 0.0);
  EXPECT_EQ(quad_scaled_jacobian({Vec3{0, 0, 0}, {0, 0, 0}, {1, 1, 0}, {0, 1, 0}}), 0.0);
}

TEST(Quality, SurfaceNormalAtCreaseCornersIsTakenOnTheQuadsSide) {
  // The cube's 6 quads against its triangulation: every corner sits on a crease, where the
  // nearest input face may lie on the other side; the normal is taken just inside the quad.
  const PolyMesh quads = test::cube_quads();
  const PolyMesh tris = test::subdivided_cube(1);
  const QualityReport q = measure_quality(quads, &tris);
  EXPECT_EQ(q.sj_surface_nonpositive, 0u);
  EXPECT_NEAR(q.sj_surface_min, 1.0, 1e-12);
  const std::vector<double> sj = surface_scaled_jacobians(quads, tris);
  ASSERT_EQ(sj.size(), 6u);
  for (const double s : sj) EXPECT_NEAR(s, 1.0, 1e-12);
  // A quad turned inside out is folded against the surface.
  PolyMesh flipped = quads;
  const auto f0 = flipped.face(0);
  std::vector<uint32_t> reversed(f0.rbegin(), f0.rend());
  std::copy(reversed.begin(), reversed.end(), flipped.face_vertices.begin());
  EXPECT_LT(surface_scaled_jacobians(flipped, tris)[0], 0.0);
}

// Where the closest surface point is on an edge (above a ridge) the normal is the mean of the
// two faces' normals, whichever of them the search meets first; above one face, that face's.
TEST(Quality, NormalAtAClosestEdgeIsTheMeanOfItsFaces) {
  // A roof: two faces meeting along the x axis at 90 degrees, both facing up and outwards.
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, l{0, -1, -1}, r{0, 1, -1}, l2{1, -1, -1}, r2{1, 1, -1};
  for (int order = 0; order < 2; ++order) {
    std::vector<std::array<Vec3, 3>> tris = {{a, l, l2}, {a, l2, b}, {a, b, r2}, {a, r2, r}};
    if (order) std::reverse(tris.begin(), tris.end());
    const AabbTree tree(tris);
    const Vec3 up = tree.normal_at_closest({0.5, 0, 0.3});
    EXPECT_NEAR(up.x, 0, 1e-12);
    EXPECT_NEAR(up.y, 0, 1e-12);
    EXPECT_NEAR(up.z, 1, 1e-12);
    const Vec3 side = tree.normal_at_closest({0.5, 0.5, -0.4});  // above the right face
    EXPECT_NEAR(side.y, std::sqrt(0.5), 1e-12);
    EXPECT_NEAR(side.z, std::sqrt(0.5), 1e-12);
  }
}

// The tree searches nearer boxes first and prunes with the best distance so far; its answers
// must be those of a scan of every triangle: the distance, and the normal averaged over every
// triangle within the tolerance of it (in triangle order), so that untangling, snapping and
// `isoquad quality` agree whatever the tree's layout. Fandisk has ridges and corners, where
// several triangles are closest; the points are at and near its vertices, edges and faces.
TEST(Quality, TreeQueriesEqualAScanOfEveryTriangle) {
  const PreparedMesh prep = prepare(read_mesh(test::data_dir() / "fandisk.off").mesh);
  const TriMesh& mesh = prep.components.at(0).mesh;
  const std::vector<std::array<Vec3, 3>> tris = face_triangles(mesh);
  const AabbTree tree(tris);
  Box3 box;
  for (const Vec3& p : mesh.positions()) box.add(p);
  const double tol = 1e-9 * box.diagonal();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> offset(-0.02, 0.02);
  uint32_t shared = 0;  // queries whose closest point is on several triangles
  for (uint32_t i = 0; i < 600; ++i) {
    const Tri& t = mesh.face(uint32_t(rng() % mesh.num_faces()));
    const double w0 = (i % 3 == 0) ? 1.0 : 0.2, w1 = (i % 3 == 1) ? 0.0 : 0.3;  // vertex, edge
    const Vec3 on =
        w0 * mesh.position(t[0]) + w1 * mesh.position(t[1]) + (1 - w0 - w1) * mesh.position(t[2]);
    // Half of the points on the surface (on a vertex or an edge: several triangles closest),
    // half off it.
    const double off = i % 2 ? box.diagonal() : 0.0;
    const Vec3 p = on + off * Vec3{offset(rng), offset(rng), offset(rng)};
    double best = INFINITY;
    for (const auto& s : tris)
      best = std::min(best, norm(closest_point_on_triangle(p, s[0], s[1], s[2]) - p));
    EXPECT_EQ(tree.closest(p).distance, best);
    Vec3 sum{0, 0, 0};
    uint32_t within = 0;
    for (const auto& s : tris)
      if (norm(closest_point_on_triangle(p, s[0], s[1], s[2]) - p) <= best + tol) {
        sum = sum + normalized(cross(s[1] - s[0], s[2] - s[0]));
        ++within;
      }
    shared += within > 1;
    const Vec3 n = tree.normal_at_closest(p), hinted = tree.normal_at_closest(p, t[0] % 7);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(n[k], normalized(sum)[k]) << "query " << i;
      EXPECT_EQ(hinted[k], n[k]) << "query " << i;
    }
  }
  EXPECT_GT(shared, 100u);  // the ties the averaging is for were exercised
}
