#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "field/cross_field.hpp"
#include "field/feature_curves.hpp"
#include "field/field_segment.hpp"
#include "field/trace.hpp"
#include "pipeline/sizing.hpp"
#include "prep/prepare.hpp"
#include "shapes.hpp"

using namespace isoquad;

namespace {

constexpr double kPi = std::numbers::pi;

PreparedComponent prepared(const PolyMesh& m, double feature_angle = 60) {
  PreparedMesh p = prepare(m, {.feature_angle_deg = feature_angle});
  return std::move(p.components.at(0));
}

CrossField field_of(const PreparedComponent& c, double quads = 200) {
  CrossFieldOptions o;
  o.edge_length = edge_length_for_quads(c.mesh, quads);
  return compute_cross_field(c.mesh, c.feature, o);
}

// The angle (degrees, in [0, 45]) between a 3D direction and the nearest arm of f's cross.
double off_cross_deg(const CrossField& cf, uint32_t f, Vec3 d) {
  const double a = cf.frames.arg(f, d) - cf.angle[f];
  return std::abs(std::remainder(a, kPi / 2)) * 180 / kPi;
}

int count_index(const CrossField& cf, int32_t index4) {
  return int(std::count(cf.index4.begin(), cf.index4.end(), index4));
}

int64_t index_sum(const CrossField& cf) {
  int64_t s = 0;
  for (int32_t i : cf.index4) s += i;
  return s;
}

}  // namespace

TEST(CrossField, FlatSquareIsConstantWithFourCornerIndices) {
  const PreparedComponent c = prepared(test::grid_plate(12, 12));
  const CrossField cf = field_of(c);
  EXPECT_EQ(cf.variant, FieldVariant::linear);
  for (uint32_t f = 0; f < c.mesh.num_faces(); ++f)
    EXPECT_LT(off_cross_deg(cf, f, {1, 0, 0}), 1e-9) << "face " << f;
  // The four corners are quarter-turn vertices (a convex corner: one quad); nothing else turns.
  EXPECT_EQ(count_index(cf, 1), 4);
  EXPECT_EQ(count_index(cf, 0), int(c.mesh.num_vertices()) - 4);
  EXPECT_TRUE(cf.singular.empty());
  EXPECT_NEAR(cf.energy, 0, 1e-12);
}

TEST(CrossField, OpenCylinderFollowsItsRulings) {
  const PreparedComponent c = prepared(test::open_cylinder(32, 12));
  const CrossField cf = field_of(c);
  // The cylinder's axis is the coordinate axis along which it is longest.
  const Box3 box = c.mesh.bounding_box();
  const Vec3 ext = box.hi - box.lo;
  const Vec3 along = ext.x > ext.y && ext.x > ext.z ? Vec3{1, 0, 0}
                     : ext.y > ext.z                ? Vec3{0, 1, 0}
                                                    : Vec3{0, 0, 1};
  double worst = 0;
  for (uint32_t f = 0; f < c.mesh.num_faces(); ++f)
    worst = std::max(worst, off_cross_deg(cf, f, along));
  EXPECT_LT(worst, 1.0);
  EXPECT_EQ(index_sum(cf), 0);
  EXPECT_TRUE(cf.singular.empty());
}

TEST(CrossField, CubeHasEightPositiveQuarterSingularitiesAtItsCorners) {
  const PreparedComponent c = prepared(test::subdivided_cube(8));
  const CrossField cf = field_of(c);
  EXPECT_EQ(index_sum(cf), 4 * 2);
  ASSERT_EQ(cf.singular.size(), 8u);
  for (uint32_t v : cf.singular) {
    EXPECT_EQ(cf.index4[v], 1);
    // A cube corner: every coordinate at the box's extremes.
    const Vec3 p = c.mesh.position(v);
    const Box3 box = c.mesh.bounding_box();
    for (int i = 0; i < 3; ++i)
      EXPECT_TRUE(std::abs(p[i] - box.lo[i]) < 1e-9 || std::abs(p[i] - box.hi[i]) < 1e-9);
  }
}

