#include <algorithm>
#include <gtest/gtest.h>
#include <set>

#include "prep/prepare.hpp"
#include "seg/patch_topology.hpp"
#include "seg/segment.hpp"
#include "seg_checks.hpp"
#include "shapes.hpp"

using namespace isoquad;

namespace {

PreparedComponent prepared(const PolyMesh& m, double feature_angle = 60) {
  PreparedMesh p = prepare(m, {.feature_angle_deg = feature_angle});
  return std::move(p.components.at(0));
}

void expect_valid(const TriMesh& base, const SegmentResult& r) { test::expect_valid_segmentation(base, r); }

SegmentOptions with_patches(uint32_t k, double compactness = 0.05) {
  SegmentOptions o;
  o.vsa.patches = k;
  o.vsa.compactness = compactness;
  return o;
}

}  // namespace

TEST(Vsa, CubeFacesAreFoundWithoutFeatureHints) {
  const PreparedComponent c = prepared(test::subdivided_cube(6), 0);  // no feature barriers
  const EdgeData<char> none(c.mesh.num_edges(), 0);
  VsaOptions o;
  o.patches = 6;
  o.compactness = 0;
  const Segmentation s = segment_vsa(c.mesh, none, o);
  ASSERT_EQ(s.num_patches(), 6u);
  EXPECT_LT(s.energy_log.back(), 1e-12);  // every region is exactly one flat cube face
  for (uint32_t f = 0; f < c.mesh.num_faces(); ++f)
    EXPECT_NEAR(dot(c.mesh.face_normal(f), s.proxies[s.face_patch[f]].normal), 1.0, 1e-9);
}

TEST(Vsa, DeterministicForASeed) {
  const PreparedComponent c = prepared(test::torus(40, 16));
  VsaOptions o;
  o.patches = 12;
  const Segmentation a = segment_vsa(c.mesh, c.feature, o), b = segment_vsa(c.mesh, c.feature, o);
  EXPECT_EQ(a.face_patch.values(), b.face_patch.values());
  o.seed = 7;
  const Segmentation d = segment_vsa(c.mesh, c.feature, o);
  EXPECT_EQ(d.num_patches(), 12u);
}

TEST(Vsa, FeatureEdgesAreNeverInsideAPatch) {
  const PreparedComponent c = prepared(test::subdivided_cube(5));
  ASSERT_EQ(std::count(c.feature.begin(), c.feature.end(), 1), 12 * 5);
  const SegmentResult r = segment(c.mesh, c.feature, with_patches(2));
  const TriMesh& rm = r.refined.mesh;
  EXPECT_EQ(std::count(r.feature.begin(), r.feature.end(), 1), 12 * 5);
  for (uint32_t e = 0; e < rm.num_edges(); ++e) {
    if (!r.feature[e]) continue;
    const uint32_t h = rm.edge_halfedge(e);
    EXPECT_NE(r.labels[TriMesh::face_of(h)], r.labels[TriMesh::face_of(rm.twin(h))]);
  }
  EXPECT_EQ(r.num_patches, 6u);  // one patch per cube face, whatever K asks
  EXPECT_EQ(r.meta.vertices.size(), 8u);
  EXPECT_EQ(r.meta.edges.size(), 12u);
  for (const MetaVertex& v : r.meta.vertices) EXPECT_EQ(v.wedge_patches.size(), 3u);
  expect_valid(c.mesh, r);
}

TEST(Disk, SphereInOnePatchIsSplit) {
  const PreparedComponent c = prepared(test::icosphere(3));
  const SegmentResult r = segment(c.mesh, c.feature, with_patches(1));
  EXPECT_GE(r.num_patches, 2u);
  EXPECT_GE(r.repair.voronoi_splits, 1u);
  expect_valid(c.mesh, r);
}

TEST(Disk, AnnulusIsCutIntoTwoDisks) {
  const PreparedComponent c = prepared(test::plate_with_hole(20));
  ASSERT_EQ(c.mesh.boundary_loops().size(), 2u);
  const SegmentResult r = segment(c.mesh, c.feature, with_patches(1));
  EXPECT_EQ(r.num_patches, 2u);
  EXPECT_EQ(r.repair.two_path_cuts, 1u);
  expect_valid(c.mesh, r);
}

