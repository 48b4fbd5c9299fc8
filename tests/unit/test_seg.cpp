#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <set>
#include <tuple>

#include "core/refined_mesh.hpp"
#include "corpus.hpp"
#include "io/read_mesh.hpp"
#include "isoquad/error.hpp"
#include "marching_tets.hpp"
#include "prep/prepare.hpp"
#include "seg/disk_patches.hpp"
#include "seg/geodesic.hpp"
#include "seg/patch_topology.hpp"
#include "seg/segment.hpp"
#include "seg/vsa.hpp"
#include "seg_checks.hpp"
#include "shapes.hpp"
#include "stress_parametric.hpp"

using namespace isoquad;

namespace {

PreparedComponent prepared(const PolyMesh& m, double feature_angle = 60) {
  PreparedMesh p = prepare(m, {.feature_angle_deg = feature_angle});
  return std::move(p.components.at(0));
}

void expect_valid(const TriMesh& base, const SegmentResult& r) {
  test::expect_valid_segmentation(base, r);
}

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

// Two cube faces given as one region come apart exactly along their shared edge: the split is a
// two-proxy VSA inside the region, and with the pure L2,1 metric each flat face is one proxy.
TEST(VsaSplit, ARegionOfTwoCubeFacesSplitsAlongTheirEdge) {
  const PreparedComponent c = prepared(test::subdivided_cube(6), 0);
  const EdgeData<char> none(c.mesh.num_edges(), 0);
  // Labels by face normal: +x and +y together as region 0, the other four faces 1..4.
  FaceData<uint32_t> labels(c.mesh.num_faces(), 0);
  uint32_t next = 1;
  std::map<std::tuple<long, long, long>, uint32_t> by_normal;
  for (uint32_t f = 0; f < c.mesh.num_faces(); ++f) {
    const Vec3 n = c.mesh.face_normal(f);
    if (n.x > 0.5 || n.y > 0.5) continue;
    const auto key = std::tuple(std::lround(n.x), std::lround(n.y), std::lround(n.z));
    if (!by_normal.count(key)) by_normal[key] = next++;
    labels[f] = by_normal[key];
  }
  ASSERT_EQ(next, 5u);
  VsaOptions o;
  o.compactness = 0;
  const FaceData<uint32_t> split = split_vsa_regions(c.mesh, none, labels, {0}, o);
  std::set<uint32_t> plus_x, plus_y;
  for (uint32_t f = 0; f < c.mesh.num_faces(); ++f) {
    const Vec3 n = c.mesh.face_normal(f);
    if (labels[f] != 0) {
      EXPECT_EQ(split[f], labels[f]) << "face " << f << " is outside the split region";
      continue;
    }
    (n.x > 0.5 ? plus_x : plus_y).insert(split[f]);
  }
  ASSERT_EQ(plus_x.size(), 1u);
  ASSERT_EQ(plus_y.size(), 1u);
  EXPECT_NE(*plus_x.begin(), *plus_y.begin());
  EXPECT_EQ(std::max(*plus_x.begin(), *plus_y.begin()), 5u);  // the new part comes after the rest
  EXPECT_EQ(std::min(*plus_x.begin(), *plus_y.begin()), 0u);
}

// On a curved surface every split region becomes two connected parts, the rest is untouched.
TEST(VsaSplit, SplitRegionsBecomeTwoConnectedParts) {
  const PreparedComponent c = prepared(test::torus(40, 16));
  VsaOptions o;
  o.patches = 12;
  const Segmentation s = segment_vsa(c.mesh, c.feature, o);
  ASSERT_EQ(s.num_patches(), 12u);
  const FaceData<uint32_t> split = split_vsa_regions(c.mesh, c.feature, s.face_patch, {3, 7}, o);
  std::map<uint32_t, std::set<uint32_t>> parts;
  for (uint32_t f = 0; f < c.mesh.num_faces(); ++f) {
    parts[s.face_patch[f]].insert(split[f]);
    if (s.face_patch[f] != 3 && s.face_patch[f] != 7) {
      EXPECT_EQ(split[f], s.face_patch[f]);
    }
  }
  for (const uint32_t r : {3u, 7u}) {
    ASSERT_EQ(parts[r].size(), 2u) << "region " << r;
    EXPECT_TRUE(parts[r].count(r));
    for (const uint32_t l : parts[r]) EXPECT_TRUE(test::patch_connected(c.mesh, split, l));
  }
  std::set<uint32_t> all(split.begin(), split.end());
  EXPECT_EQ(all.size(), 14u);
  EXPECT_EQ(*all.rbegin(), 13u);
  // Deterministic.
  EXPECT_EQ(split_vsa_regions(c.mesh, c.feature, s.face_patch, {3, 7}, o).values(), split.values());
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

// One label over a surface whose hole or handle is far smaller than the cells a Voronoi split of
// 24 seeds makes: the hole gets a strip to the outer loop, the handle a ring round it, and every
// patch ends a disk.
FaceData<uint32_t> disk_patches_from_one(const TriMesh& m, DiskRepairLog& log) {
  FaceData<uint32_t> labels(m.num_faces(), 0u);
  const uint32_t n = make_disk_patches(m, labels, log);
  const auto topo = patch_topology(m, labels, n);
  for (uint32_t p = 0; p < n; ++p)
    EXPECT_TRUE(topo[p].is_disk())
        << "patch " << p << ": " << topo[p].boundary_loops << " loops, euler " << topo[p].euler();
  for (uint32_t v = 0; v < m.num_vertices(); ++v) {
    const auto w = wedges_at(m, labels, v);
    for (std::size_t i = 0; i < w.size(); ++i)
      for (std::size_t j = i + 1; j < w.size(); ++j)
        EXPECT_NE(w[i].patch, w[j].patch) << "patch " << w[i].patch << " pinched at vertex " << v;
  }
  return labels;
}

TEST(Disk, SmallHoleGetsAStripToTheOuterLoop) {
  const PreparedComponent c = prepared(test::plate_with_holes(4, 4, {{{1.3, 2.2, 0.03}}}, 0.05), 0);
  ASSERT_EQ(c.mesh.boundary_loops().size(), 2u);
  DiskRepairLog log;
  disk_patches_from_one(c.mesh, log);
  EXPECT_EQ(log.strips_cut, 1u);
  EXPECT_EQ(log.voronoi_splits, 0u);
}

TEST(Disk, SmallHandleGetsARingRoundIt) {
  // A unit sphere with a ring of radius 0.2 and thickness 0.07 across its top: genus 1.
  const auto f = [](const Vec3& p) {
    const Vec3 q = p - Vec3{0, 0, 1};
    const double ring = std::hypot(std::hypot(q.y, q.z) - 0.2, q.x) - 0.09;
    return std::min(norm(p) - 1, ring);
  };
  const PreparedComponent c = prepared(
      test::largest_component(test::marching_tets(f, {-1.3, -1.3, -1.3}, {1.3, 1.3, 1.4}, 0.05)),
      0);
  ASSERT_EQ(c.mesh.euler_characteristic(), 0);
  DiskRepairLog log;
  disk_patches_from_one(c.mesh, log);
  EXPECT_EQ(log.handles_cut, 1u);
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
        for (uint32_t v : rm.face(f))
          lo = std::min(lo, rm.position(v).z), hi = std::max(hi, rm.position(v).z);
    EXPECT_NEAR(hi - lo, c.mesh.bounding_box().hi.z - c.mesh.bounding_box().lo.z, 1e-12);
  }
  expect_valid(c.mesh, r);
}

// A sphere with a handle two triangles long between neighbouring faces, in one patch: every
// Voronoi cell of up to 24 seeds that holds the handle is not a disk, so a ring of faces round
// the handle is cut off, piecewise or not.
TEST(Disk, TinyHandleInOnePatchIsCutAway) {
  PolyMesh m = test::icosphere(4);
  const auto centroid = [&](std::size_t f) {
    const auto v = m.face(f);
    return (m.positions[v[0]] + m.positions[v[1]] + m.positions[v[2]]) / 3.0;
  };
  // The nearest face with no vertex on face 0's vertices' one-rings, so that the tube's edges
  // are new edges.
  std::set<uint32_t> near;
  for (std::size_t g = 0; g < m.num_faces(); ++g)
    for (uint32_t v : m.face(g))
      if (std::ranges::find(m.face(0), v) != m.face(0).end())
        for (uint32_t w : m.face(g)) near.insert(w);
  const auto apart = [&](std::size_t g) {
    return std::ranges::none_of(m.face(g), [&](uint32_t v) { return near.count(v) > 0; });
  };
  std::size_t other = 0;
  for (std::size_t g = 1; g < m.num_faces(); ++g)
    if (apart(g) &&
        (other == 0 || norm(centroid(g) - centroid(0)) < norm(centroid(other) - centroid(0))))
      other = g;
  ASSERT_GT(other, 0u);
  const auto t0 = m.face(0), t1 = m.face(other);
  const uint32_t a = t0[0], b = t0[1], c = t0[2], d = t1[0], e = t1[1], f = t1[2];
  PolyMesh handled;
  handled.positions = m.positions;
  for (std::size_t g = 0; g < m.num_faces(); ++g)
    if (g != 0 && g != other) {
      const auto v = m.face(g);
      handled.add_face({v[0], v[1], v[2]});
    }
  // The tube's three quads, each as two triangles: they hold a->b, b->c, c->a and d->e, e->f,
  // f->d, the halfedges the two removed faces held.
  for (const std::array<uint32_t, 4>& q :
       {std::array<uint32_t, 4>{a, b, d, e}, {b, c, f, d}, {c, a, e, f}}) {
    handled.add_face({q[0], q[1], q[2]});
    handled.add_face({q[0], q[2], q[3]});
  }
  const PreparedComponent comp = prepared(handled);
  ASSERT_EQ(comp.mesh.euler_characteristic(), 0);  // a torus: the handle is a handle
  for (const bool piecewise : {false, true}) {
    SegmentOptions o = with_patches(1);
    o.piecewise_disks = piecewise;
    const SegmentResult r = segment(comp.mesh, comp.feature, o);
    EXPECT_EQ(r.repair.handles_cut, 1u);
    expect_valid(comp.mesh, r);
  }
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
    labels[f] =
        c.mesh.position(t[0]).z + c.mesh.position(t[1]).z + c.mesh.position(t[2]).z > 0 ? 1 : 0;
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
    const double u = (m.x - box.lo.x) / (box.hi.x - box.lo.x),
                 v = (m.y - box.lo.y) / (box.hi.y - box.lo.y);
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

TEST(Meta, Torus2x2IsAMultigraph) {
  // Four quadrant patches on a torus: each pair of neighbours shares two meta-edges.
  const int nu = 32, nv = 16;
  const PreparedComponent c = prepared(test::torus(nu, nv));
  FaceData<uint32_t> labels(c.mesh.num_faces());
  for (uint32_t f = 0; f < c.mesh.num_faces(); ++f) {
    const uint32_t input = c.input_face[f];  // torus faces come in pairs per grid cell (i, j)
    const int i = int(input / 2) / nv, j = int(input / 2) % nv;
    labels[f] = (i < nu / 2 ? 0 : 1) + (j < nv / 2 ? 0 : 2);
  }
  const MetaMesh mm = build_meta_mesh(c.mesh, labels, 4, c.feature);
  EXPECT_EQ(mm.vertices.size(), 4u);
  EXPECT_EQ(mm.edges.size(), 8u);
  EXPECT_EQ(mm.euler(), 0);
  for (const MetaVertex& v : mm.vertices) EXPECT_EQ(v.wedge_patches.size(), 4u);
  std::map<std::pair<uint32_t, uint32_t>, int> between;
  for (const MetaEdge& e : mm.edges) ++between[std::minmax(e.left, e.right)];
  for (const auto& [pair, count] : between) EXPECT_EQ(count, 2) << pair.first << "-" << pair.second;
  EXPECT_NO_THROW(check_meta_mesh(c.mesh, labels, mm));
}

TEST(Refine, SplitEdgesKeepsSurfaceAndProvenance) {
  const PreparedComponent c = prepared(test::icosphere(2));
  RefinedMesh r = identity_refinement(c.mesh);
  // Split one edge, then two edges of one face, then all three of another.
  const uint32_t f = 10, g = 200;
  std::vector<uint32_t> edges = {c.mesh.edge(3 * f),     c.mesh.edge(3 * f + 1),
                                 c.mesh.edge(3 * g),     c.mesh.edge(3 * g + 1),
                                 c.mesh.edge(3 * g + 2), c.mesh.edge(3 * 100)};
  FaceData<uint32_t> labels(c.mesh.num_faces());
  for (uint32_t k = 0; k < c.mesh.num_faces(); ++k) labels[k] = k;
  EdgeData<char> flags(c.mesh.num_edges(), 0);
  flags[edges[0]] = 1;
  r = split_edges(r, edges, &labels, &flags);
  const TriMesh& m = r.mesh;
  EXPECT_EQ(m.num_vertices(), c.mesh.num_vertices() + 6);
  EXPECT_EQ(m.euler_characteristic(), 2);
  EXPECT_EQ(std::count(flags.begin(), flags.end(), 1), 2);  // both halves of the flagged edge
  double area = 0, base_area = 0;
  for (uint32_t k = 0; k < m.num_faces(); ++k) {
    area += m.face_area(k);
    EXPECT_EQ(labels[k], r.base_face[k]);  // labels follow the pieces
    EXPECT_GT(dot(m.face_normal(k), c.mesh.face_normal(r.base_face[k])),
              0.999999);  // orientation kept
  }
  for (uint32_t k = 0; k < c.mesh.num_faces(); ++k) base_area += c.mesh.face_area(k);
  EXPECT_NEAR(area, base_area, 1e-14);
  for (uint32_t v = 0; v < m.num_vertices(); ++v) {
    const SurfacePoint sp = r.vertex_origin(v);
    const Tri& t = c.mesh.face(sp.face);
    const Vec3 p = sp.bary[0] * c.mesh.position(t[0]) + sp.bary[1] * c.mesh.position(t[1]) +
                   sp.bary[2] * c.mesh.position(t[2]);
    EXPECT_LT(norm(p - m.position(v)), 1e-15);
  }
}

// Cuts along chords (the quad split's cuts along straight rays): two points on one edge and
// one on the next, chords from the opposite corner and across the corner between them. Every
// new vertex is where its fraction says, provenance is exact through every face, the chords and
// the edge pieces are edges, the pieces are non-degenerate and keep the orientation, the area
// and chi are kept, and a feature flag passes to all pieces of its edge.
TEST(Refine, CutAlongChords) {
  const PreparedComponent c = prepared(test::icosphere(2));
  const TriMesh& base = c.mesh;
  RefinedMesh r = identity_refinement(base);
  const uint32_t f = 10, nv = base.num_vertices();
  const Tri t = base.face(f);
  const uint32_t e0 = base.edge(3 * f), e1 = base.edge(3 * f + 1);  // v0 -> v1, v1 -> v2
  // Fractions are from the start of the edge's own halfedge.
  auto from_start = [&](uint32_t e, uint32_t v, double s) {
    return base.from(base.edge_halfedge(e)) == v ? s : 1 - s;
  };
  const std::vector<EdgePoint> points = {{e0, from_start(e0, t[0], 0.3)},
                                         {e0, from_start(e0, t[0], 0.6)},
                                         {e1, from_start(e1, t[1], 0.5)}};
  const std::vector<Chord> chords = {{f, t[2], nv}, {f, nv + 1, nv + 2}};
  FaceData<uint32_t> labels(base.num_faces());
  for (uint32_t k = 0; k < base.num_faces(); ++k) labels[k] = k;
  EdgeData<char> flags(base.num_edges(), 0);
  flags[e0] = 1;
  r = cut_along_chords(r, points, chords, &labels, &flags);
  const TriMesh& m = r.mesh;
  ASSERT_EQ(m.num_vertices(), nv + 3);
  EXPECT_EQ(m.euler_characteristic(), 2);
  for (uint32_t i = 0; i < 3; ++i) {
    const uint32_t h = base.edge_halfedge(points[i].edge);
    const double s = points[i].fraction;
    EXPECT_LT(norm(m.position(nv + i) -
                   ((1 - s) * base.position(base.from(h)) + s * base.position(base.to(h)))),
              1e-15);
  }
  double area = 0, base_area = 0;
  for (uint32_t k = 0; k < m.num_faces(); ++k) {
    area += m.face_area(k);
    EXPECT_GT(m.face_area(k), 1e-6 * base.face_area(r.base_face[k]));
    EXPECT_GT(dot(m.face_normal(k), base.face_normal(r.base_face[k])), 0.999999);
    EXPECT_EQ(labels[k], r.base_face[k]);
    const Tri& bt = base.face(r.base_face[k]);
    for (uint32_t i = 0; i < 3; ++i) {
      const auto& b = r.corner_bary[k][i];
      const Vec3 p =
          b[0] * base.position(bt[0]) + b[1] * base.position(bt[1]) + b[2] * base.position(bt[2]);
      EXPECT_LT(norm(p - m.position(m.face(k)[i])), 1e-14) << "face " << k << " corner " << i;
    }
  }
  for (uint32_t k = 0; k < base.num_faces(); ++k) base_area += base.face_area(k);
  EXPECT_NEAR(area, base_area, 1e-13);
  auto joined = [&](uint32_t a, uint32_t b) {
    bool yes = false;
    m.for_each_outgoing(a, [&](uint32_t h) { yes = yes || m.to(h) == b; });
    m.for_each_outgoing(b, [&](uint32_t h) { yes = yes || m.to(h) == a; });
    return yes;
  };
  EXPECT_TRUE(joined(t[2], nv));
  EXPECT_TRUE(joined(nv + 1, nv + 2));
  EXPECT_TRUE(joined(t[0], nv) && joined(nv, nv + 1) && joined(nv + 1, t[1]));
  EXPECT_EQ(std::count(flags.begin(), flags.end(), 1), 3);  // the three pieces of e0
}

namespace {

// The distinct patches around v.
std::set<uint32_t> patches_at(const TriMesh& m, const FaceData<uint32_t>& labels, uint32_t v) {
  std::set<uint32_t> out;
  m.for_each_outgoing(v, [&](uint32_t h) { out.insert(labels[TriMesh::face_of(h)]); });
  return out;
}

// The vertex nearest to p.
uint32_t nearest_vertex(const TriMesh& m, const Vec3& p) {
  uint32_t best = 0;
  for (uint32_t v = 1; v < m.num_vertices(); ++v)
    if (norm(m.position(v) - p) < norm(m.position(best) - p)) best = v;
  return best;
}

}  // namespace

TEST(TipSplit, TipInsideAPatchBecomesAJunctionOfThreeWedges) {
  // The upper hemisphere is one patch and the pole is inside it: it is cut into three wedges
  // that meet at the pole, each reaching the equator, and the lower half is untouched.
  const PreparedComponent c = prepared(test::icosphere(3));
  const TriMesh& m = c.mesh;
  FaceData<uint32_t> labels(m.num_faces());
  for (uint32_t f = 0; f < m.num_faces(); ++f) {
    const Tri& t = m.face(f);
    labels[f] = m.position(t[0]).z + m.position(t[1]).z + m.position(t[2]).z > 0 ? 1 : 0;
  }
  const FaceData<uint32_t> before = labels;
  const uint32_t pole = nearest_vertex(m, {0, 0, 1});
  uint32_t n = 2;
  TipSplitLog log;
  split_patches_at_tips(m, {pole}, labels, n, log);
  EXPECT_EQ(log.tips, 1u);
  EXPECT_EQ(log.split, 1u);
  EXPECT_EQ(n, 4u);
  EXPECT_EQ(patches_at(m, labels, pole), (std::set<uint32_t>{1, 2, 3}));
  const std::vector<PatchTopology> topo = patch_topology(m, labels, n);
  std::set<uint32_t> at_equator;
  for (uint32_t h = 0; h < m.num_halfedges(); ++h)
    if (labels[TriMesh::face_of(m.twin(h))] == 0) at_equator.insert(labels[TriMesh::face_of(h)]);
  for (uint32_t p = 1; p < 4; ++p) {
    EXPECT_TRUE(topo[p].is_disk()) << p;
    EXPECT_TRUE(at_equator.count(p)) << p;
    // About a third of the hemisphere each (the fan's few faces split unevenly).
    EXPECT_GT(3 * topo[p].faces, (topo[1].faces + topo[2].faces + topo[3].faces) / 2) << p;
  }
  for (uint32_t f = 0; f < m.num_faces(); ++f)
    EXPECT_EQ(labels[f] == 0, before[f] == 0) << f;  // the lower half kept, nothing moved into it
  // Through the whole segmentation the pole is then a meta-vertex.
  SegmentOptions o = with_patches(4);
  o.tips = {pole};
  const SegmentResult r = segment(m, c.feature, o);
  EXPECT_EQ(r.tip_split.split, 1u);
  EXPECT_NE(r.meta.vertex_meta_vertex[pole], kInvalid);
  EXPECT_GE(patches_at(r.refined.mesh, r.labels, pole).size(), 3u);
  expect_valid(m, r);
}

TEST(TipSplit, TipOnASeamCutsTheWiderSideInTwo) {
  const PreparedComponent c = prepared(test::icosphere(3));
  const TriMesh& m = c.mesh;
  // Two patches split by a plane off the centre: a vertex on their seam sees the larger patch
  // over more than half its fan.
  const Box3 box = m.bounding_box();
  const double cut = box.lo.x + 0.7 * (box.hi.x - box.lo.x);
  FaceData<uint32_t> labels(m.num_faces());
  for (uint32_t f = 0; f < m.num_faces(); ++f) {
    const Tri& t = m.face(f);
    labels[f] = m.position(t[0]).x + m.position(t[1]).x + m.position(t[2]).x > 3 * cut ? 1 : 0;
  }
  uint32_t seam = kInvalid;
  for (uint32_t v = 0; v < m.num_vertices() && seam == kInvalid; ++v)
    if (patches_at(m, labels, v).size() == 2) seam = v;
  ASSERT_NE(seam, kInvalid);
  const uint32_t w = patch_angle(m, labels, seam, 0) > patch_angle(m, labels, seam, 1) ? 0 : 1;
  const double wide = patch_angle(m, labels, seam, w), narrow = patch_angle(m, labels, seam, 1 - w);
  ASSERT_GT(wide, narrow);
  uint32_t n = 2;
  TipSplitLog log;
  split_patches_at_tips(m, {seam}, labels, n, log);
  EXPECT_EQ(log.split, 1u);
  EXPECT_EQ(n, 3u);
  EXPECT_EQ(patches_at(m, labels, seam), (std::set<uint32_t>{0, 1, 2}));
  // The narrower side is as it was; the wider one gave about half its angle to patch 2.
  EXPECT_NEAR(patch_angle(m, labels, seam, 1 - w), narrow, 1e-12);
  EXPECT_NEAR(patch_angle(m, labels, seam, w) + patch_angle(m, labels, seam, 2), wide, 1e-12);
  EXPECT_LT(patch_angle(m, labels, seam, 2), 0.75 * wide);
  EXPECT_GT(patch_angle(m, labels, seam, 2), 0.25 * wide);
}

TEST(TipSplit, TipOnTheBoundaryIsForcedAMetaVertex) {
  // An open plate in one patch: its corners are the meta-vertices; a tip in the middle of a
  // side is listed, not split, and the segmentation makes it a fifth meta-vertex.
  const PreparedComponent c = prepared(test::grid_plate(12, 8));
  const Box3 box = c.mesh.bounding_box();
  const uint32_t tip = nearest_vertex(c.mesh, {0.5 * (box.lo.x + box.hi.x), box.lo.y, box.lo.z});
  ASSERT_TRUE(c.mesh.is_boundary_vertex(tip));
  SegmentOptions o = with_patches(1);
  o.tips = {tip};
  const SegmentResult r = segment(c.mesh, c.feature, o);
  EXPECT_EQ(r.tip_split.split, 0u);
  EXPECT_EQ(r.tip_split.boundary, std::vector<uint32_t>{tip});
  ASSERT_EQ(r.num_patches, 1u);
  EXPECT_EQ(r.meta.vertices.size(), 5u);
  EXPECT_NE(r.meta.vertex_meta_vertex[tip], kInvalid);
  expect_valid(c.mesh, r);
}

TEST(TipSplit, JunctionIsLeftAlone) {
  const PreparedComponent c = prepared(test::icosphere(3));
  const SegmentResult r = segment(c.mesh, c.feature, with_patches(6));
  const MetaVertex& junction = r.meta.vertices.front();
  FaceData<uint32_t> labels = r.labels;
  uint32_t n = r.num_patches;
  TipSplitLog log;
  split_patches_at_tips(r.refined.mesh, {junction.vertex}, labels, n, log);
  EXPECT_EQ(log.split, 0u);
  EXPECT_EQ(n, r.num_patches);
  EXPECT_TRUE(std::equal(labels.begin(), labels.end(), r.labels.begin()));
}

// The path search that reuses its arrays (one search per seam when straightening) finds what a
// search over fresh arrays finds, call after call: the same vertices and length, here between
// vertices of the elephant, through half of its vertices (the rest blocked) so that some ends
// are not reachable.
TEST(Geodesic, ReusedPathSearchEqualsAFreshOne) {
  const PreparedMesh prep = prepare(read_mesh(test::data_dir() / "elephant.off").mesh);
  const TriMesh& m = prep.components.at(0).mesh;
  const uint32_t nv = m.num_vertices();
  auto allowed = [&](uint32_t v, uint32_t) { return v % 7 != 3; };
  PathScratch scratch;
  uint32_t found = 0, missed = 0;
  for (uint32_t i = 0; i < 60; ++i) {
    const uint32_t a = (i * 7919u) % nv, b = (i * 104729u + 17u) % nv;
    if (a == b || a % 7 == 3) continue;
    const ShortestPaths fresh =
        vertex_dijkstra(m, {a}, allowed, [&](uint32_t v) { return v == b; });
    double length = -1;
    const std::vector<uint32_t> path = vertex_path(m, a, b, allowed, scratch, length);
    EXPECT_EQ(path, fresh.path_to(b)) << a << " -> " << b;
    EXPECT_EQ(length, fresh.distance[b]) << a << " -> " << b;
    (path.empty() ? missed : found) += 1;
  }
  EXPECT_GT(found, 20u);
  // Between searches every slot is back to unreached.
  EXPECT_TRUE(std::all_of(scratch.distance.begin(), scratch.distance.end(),
                          [](double d) { return d == INFINITY; }));
  EXPECT_TRUE(std::all_of(scratch.predecessor.begin(), scratch.predecessor.end(),
                          [](uint32_t p) { return p == kInvalid; }));
  EXPECT_GT(missed, 0u);  // an end blocked off: no path, as without the reuse
}

// The topology of two patches from their faces alone (once per seam while straightening)
// equals the whole mesh's count: every pair of neighbouring patches of the elephant in 30 VSA
// patches, as VSA leaves them (not all disks yet).
TEST(PatchTopology, LocalCountsEqualTheWholeMeshs) {
  const PreparedMesh prep = prepare(read_mesh(test::data_dir() / "elephant.off").mesh);
  const TriMesh& m = prep.components.at(0).mesh;
  VsaOptions o;
  o.patches = 30;
  const FaceData<uint32_t> labels = segment_vsa(m, prep.components[0].feature, o).face_patch;
  const uint32_t n = 1 + *std::max_element(labels.begin(), labels.end());
  const std::vector<PatchTopology> whole = patch_topology(m, labels, n);
  std::vector<std::vector<uint32_t>> faces(n);
  for (uint32_t f = 0; f < m.num_faces(); ++f) faces[labels[f]].push_back(f);
  std::set<std::pair<uint32_t, uint32_t>> pairs;
  for (uint32_t h = 0; h < m.num_halfedges(); ++h) {
    const uint32_t p = labels[TriMesh::face_of(h)], q = labels[TriMesh::face_of(m.twin(h))];
    if (p < q) pairs.insert({p, q});
  }
  ASSERT_GT(pairs.size(), 40u);
  for (const auto& [p, q] : pairs) {
    std::vector<uint32_t> region;
    std::merge(faces[p].begin(), faces[p].end(), faces[q].begin(), faces[q].end(),
               std::back_inserter(region));
    const std::vector<PatchTopology> local = local_patch_topology(m, labels, region, {p, q});
    for (int k = 0; k < 2; ++k) {
      const PatchTopology& w = whole[k ? q : p];
      EXPECT_EQ(local[k].faces, w.faces) << p << " " << q;
      EXPECT_EQ(local[k].vertices, w.vertices) << p << " " << q;
      EXPECT_EQ(local[k].edges, w.edges) << p << " " << q;
      EXPECT_EQ(local[k].boundary_loops, w.boundary_loops) << p << " " << q;
      EXPECT_EQ(local[k].boundary_edges, w.boundary_edges) << p << " " << q;
    }
  }
}