TEST(CrossField, RoundedCubeWithoutFeaturesUsesTheSmoothestField) {
  const PreparedComponent c = prepared(test::subdivided_cube(8), 0);  // no feature edge
  const CrossField cf = field_of(c);
  EXPECT_EQ(cf.constrained_faces, 0u);
  EXPECT_EQ(index_sum(cf), 8);
  EXPECT_EQ(count_index(cf, 1), 8);
  EXPECT_EQ(cf.singular.size(), 8u);
}

TEST(CrossField, SphereIndicesSumToTwo) {
  const PreparedComponent c = prepared(test::icosphere(4));
  const CrossField cf = field_of(c);
  EXPECT_EQ(cf.variant, FieldVariant::eigen);
  EXPECT_EQ(index_sum(cf), 8);
  // The smoothest field on a round sphere: eight +1/4 singularities and nothing else.
  EXPECT_EQ(count_index(cf, 1), 8);
  EXPECT_EQ(cf.singular.size(), 8u);
}

TEST(CrossField, TorusHasNoSingularity) {
  const PreparedComponent c = prepared(test::torus(48, 16));
  const CrossField cf = field_of(c);
  EXPECT_EQ(index_sum(cf), 0);
  EXPECT_TRUE(cf.singular.empty());
}

TEST(CrossField, PlateWithStaircaseHoleSplitsConflictsAndSumsToZero) {
  // The hole is cut out by face centroids, so its boundary has 45-degree steps: faces with an
  // axis-aligned and a diagonal boundary edge, which no cross can follow both of.
  const PreparedComponent c = prepared(test::plate_with_hole(12));
  EdgeData<char> feature = c.feature;
  const RefinedMesh r = split_constraint_conflicts(identity_refinement(c.mesh), feature);
  EXPECT_GT(r.mesh.num_faces(), c.mesh.num_faces());
  EXPECT_EQ(r.mesh.boundary_loops().size(), 2u);
  CrossFieldOptions o;
  o.edge_length = edge_length_for_quads(r.mesh, 200);
  const CrossField cf = compute_cross_field(r.mesh, feature, o);
  EXPECT_EQ(index_sum(cf), 0);
  // The four outer corners are convex quarter turns; the hole's staircase turns both ways.
  EXPECT_GE(count_index(cf, 1), 4);
  EXPECT_GE(count_index(cf, -1), 4);
  // Every constrained face follows its boundary edge exactly.
  for (uint32_t f = 0; f < r.mesh.num_faces(); ++f)
    for (uint32_t i = 0; i < 3; ++i) {
      const uint32_t h = 3 * f + i;
      if (r.mesh.twin(h) != kInvalid) continue;
      const Vec3 d = r.mesh.position(r.mesh.to(h)) - r.mesh.position(r.mesh.from(h));
      EXPECT_LT(off_cross_deg(cf, f, d), 1e-9) << "face " << f;
    }
}

TEST(CrossField, SquareWithAxisHoleIsConstant) {
  // A 12 x 12 grid without the 4 x 4 cells at its middle: the hole's sides are grid lines.
  PolyMesh m;
  const PolyMesh grid = test::grid_plate(12, 12);
  m.positions = grid.positions;
  for (std::size_t f = 0; f < grid.num_faces(); f += 2) {
    const uint32_t cell = uint32_t(f / 2), i = cell % 12, j = cell / 12;
    if (i >= 4 && i < 8 && j >= 4 && j < 8) continue;
    m.add_face(grid.face(f));
    m.add_face(grid.face(f + 1));
  }
  const PreparedComponent c = prepared(m);
  const CrossField cf = field_of(c);
  EXPECT_EQ(index_sum(cf), 0);
  EXPECT_EQ(count_index(cf, 1), 4);   // outer corners: one quad each
  EXPECT_EQ(count_index(cf, -1), 4);  // the hole's corners: three quads each
  EXPECT_TRUE(cf.singular.empty());
  for (uint32_t f = 0; f < c.mesh.num_faces(); ++f)
    EXPECT_LT(off_cross_deg(cf, f, {1, 0, 0}), 1e-9) << "face " << f;
}