TEST(Disk, OpenTubeBecomesLongStripsNotRings) {
  const PreparedComponent c = prepared(test::open_cylinder(24, 40));
  const SegmentResult r = segment(c.mesh, c.feature, with_patches(1));
  ASSERT_EQ(r.num_patches, 2u);
  const TriMesh& rm = r.refined.mesh;
  for (uint32_t p = 0; p < 2; ++p) {  // each strip runs the whole length of the tube
    double lo = INFINITY, hi = -INFINITY;
    for (uint32_t f = 0; f < rm.num_faces(); ++f)
      if (r.labels[f] == p)
        for (uint32_t v : rm.face(f)) lo = std::min(lo, rm.position(v).z), hi = std::max(hi, rm.position(v).z);
    EXPECT_NEAR(hi - lo, c.mesh.bounding_box().hi.z - c.mesh.bounding_box().lo.z, 1e-12);
  }
  expect_valid(c.mesh, r);
}

TEST(Disk, TorusInOnePatch) {
  const PreparedComponent c = prepared(test::torus(48, 16));
  const SegmentResult r = segment(c.mesh, c.feature, with_patches(1));
  EXPECT_EQ(r.meta.euler(), 0);
  expect_valid(c.mesh, r);
}

TEST(Meta, PlateCornersAreTheGeometricCorners) {
  const PreparedComponent c = prepared(test::grid_plate(12, 8));
  const SegmentResult r = segment(c.mesh, c.feature, with_patches(1));
  ASSERT_EQ(r.num_patches, 1u);
  ASSERT_EQ(r.meta.vertices.size(), 4u);
  EXPECT_EQ(r.meta.inserted, 0u);
  const Box3 box = c.mesh.bounding_box();
  for (const MetaVertex& v : r.meta.vertices) {
    const Vec3 p = c.mesh.position(v.vertex);
    EXPECT_TRUE(p.x == box.lo.x || p.x == box.hi.x) << p.x;
    EXPECT_TRUE(p.y == box.lo.y || p.y == box.hi.y) << p.y;
  }
  expect_valid(c.mesh, r);
}

TEST(Meta, TwoHemispheresGetInsertedMetaVertices) {
  // Two patches meeting along one closed seam: no junction anywhere, so 4 are inserted.
  const PreparedComponent c = prepared(test::icosphere(3));
  FaceData<uint32_t> labels(c.mesh.num_faces());
  for (uint32_t f = 0; f < c.mesh.num_faces(); ++f) {
    const Tri& t = c.mesh.face(f);
    labels[f] = c.mesh.position(t[0]).z + c.mesh.position(t[1]).z + c.mesh.position(t[2]).z > 0 ? 1 : 0;
  }
  const MetaMesh mm = build_meta_mesh(c.mesh, labels, 2, c.feature);
  EXPECT_EQ(mm.inserted, 4u);
  EXPECT_EQ(mm.vertices.size(), 4u);
  EXPECT_EQ(mm.edges.size(), 4u);  // 2 - 4 + 2 = 0? no: V - E + F = 4 - 4 + 2 = 2
  EXPECT_EQ(mm.euler(), 2);
  for (const MetaEdge& e : mm.edges) EXPECT_NE(e.left, e.right);
  EXPECT_NO_THROW(check_meta_mesh(c.mesh, labels, mm));
}

TEST(Straighten, StaircaseSeamGetsShorterAndTopologyIsKept) {
  // A plate split by a square wave: 8 teeth of depth 0.2 across a unit plate.
  const PreparedComponent c = prepared(test::grid_plate(40, 40));
  const Box3 box = c.mesh.bounding_box();
  FaceData<uint32_t> labels(c.mesh.num_faces());
  for (uint32_t f = 0; f < c.mesh.num_faces(); ++f) {
    const Tri& t = c.mesh.face(f);
    const Vec3 m = (c.mesh.position(t[0]) + c.mesh.position(t[1]) + c.mesh.position(t[2])) / 3.0;
    const double u = (m.x - box.lo.x) / (box.hi.x - box.lo.x), v = (m.y - box.lo.y) / (box.hi.y - box.lo.y);
    labels[f] = u < 0.4 + 0.2 * (int(v * 8) % 2) ? 0 : 1;
  }
  const auto before = patch_topology(c.mesh, labels, 2);
  ASSERT_TRUE(before[0].is_disk() && before[1].is_disk());
  StraightenLog log;
  straighten_seams(c.mesh, labels, 2, c.feature, log);
  EXPECT_LT(log.seam_length_after, 0.5 * log.seam_length_before);  // 2.6 units of zigzag become ~1
  const auto after = patch_topology(c.mesh, labels, 2);
  EXPECT_TRUE(after[0].is_disk() && after[1].is_disk());
  EXPECT_EQ(build_meta_mesh(c.mesh, labels, 2, c.feature).euler(), 1);
}
