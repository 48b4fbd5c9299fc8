// The measures a layout is judged by (issue 32), on small quad meshes whose values are known:
// quads not valid against their own normal, aspect ratio, area spread, feature coverage.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "io/report_json.hpp"
#include "metrics/aabb_tree.hpp"
#include "metrics/feature_coverage.hpp"
#include "metrics/quality.hpp"
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