TEST(CrossField, SameInputGivesTheSameBits) {
  const PreparedComponent c = prepared(test::torus(40, 14));
  const CrossField a = field_of(c), b = field_of(c);
  EXPECT_EQ(a.angle.values(), b.angle.values());
  EXPECT_EQ(a.index4.values(), b.index4.values());
}

TEST(FeatureCurves, CubeEdgesAreTwelveCurvesInOneNetwork) {
  const PreparedComponent c = prepared(test::subdivided_cube(6));
  const std::vector<FeatureCurve> curves = feature_curves(c.mesh, c.feature);
  ASSERT_EQ(curves.size(), 12u);
  const Box3 box = c.mesh.bounding_box();
  const double side = box.hi.x - box.lo.x;
  for (const FeatureCurve& curve : curves) {
    EXPECT_NEAR(curve.length, side, 1e-9);
    EXPECT_EQ(curve.halfedges.size(), 6u);
    EXPECT_FALSE(curve.closed);
  }
  // One network of 12 sides: kept whole below its total length, dropped whole above it.
  uint32_t dropped = 0;
  const EdgeData<char> kept = long_features(c.mesh, c.feature, {11.5 * side}, &dropped);
  EXPECT_EQ(dropped, 0u);
  EXPECT_EQ(kept.values(), c.feature.values());
  const EdgeData<char> none = long_features(c.mesh, c.feature, {12.5 * side}, &dropped);
  EXPECT_EQ(dropped, 1u);
  EXPECT_EQ(std::count(none.begin(), none.end(), 1), 0);
}

TEST(FeatureCurves, ShortNetworksAreDroppedOnlyWhereTheyAreWeak) {
  // The cube's creases bend by 90 degrees: a short network that is kept when weak means below
  // 85 degrees, dropped when it means below 95, and kept at any angle once long enough.
  const PreparedComponent c = prepared(test::subdivided_cube(6));
  const Box3 box = c.mesh.bounding_box();
  const double side = box.hi.x - box.lo.x;
  uint32_t dropped = 0;
  EXPECT_EQ(long_features(c.mesh, c.feature, {side, 13 * side, 85}, &dropped).values(),
            c.feature.values());
  EXPECT_EQ(dropped, 0u);
  const EdgeData<char> weak = long_features(c.mesh, c.feature, {side, 13 * side, 95}, &dropped);
  EXPECT_EQ(std::count(weak.begin(), weak.end(), 1), 0);
  EXPECT_EQ(dropped, 1u);
  EXPECT_EQ(long_features(c.mesh, c.feature, {side, 11 * side, 95}, &dropped).values(),
            c.feature.values());
}

TEST(FeatureCurves, ClosedRingIsOneClosedCurve) {
  // The cylinder's boundary is not a feature; a feature ring is marked by hand around its middle.
  const PreparedComponent c = prepared(test::open_cylinder(24, 8));
  EdgeData<char> ring(c.mesh.num_edges(), 0);
  const Box3 box = c.mesh.bounding_box();
  const double mid = 0.5 * (box.lo.z + box.hi.z);
  uint32_t marked = 0;
  for (uint32_t e = 0; e < c.mesh.num_edges(); ++e) {
    const uint32_t h = c.mesh.edge_halfedge(e);
    if (std::abs(c.mesh.position(c.mesh.from(h)).z - mid) < 1e-9 &&
        std::abs(c.mesh.position(c.mesh.to(h)).z - mid) < 1e-9)
      ring[e] = 1, ++marked;
  }
  ASSERT_EQ(marked, 24u);
  const std::vector<FeatureCurve> curves = feature_curves(c.mesh, ring);
  ASSERT_EQ(curves.size(), 1u);
  EXPECT_TRUE(curves[0].closed);
  EXPECT_EQ(curves[0].halfedges.size(), 24u);
  for (std::size_t i = 0; i < 24; ++i)
    EXPECT_EQ(c.mesh.to(curves[0].halfedges[i]), c.mesh.from(curves[0].halfedges[(i + 1) % 24]));
}

namespace {

// A 12 x 12 grid without the cells whose (i, j) `drop` says.
template <class Drop>
PolyMesh grid_without(Drop drop) {
  PolyMesh m;
  const PolyMesh grid = test::grid_plate(12, 12);
  m.positions = grid.positions;
  for (std::size_t f = 0; f < grid.num_faces(); f += 2) {
    const uint32_t cell = uint32_t(f / 2), i = cell % 12, j = cell / 12;
    if (drop(i, j)) continue;
    m.add_face(grid.face(f));
    m.add_face(grid.face(f + 1));
  }
  return m;
}

TraceResult traces_of(const CrossField& cf, double h) {
  TraceOptions o;
  o.edge_length = h;
  return trace_separatrices(cf, o);
}

}  // namespace

TEST(Trace, SquareNeedsNoTrace) {
  const PreparedComponent c = prepared(test::grid_plate(12, 12));
  const CrossField cf = field_of(c);
  EXPECT_TRUE(traces_of(cf, 0.1).traces.empty());
}

TEST(Trace, LPlateConcaveCornerCutsItIntoThree) {
  const PreparedComponent c =
      prepared(grid_without([](uint32_t i, uint32_t j) { return i >= 6 && j >= 6; }));
  const CrossField cf = field_of(c);
  const TraceResult r = traces_of(cf, 0.1);
  ASSERT_EQ(r.nodes.size(), 1u);  // the concave corner; the five convex ones emit nothing
  ASSERT_EQ(r.traces.size(), 2u);
  for (const Trace& t : r.traces) {
    EXPECT_EQ(t.end, TraceEnd::boundary);
    // Each runs straight along a grid line, from the corner to the opposite side (within 1e-9
    // of an edge's length: a trace along mesh edges passes beside the vertices, which the
    // embedding snaps).
    const Vec3 a = position_on(c.mesh, t.points.front()), b = position_on(c.mesh, t.points.back());
    const Vec3 d = b - a;
    EXPECT_NEAR(std::min(std::abs(d.x), std::abs(d.y)), 0, 1e-9);
    for (const SurfacePoint& p : t.points) {
      const Vec3 q = position_on(c.mesh, p);
      EXPECT_NEAR(std::abs(d.x) < std::abs(d.y) ? q.x - a.x : q.y - a.y, 0, 1e-9);
    }
    EXPECT_NEAR(t.length, norm(d), 1e-9);
  }
}

// A ray the coarse layout removes is not traced and makes its node partial; of two neighbouring
// rays of one node only the first goes (their sector would turn by three quarters).
TEST(Trace, RemovedRaysAreNotTracedAndNeverTwoNeighbours) {
  const PreparedComponent c =
      prepared(grid_without([](uint32_t i, uint32_t j) { return i >= 6 && j >= 6; }));
  const CrossField cf = field_of(c);
  const TraceResult all = traces_of(cf, 0.1);
  ASSERT_EQ(all.traces.size(), 2u);
  std::vector<RayId> rays;
  for (const Trace& t : all.traces) rays.push_back({t.source, t.first_face, t.first_arm});
  TraceOptions o;
  o.edge_length = 0.1;
  o.removed = {rays[1]};
  const TraceResult one = trace_separatrices(cf, o);
  ASSERT_EQ(one.traces.size(), 1u);
  EXPECT_EQ(one.traces[0].first_face, rays[0].face);
  EXPECT_EQ(one.traces[0].first_arm, rays[0].arm);
  EXPECT_EQ(one.deleted, 1u);
  EXPECT_EQ(one.partial_nodes, std::vector<uint32_t>{rays[1].vertex});
  o.removed = rays;
  const TraceResult both = trace_separatrices(cf, o);
  ASSERT_EQ(both.traces.size(), 1u);
  EXPECT_EQ(both.deleted, 1u);
  EXPECT_EQ(both.traces[0].first_face, rays[1].face);
}

TEST(Trace, SphereSeparatricesAllEndOnTracksOrSingularities) {
  const PreparedComponent c = prepared(test::icosphere(4));
  const CrossField cf = field_of(c);
  ASSERT_EQ(cf.singular.size(), 8u);
  const TraceResult r = traces_of(cf, edge_length_for_quads(c.mesh, 200));
  EXPECT_EQ(r.ray_mismatches, 0u);
  // Three rays per +1/4 singularity: each one traced, or the far end of a connection (a
  // separatrix from singularity to singularity, traced once), or deleted beside a parallel trace.
  EXPECT_EQ(r.traces.size() + r.connections + r.deleted, 24u);
  EXPECT_GT(r.connections, 0u);
  uint32_t at_nodes = 0;
  for (const Trace& t : r.traces) {
    EXPECT_TRUE(t.end == TraceEnd::track || t.end == TraceEnd::node);
    EXPECT_EQ(t.points.size(), t.faces.size() + 1);
    if (t.end == TraceEnd::track) {
      EXPECT_NE(t.end_trace, kInvalid);
      continue;
    }
    ++at_nodes;
    // A connection ends at another singular vertex, exactly at it.
    EXPECT_NE(t.end_vertex, t.source);
    EXPECT_NE(std::find(cf.singular.begin(), cf.singular.end(), t.end_vertex), cf.singular.end());
    EXPECT_LT(norm(position_on(c.mesh, t.points.back()) - c.mesh.position(t.end_vertex)), 1e-12);
  }
  EXPECT_EQ(at_nodes, r.connections);
  // The same input gives the same traces.
  const TraceResult again = traces_of(cf, edge_length_for_quads(c.mesh, 200));
  ASSERT_EQ(again.traces.size(), r.traces.size());
  for (std::size_t i = 0; i < r.traces.size(); ++i) {
    EXPECT_EQ(again.traces[i].faces, r.traces[i].faces);
    EXPECT_EQ(again.traces[i].length, r.traces[i].length);
  }
}

TEST(Trace, TorusHasNoNodes) {
  const PreparedComponent c = prepared(test::torus(48, 16));
  const CrossField cf = field_of(c);
  EXPECT_TRUE(traces_of(cf, 0.1).nodes.empty());
}

// A torus has no node, so no trace and one patch that is not a disk: two seeds far apart, each
// closing a loop around the tube and joining the other along it, cut it into four disks whose
// corners are all the traces' (FIELD_LAYOUT.md §4).
TEST(FieldSegment, TorusIsCutIntoFourDisksBySeeds) {
  const PreparedComponent c = prepared(test::torus(48, 16));
  FieldLayoutLog log;
  const FieldSegmentation fs =
      field_segment(c.mesh, c.feature, edge_length_for_quads(c.mesh, 400), log);
  ASSERT_TRUE(log.failure.empty()) << log.failure;
  EXPECT_EQ(log.singularities, 0u);
  EXPECT_EQ(log.seeds, 2u);
  EXPECT_EQ(fs.seg.num_patches, 4u);
  EXPECT_EQ(log.free_corner_patches, 0u);
  ASSERT_EQ(fs.corners.size(), 4u);
  for (const auto& corners : fs.corners) EXPECT_NE(corners, kFreeCorners);
}
