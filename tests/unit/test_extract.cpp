#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <set>

#include "corpus.hpp"
#include "extract/collapse.hpp"
#include "extract/extract.hpp"
#include "extract/snap.hpp"
#include "extract/surface_walk.hpp"
#include "extract/untangle.hpp"
#include "io/read_mesh.hpp"
#include "isoquad/error.hpp"
#include "isoquad/remesh.hpp"
#include "metrics/aabb_tree.hpp"
#include "metrics/quality.hpp"
#include "pipeline/pipeline.hpp"
#include "pipeline/remesh.hpp"
#include "pipeline/sizing.hpp"
#include "prep/prepare.hpp"
#include "shapes.hpp"

using namespace isoquad;

namespace {

struct Remeshed {
  PreparedMesh prep;
  ComponentRun run;
  PolyMesh quads;
};

Remeshed remesh_shape(const PolyMesh& m, uint32_t k, double quads,
                      WeightKind weights = WeightKind::smvc, bool untangle = true, bool snap = true,
                      bool tip_split = false) {
  Remeshed r{prepare(m), {}, {}};
  PipelineOptions o;
  o.untangle = untangle;
  o.snap = snap;
  o.tip_split = tip_split;  // the stages of one run, unless asked
  o.refine = false;         // the layout's lattice quads (a fold would be cut finer)
  o.smooth = 0;             // as extracted (the smoothing tests smooth them themselves)
  o.param.weights = weights;
  o.patches = k;
  o.quads = quads;
  r.run = run_component(r.prep, 0, o);
  r.quads = merge_quads(r.prep, {r.run});
  return r;
}

PolyMesh component_as_poly(const TriMesh& t) {
  PolyMesh p;
  p.positions = t.positions();
  for (const Tri& f : t.faces()) p.add_face({f[0], f[1], f[2]});
  return p;
}

}  // namespace

TEST(Extract, CubeIsSixRegularGrids) {
  // Mean value weights reproduce the flat faces exactly: every quad a square.
  const Remeshed r = remesh_shape(test::subdivided_cube(8), 6, 6 * 36, WeightKind::mvc);
  ASSERT_EQ(r.run.seg.num_patches, 6u);
  const int64_t n = r.run.layout.charts[0].width;
  EXPECT_EQ(r.quads.num_faces(), std::size_t(6 * n * n));
  EXPECT_EQ(r.quads.num_vertices(), std::size_t(6 * n * n + 2));
  const QualityReport q = measure_quality(r.quads, nullptr);
  EXPECT_TRUE(q.pure_quad);
  EXPECT_GT(q.sj_min, 1 - 1e-9);
  EXPECT_EQ(q.irregular, 8u);  // the cube's corners, valence 3
  EXPECT_EQ(q.valence.at(3), 8u);
}

TEST(Extract, VerifierCatchesAFoldedMapAndFallsBackToTheLockedOne) {
  const Remeshed r = remesh_shape(test::subdivided_cube(8), 6, 6 * 36, WeightKind::mvc);
  ASSERT_EQ(r.run.seg.num_patches, 6u);
  EXPECT_EQ(r.run.extract_report.multiply_covered, 0u);
  EXPECT_EQ(r.run.extract_report.patches_locked, 0u);
  // Drag one vertex of patch 0 four lattice units across its neighbours: its stretched fan now
  // overlaps their faces, and lattice points there are covered twice (the verifier looks only
  // at lattice points, so the drag must reach some).
  const TriMesh& mesh = r.run.seg.refined.mesh;
  const FaceData<uint32_t>& labels = r.run.seg.labels;
  uint32_t victim = kInvalid;
  for (uint32_t v = 0; v < mesh.num_vertices() && victim == kInvalid; ++v) {
    bool inside = !mesh.is_boundary_vertex(v);
    mesh.for_each_outgoing(v, [&](uint32_t h) {
      mesh.for_each_outgoing(mesh.to(h),
                             [&](uint32_t g) { inside = inside && labels[mesh.face_of(g)] == 0; });
    });
    if (inside) victim = v;
  }
  ASSERT_NE(victim, kInvalid);
  Param broken = r.run.param;
  mesh.for_each_outgoing(victim, [&](uint32_t h) {
    const uint32_t f = mesh.face_of(h);
    for (int c = 0; c < 3; ++c)
      if (mesh.face(f)[c] == victim) broken.map.uv[f][c][0] += 4.0;
  });
  ExtractReport report;
  const QuadMesh q = extract_quads(r.run.seg.refined, r.run.surface.mesh, labels, r.run.seg.meta,
                                   r.run.layout, broken, report);
  EXPECT_GT(report.multiply_covered, 0u);
  EXPECT_EQ(report.patches_locked, 1u);
  // The locked map of a cube face is its exact grid: every quad is still a square.
  PolyMesh quads;
  quads.positions = q.positions;
  for (const auto& quad : q.quads) quads.add_face({quad[0], quad[1], quad[2], quad[3]});
  EXPECT_GT(measure_quality(quads, nullptr).sj_min, 1 - 1e-9);
}

TEST(Extract, CountsTopologyAndValencesFollowTheLayout) {
  const std::pair<const char*, PolyMesh> shapes[] = {{"torus", test::torus(48, 20)},
                                                     {"plate_with_hole", test::plate_with_hole(30)},
                                                     {"cylinder", test::open_cylinder(40, 16)},
                                                     {"sphere", test::icosphere(4)}};
  for (const auto& [name, mesh] : shapes) {
    SCOPED_TRACE(name);
    const Remeshed r = remesh_shape(mesh, 0, 600);
    const Layout& l = r.run.layout;
    const MetaMesh& mm = r.run.seg.meta;
    uint64_t nv = mm.vertices.size(), nq = 0;
    for (const Chart& c : l.charts) nv += (c.width - 1) * (c.height - 1), nq += c.width * c.height;
    for (const int64_t x : l.length) nv += x - 1;
    EXPECT_EQ(r.quads.num_vertices(), nv);
    EXPECT_EQ(r.quads.num_faces(), nq);
    const PolyMesh input = component_as_poly(r.prep.components[0].mesh);
    const QualityReport q = measure_quality(r.quads, &input);
    EXPECT_TRUE(q.pure_quad);
    EXPECT_TRUE(q.edge_manifold);
    EXPECT_TRUE(q.vertex_manifold);
    EXPECT_TRUE(q.oriented);
    EXPECT_TRUE(q.same_topology);
    // Interior valences: a_v at the meta-vertices, 4 everywhere else.
    std::map<int, uint32_t> expected;
    uint32_t interior = 0;
    for (uint32_t v = 0; v < mm.vertices.size(); ++v)
      if (!mm.vertices[v].on_boundary) ++expected[l.quarter_turns[v]], ++interior;
    uint32_t total = 0;
    for (const auto& [k, n] : q.valence) total += n;
    expected[4] += total - interior;
    std::erase_if(expected, [](const auto& e) { return e.second == 0; });
    EXPECT_EQ(q.valence, expected);
  }
}

namespace {

// The cube's quads (mvc: every face's map is linear, its lattice exact) with these lattice
// points marked, cut finer `rounds` times (each round marking the same points again, which
// then lie in finer quads).
struct CubeRefined {
  Remeshed r;
  LatticeQuads lattice;
  QuadMesh quads;
  uint32_t cut = 0;
};

CubeRefined refine_cube(const std::vector<uint32_t>& marked, uint32_t rounds = 1) {
  CubeRefined c{remesh_shape(test::subdivided_cube(8), 6, 6 * 36, WeightKind::mvc), {}, {}};
  const ComponentRun& run = c.r.run;
  c.lattice = lattice_quads(run.seg.meta, run.layout);
  for (uint32_t k = 0; k < rounds; ++k) {
    std::vector<char> marks(c.lattice.points.size(), 0);
    for (const uint32_t v : marked) marks[v] = 1;
    c.cut += refine_lattice_quads(c.lattice, run.layout, marks);
  }
  ExtractReport report;
  c.quads = place_quads(run.seg.refined, run.surface.mesh, run.seg.labels, run.seg.meta, run.layout,
                        run.param, c.lattice, report);
  return c;
}

// Valid, of the cube's topology, on the cube, its quads convex (scaled Jacobian above `sj`).
void expect_valid_on_cube(const CubeRefined& c, double sj) {
  const PolyMesh input = component_as_poly(c.r.prep.components[0].mesh);
  const QualityReport q = measure_quality(as_poly(c.quads), &input);
  EXPECT_TRUE(q.pure_quad);
  EXPECT_TRUE(q.edge_manifold);
  EXPECT_TRUE(q.vertex_manifold);
  EXPECT_TRUE(q.oriented);
  EXPECT_TRUE(q.same_topology);
  EXPECT_GT(q.sj_min, sj);
  EXPECT_LT(q.hausdorff, 1e-9);
}

}  // namespace

// One marked point inside a face: its four cells become three quads each (a small quad at the
// point, two around), with a new point a third along each of its four edges and one inside each
// cell. Those inside have valence 3, and the cells' far corners 5.
TEST(LocalRefine, OneMarkedPointCutsItsFourCells) {
  const CubeRefined plain = refine_cube({});
  const uint32_t nv = uint32_t(plain.quads.positions.size()),
                 nf = uint32_t(plain.quads.quads.size());
  EXPECT_EQ(plain.cut, 0u);
  // A point of patch 0 two cells from its border: its cells and their corners are inside.
  const std::array<int64_t, 2> two{2 * LatticeQuads::kScale, 2 * LatticeQuads::kScale};
  ASSERT_GE(plain.r.run.layout.charts[0].width, 5);
  uint32_t inner = kInvalid;
  for (uint32_t v = plain.lattice.meta_vertices; v < plain.lattice.points.size(); ++v)
    if (plain.lattice.points[v].patch == 0 && plain.lattice.points[v].at == two) inner = v;
  ASSERT_NE(inner, kInvalid);
  const CubeRefined c = refine_cube({inner});
  EXPECT_EQ(c.cut, 4u);
  EXPECT_EQ(c.quads.quads.size(), nf + 4 * 2);
  EXPECT_EQ(c.quads.positions.size(), nv + 4 + 4);
  // The templates on a square: the worst corner is 45 or 135 degrees.
  expect_valid_on_cube(c, std::sqrt(0.5) - 1e-9);
  const QualityReport q = measure_quality(as_poly(c.quads), nullptr);
  EXPECT_EQ(q.valence.at(3), 8u + 4u);
  EXPECT_EQ(q.valence.at(5), 4u);
  // The marked point stays where it was; its small quads are a ninth of a cell.
  EXPECT_LT(norm(c.quads.positions[inner] - plain.quads.positions[inner]), 1e-12);
}

// Two opposite corners of a cell marked: the marks are closed (all four), the cell is cut three
// by three, its four side neighbours by the two-corner template (seven quads) and its four
// diagonal neighbours by the one-corner template (three).
TEST(LocalRefine, MarksAreClosedSoEveryCellHasATemplate) {
  const CubeRefined plain = refine_cube({});
  // A cell of patch 0 with no corner on a seam, and its diagonal corners.
  std::array<uint32_t, 4> cell{};
  bool found = false;
  for (std::size_t f = 0; f < plain.lattice.quads.size() && !found; ++f) {
    const auto& q = plain.lattice.quads[f];
    found = std::all_of(q.begin(), q.end(), [&](uint32_t v) {
      return v >= plain.lattice.meta_vertices && plain.lattice.points[v].edge == kInvalid;
    });
    if (found) cell = q;
  }
  ASSERT_TRUE(found);
  const CubeRefined c = refine_cube({cell[0], cell[2]});
  EXPECT_EQ(c.cut, 9u);
  EXPECT_EQ(c.quads.quads.size(), plain.quads.quads.size() - 9 + 9 + 4 * 7 + 4 * 3);
  expect_valid_on_cube(c, std::sqrt(0.5) - 1e-9);
}

// Points on seams and at a meta-vertex: the cells on both sides of a seam agree on its new
// points, which lie on the meta-edge; cut again (a second round in the finer quads), the mesh
// is still conforming, pure quad and on the cube.
TEST(LocalRefine, AcrossSeamsAndAgainInFinerQuads) {
  const CubeRefined plain = refine_cube({});
  // A seam point two cells or more from every cube corner.
  const auto& x = plain.quads.positions;
  double side = 0;  // the cube's edge
  for (uint32_t a = 0; a < plain.lattice.meta_vertices; ++a)
    for (uint32_t b = 0; b < plain.lattice.meta_vertices; ++b)
      side = std::max(side, norm(x[a] - x[b]));
  side /= std::sqrt(3.0);
  const double unit = side / double(plain.r.run.layout.charts[0].width);
  uint32_t seam = kInvalid;
  for (uint32_t v = plain.lattice.meta_vertices;
       v < plain.lattice.points.size() && seam == kInvalid; ++v) {
    if (plain.lattice.points[v].edge == kInvalid) continue;
    bool far = true;
    for (uint32_t m = 0; m < plain.lattice.meta_vertices; ++m)
      far = far && norm(x[v] - x[m]) > 1.5 * unit;
    if (far) seam = v;
  }
  ASSERT_NE(seam, kInvalid);
  const CubeRefined once = refine_cube({seam, 0});
  expect_valid_on_cube(once, 0.5);
  // The cube corner (valence 3): its three cells; the seam point: its four, over two faces.
  EXPECT_EQ(once.cut, 3u + 4u);
  uint32_t on_seams = 0;
  const TriMesh& cube = once.r.run.surface.mesh;
  for (uint32_t v = uint32_t(plain.quads.positions.size()); v < once.quads.positions.size(); ++v) {
    const uint32_t e = once.quads.vertex_meta_edge[v];
    if (e == kInvalid) continue;
    ++on_seams;
    // On the meta-edge's polyline: two of its coordinates are the cube's +-extent.
    const Vec3 x = once.quads.positions[v];
    const Vec3 a = cube.position(once.r.run.seg.meta.edges[e].vertices.front());
    const Vec3 b = cube.position(once.r.run.seg.meta.edges[e].vertices.back());
    EXPECT_LT(norm(cross(b - a, x - a)), 1e-9 * norm(b - a));
  }
  // Two from the corner's three edges, and the seam point's edge a third on each side of it.
  EXPECT_EQ(on_seams, 3u + 2u);
  const CubeRefined twice = refine_cube({seam, 0}, 2);
  EXPECT_GT(twice.cut, once.cut);
  EXPECT_GT(twice.quads.quads.size(), once.quads.quads.size());
  expect_valid_on_cube(twice, 0.2);
}

TEST(Extract, EveryVertexIsOnTheInputSurface) {
  const Remeshed r = remesh_shape(test::torus(48, 20), 0, 600);
  const TriMesh& base = r.prep.components[0].mesh;
  const QuadMesh& qm = r.run.quads;
  ASSERT_EQ(qm.surface.size(), qm.positions.size());
  for (std::size_t v = 0; v < qm.positions.size(); ++v) {
    const SurfacePoint& s = qm.surface[v];
    ASSERT_LT(s.face, base.num_faces());
    double sum = 0;
    for (const double b : s.bary) {
      EXPECT_GE(b, -1e-12);
      sum += b;
    }
    EXPECT_NEAR(sum, 1.0, 1e-12);
    EXPECT_LT(norm(position_of(base, s) - qm.positions[v]), 1e-12);
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

TEST(Remesh, EigenEntryPoint) {
  const PolyMesh s = test::icosphere(3);
  Eigen::MatrixXd V(Eigen::Index(s.num_vertices()), 3);
  Eigen::MatrixXi F(Eigen::Index(s.num_faces()), 3);
  for (std::size_t i = 0; i < s.num_vertices(); ++i)
    V.row(Eigen::Index(i)) << s.positions[i].x, s.positions[i].y, s.positions[i].z;
  for (std::size_t f = 0; f < s.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) F(Eigen::Index(f), k) = int(s.face(f)[k]);
  RemeshOptions o;
  o.quads = 400;
  const RemeshResult r = remesh(V, F, o);
  ASSERT_EQ(r.Q.cols(), 4);
  EXPECT_EQ(r.patch.size(), r.Q.rows());
  EXPECT_GT(r.Q.rows(), 300);
  EXPECT_EQ(r.Q.minCoeff(), 0);
  EXPECT_EQ(r.Q.maxCoeff(), r.V.rows() - 1);
  // Euler characteristic of the quads: V - E + F = 2 with E = 2F for a closed quad mesh.
  EXPECT_EQ(r.V.rows() - r.Q.rows(), 2);
  EXPECT_NE(r.report.find("\"pure_quad\": true"), std::string::npos);
  F(0, 1) = int(V.rows());  // out of range
  try {
    remesh(V, F, o);
    ADD_FAILURE() << "accepted a bad index";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), "E020");
    EXPECT_EQ(e.context().faces, std::vector<uint32_t>{0});
  }
}

// A sphere at coordinate scales 1e-300, 1e150 and 1e300 (where squares of coordinates
// underflow or overflow; remesh crashed in the segmentation from about 1e154): valid quads of the
// sphere's topology, each vertex on the input surface, measured in input units. Scaled by an
// exact power of two (2^1000), the quads are the unit sphere's scaled, to the bit.
TEST(Remesh, ExtremeCoordinateScalesGiveValidQuads) {
  const PolyMesh unit = test::icosphere(3);
  RemeshOptions o;
  o.quads = 300;
  const PolyMesh unit_quads = remesh_polymesh(unit, o).quads;
  for (const double scale : {1e-300, 1e150, 1e300, std::ldexp(1.0, 1000)}) {
    PolyMesh m = unit;
    for (Vec3& p : m.positions) p = scale * p;
    const PolyMesh quads = remesh_polymesh(m, o).quads;
    const QualityReport q = measure_quality(quads, &m);
    EXPECT_TRUE(q.pure_quad) << scale;
    EXPECT_TRUE(q.edge_manifold && q.vertex_manifold && q.oriented) << scale;
    EXPECT_TRUE(q.same_topology) << scale;
    EXPECT_EQ(q.sj_surface_nonpositive, 0u) << scale;
    EXPECT_LT(q.hausdorff, 0.02) << scale;
    EXPECT_GT(quads.num_faces(), 200u) << scale;
    for (const Vec3& p : quads.positions) {
      ASSERT_TRUE(is_finite(p)) << scale;
      EXPECT_NEAR(norm(p / scale), 1.0, 0.02) << scale;  // the icosphere's radius is 1
    }
    if (scale == std::ldexp(1.0, 1000)) {
      ASSERT_EQ(quads.face_vertices, unit_quads.face_vertices);
      for (std::size_t v = 0; v < quads.num_vertices(); ++v)
        EXPECT_EQ(quads.positions[v], ldexp(unit_quads.positions[v], 1000)) << v;
    }
  }
}

// An option out of its range is refused (E003) before any work instead of read as the
// default (quads = -5 ran at the default size); quads = 0 and edge_length = 0 mean "not given".
TEST(Remesh, OptionsOutOfRangeAreRefused) {
  const PolyMesh sphere = test::icosphere(2);
  const auto code_of = [&](const RemeshOptions& o) -> std::string {
    try {
      remesh_polymesh(sphere, o);
    } catch (const Error& e) {
      return e.code();
    }
    return "accepted";
  };
  const std::vector<std::function<void(RemeshOptions&)>> bad{
      [](RemeshOptions& o) { o.quads = -5; }, [](RemeshOptions& o) { o.quads = 0.5; },
      [](RemeshOptions& o) { o.quads = NAN; }, [](RemeshOptions& o) { o.quads = INFINITY; },
      [](RemeshOptions& o) { o.edge_length = -1; }, [](RemeshOptions& o) { o.edge_length = NAN; },
      [](RemeshOptions& o) { o.edge_length = INFINITY; },
      [](RemeshOptions& o) { o.quads = 100, o.edge_length = 0.1; },
      [](RemeshOptions& o) { o.feature_angle_deg = -1; },
      [](RemeshOptions& o) { o.feature_angle_deg = 181; },
      [](RemeshOptions& o) { o.relax = "none"; },
      [](RemeshOptions& o) { o.tolerance = 0.01, o.tolerance_rounds = 0; },
      // VSA's patch count and corner choice mean nothing for the field layout.
      [](RemeshOptions& o) { o.segmentation = "field", o.patches = 12; },
      [](RemeshOptions& o) { o.segmentation = "field", o.local_corners = true; },
      [](RemeshOptions& o) { o.segmentation = "field", o.split_patches = true; }};
  for (std::size_t i = 0; i < bad.size(); ++i) {
    RemeshOptions o;
    bad[i](o);
    EXPECT_EQ(code_of(o), "E003") << "case " << i;
  }
  RemeshOptions fine;
  fine.quads = 100;
  fine.feature_angle_deg = 0;
  EXPECT_EQ(code_of(fine), "accepted");
}

// Three disjoint shapes in one input (a sphere, a torus and an open plate): each component is
// remeshed on its own, with its share of the count by area, and the quads are merged. The
// output has the input's three components, Euler characteristic (2 + 0 + 1) and boundary loop;
// each component's quads lie on that component alone, in one block, with patch ids of their
// own (the next component's count on from the last one's).
TEST(Remesh, ComponentsAreRemeshedApartAndMerged) {
  const std::array<PolyMesh, 3> shapes{test::icosphere(3), test::torus(48, 16),
                                       test::grid_plate(12, 12)};
  const std::array<Vec3, 3> shift{Vec3{0, 0, 0}, Vec3{4, 0, 0}, Vec3{-4, -0.5, 0}};
  PolyMesh input;
  std::array<std::vector<std::array<Vec3, 3>>, 3> tris;
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    const uint32_t base = uint32_t(input.positions.size());
    for (const Vec3& p : shapes[k].positions) input.positions.push_back(p + shift[k]);
    for (std::size_t f = 0; f < shapes[k].num_faces(); ++f) {
      std::vector<uint32_t> vs;
      for (const uint32_t v : shapes[k].face(f)) vs.push_back(base + v);
      input.add_face(vs);
      tris[k].push_back({input.positions[vs[0]], input.positions[vs[1]], input.positions[vs[2]]});
    }
  }
  RemeshOptions o;
  o.quads = 1200;
  const RemeshRun run = remesh_run(input, o);
  ASSERT_EQ(run.runs.size(), 3u);
  const PolyMesh& quads = run.result.quads;
  const QualityReport q = measure_quality(quads, &input);
  EXPECT_TRUE(q.pure_quad);
  EXPECT_TRUE(q.edge_manifold);
  EXPECT_TRUE(q.vertex_manifold);
  EXPECT_TRUE(q.oriented);
  EXPECT_TRUE(q.same_topology);
  EXPECT_EQ(q.topology.components, 3u);
  EXPECT_EQ(q.topology.euler, 3);
  EXPECT_EQ(q.topology.boundary_loops, 1u);
  EXPECT_EQ(q.sj_surface_nonpositive, 0u);
  EXPECT_NEAR(double(quads.num_faces()), 1200.0, 120.0);
  const std::array<AabbTree, 3> trees{AabbTree(tris[0]), AabbTree(tris[1]), AabbTree(tris[2])};
  double shares = 0;
  std::size_t face = 0;
  int32_t patch_base = 0;
  std::array<bool, 3> seen{};
  for (const ComponentRun& r : run.runs) {
    shares += r.area_share;
    // Its share of the count, within the slack the layout and the repairs leave.
    const double asked = 1200.0 * r.area_share;
    EXPECT_NEAR(double(r.quads.quads.size()), asked, 0.25 * asked);
    // Which shape its first vertex lies on; every vertex of its block lies on that one.
    ASSERT_LT(face, quads.num_faces()) << "a component without quads";
    const std::size_t first = quads.face(face)[0];
    std::size_t shape = 0;
    for (std::size_t k = 1; k < 3; ++k)
      if (trees[k].closest(quads.positions[first]).distance <
          trees[shape].closest(quads.positions[first]).distance)
        shape = k;
    EXPECT_FALSE(seen[shape]) << "two components on one shape";
    seen[shape] = true;
    const int32_t charts = int32_t(r.layout.charts.size());
    for (std::size_t i = 0; i < r.quads.quads.size(); ++i, ++face) {
      EXPECT_GE(quads.face_group[face], patch_base);
      EXPECT_LT(quads.face_group[face], patch_base + charts);
      for (const uint32_t v : quads.face(face)) {
        EXPECT_LT(trees[shape].closest(quads.positions[v]).distance, 1e-9);
        for (std::size_t k = 0; k < 3; ++k) {
          if (k != shape) {
            EXPECT_GT(trees[k].closest(quads.positions[v]).distance, 0.5);
          }
        }
      }
    }
    patch_base += charts;
  }
  EXPECT_EQ(face, quads.num_faces());
  EXPECT_NEAR(shares, 1.0, 1e-12);
}

// The default size is one budget for the whole input, shared by area: h is that of one quad per
// 8 triangles of the whole input (1,000 to 20,000), each component is split 1-to-4 until it has
// 8 triangles per quad of that size, and its layout aims at a quad per 8 of those triangles
// within its share of [1,000, 20,000]. 18 small spheres of 80 triangles (1,280 after two
// splits) get about 160 quads each, 2,880 together; each alone would have asked for at least
// 1,000. With a default per component, and the layout's own default on each subdivided
// surface, 1,368 triangles in 18 components asked for 43,745 quads and ran past two minutes.
TEST(Remesh, DefaultSizeIsOneBudgetSharedByTheComponents) {
  const PolyMesh sphere = test::icosphere(1);
  PolyMesh input;
  for (uint32_t k = 0; k < 18; ++k) {
    const uint32_t base = uint32_t(input.positions.size());
    for (const Vec3& p : sphere.positions)
      input.positions.push_back(p + Vec3{3.0 * (k % 6), 3.0 * (k / 6), 0});
    for (std::size_t f = 0; f < sphere.num_faces(); ++f)
      input.add_face(
          {base + sphere.face(f)[0], base + sphere.face(f)[1], base + sphere.face(f)[2]});
  }
  ASSERT_EQ(input.num_faces(), 1440u);
  ASSERT_EQ(default_quad_count(input.num_faces()), 1000.0);  // the count h is taken from
  const double budget = 18 * 80 * 16 / 8.0;                  // 2,880
  const RemeshRun run = remesh_run(input, RemeshOptions{});
  ASSERT_EQ(run.runs.size(), 18u);
  for (const ComponentRun& r : run.runs) {
    EXPECT_NEAR(r.area_share, 1.0 / 18, 1e-9);
    EXPECT_EQ(r.subdivisions, 2u);
    // A quad per 8 triangles of the surface the layout works on (more where the patches' floor
    // asks, layout.hpp kFloorMargin), not the 1,000 of the unshared default.
    EXPECT_GE(r.layout.quads_aim, r.seg.refined.mesh.num_faces() / 8.0);
    EXPECT_LT(r.layout.quads_aim, 2 * budget / 18);
    EXPECT_LT(r.quads.quads.size(), 2 * budget / 18);  // the rounds may double the quads at most
  }
  const QualityReport q = measure_quality(run.result.quads, &input);
  EXPECT_TRUE(q.pure_quad && q.edge_manifold && q.vertex_manifold && q.oriented);
  EXPECT_TRUE(q.same_topology);
  EXPECT_EQ(q.topology.components, 18u);
  EXPECT_GT(run.result.quads.num_faces(), 0.5 * budget);
  EXPECT_LT(run.result.quads.num_faces(), 1.2 * budget);
}

// A component too small for patches is remeshed, not dropped: each triangle split into three
// quads, conforming, of the same topology and orientation. A lone triangle gives 3 quads.
TEST(Remesh, LoneTriangleGivesThreeQuads) {
  PolyMesh tri;
  tri.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  tri.add_face({0, 1, 2});
  const RemeshRun run = remesh_run(tri, RemeshOptions{});
  const PolyMesh& quads = run.result.quads;
  ASSERT_EQ(quads.num_faces(), 3u);
  EXPECT_EQ(quads.num_vertices(), 7u);  // 3 corners, 3 midpoints, the centroid
  const QualityReport q = measure_quality(quads, &tri);
  EXPECT_TRUE(q.pure_quad && q.edge_manifold && q.vertex_manifold && q.oriented);
  EXPECT_TRUE(q.same_topology);
  EXPECT_EQ(q.sj_surface_nonpositive, 0u);
  for (std::size_t f = 0; f < 3; ++f) {  // counter-clockwise, as the triangle (+z)
    const auto v = quads.face(f);
    const Vec3 n = cross(quads.positions[v[1]] - quads.positions[v[0]],
                         quads.positions[v[3]] - quads.positions[v[0]]);
    EXPECT_GT(n.z, 0) << f;
  }
  ASSERT_EQ(run.warnings.size(), 1u);
  EXPECT_EQ(run.warnings[0].code, "W109");
}

namespace {

// Remeshes a small piece at `quads` and checks that its output is valid and of its topology;
// where the layout's quads were not (run_component's alternatives), the warning and the JSON
// say why. Returns that reason (empty: the layout's quads).
std::string remesh_valid_or_mended(const PolyMesh& piece, double quads) {
  RemeshOptions o;
  o.quads = quads;
  const RemeshRun run = remesh_run(piece, o);
  const QualityReport q = measure_quality(run.result.quads, &piece);
  EXPECT_TRUE(q.pure_quad && q.edge_manifold && q.vertex_manifold && q.oriented) << quads;
  EXPECT_TRUE(q.same_topology) << quads;
  EXPECT_EQ(q.sj_invalid, 0u) << quads;
  EXPECT_EQ(q.sj_surface_nonpositive, 0u) << quads;
  EXPECT_EQ(run.runs.size(), 1u);
  if (run.runs.size() != 1) return "";
  const ComponentRun& r = run.runs[0];
  const std::string reason = r.triangle_split ? r.triangle_split_reason : r.four_sided_reason;
  if (reason.empty()) return reason;
  EXPECT_FALSE(run.warnings.empty());
  if (!run.warnings.empty()) {
    EXPECT_EQ(run.warnings.back().code, r.triangle_split ? "W114" : "W115");
  }
  if (r.triangle_split) {
    EXPECT_EQ(run.result.quads.num_faces(), 3 * piece.num_faces());
  }
  const auto report = nlohmann::json::parse(run.result.report);
  EXPECT_EQ(
      report["components"][0][r.triangle_split ? "triangle_split_reason" : "four_sided_reason"],
      reason);
  return reason;
}

}  // namespace

// A small closed piece of CGAL's bones.off (18 vertices, 32 triangles), which that model's
// share of 1,500 quads gave about 8 quads: VSA's two patches came out as 4 quads of Euler
// characteristic 3, and remesh stopped with E603. Every count gives valid quads of the piece's
// topology; where the layout's quads would not be valid (at 6 and 8 quads one folds against the
// surface), the alternatives take over, with the reason.
TEST(Remesh, TooFewQuadsForAComponentStillGiveItsTopology) {
  PolyMesh piece;
  piece.positions = {
      {3.18714, -1.3356, 1.83324},  {3.15548, -1.29781, 1.946},   {3.12972, -1.35805, 2.0506},
      {3.13563, -1.45612, 2.04248}, {3.16733, -1.49395, 1.92961}, {3.19306, -1.43366, 1.82504},
      {3.08065, -1.5508, 1.88887},  {3.12138, -1.4554, 1.72343},  {3.0305, -1.49094, 2.06747},
      {3.02116, -1.33578, 2.08032}, {3.0619, -1.24045, 1.91481},  {3.112, -1.30026, 1.73639},
      {2.99408, -1.43071, 1.69989}, {2.95528, -1.52163, 1.85755}, {2.94576, -1.46155, 2.03902},
      {2.94188, -1.33261, 2.05038}, {2.94244, -1.2448, 1.88138},  {2.99018, -1.30179, 1.71136}};
  for (const std::array<uint32_t, 3>& t : std::vector<std::array<uint32_t, 3>>{
           {2, 3, 4},    {1, 2, 4},    {5, 1, 4},   {0, 1, 5},   {4, 6, 5},    {7, 5, 6},
           {3, 6, 4},    {8, 6, 3},    {2, 8, 3},   {9, 8, 2},   {1, 10, 2},   {9, 2, 10},
           {0, 10, 1},   {11, 10, 0},  {5, 7, 0},   {11, 0, 7},  {12, 16, 17}, {13, 16, 12},
           {14, 16, 13}, {15, 16, 14}, {6, 13, 12}, {7, 6, 12},  {8, 14, 13},  {6, 8, 13},
           {9, 15, 14},  {8, 9, 14},   {16, 15, 9}, {10, 16, 9}, {17, 16, 10}, {11, 17, 10},
           {12, 17, 11}, {7, 12, 11}})
    piece.add_face({t[0], t[1], t[2]});
  // The layout's 4 quads are of Euler characteristic 3; at 6 and 8 one quad folds against the
  // surface on some kernels.
  const std::string reason = remesh_valid_or_mended(piece, 4);
  EXPECT_NE(reason.find("topology"), std::string::npos) << reason;
  for (const double quads : {6.0, 8.0}) remesh_valid_or_mended(piece, quads);
}

// A piece of CGAL's boeing.off (a half-open cylinder of 49 triangles, cut along a seam of
// coincident vertices), which that model's share of 1,500 quads gave one quad, folded against
// the surface and against its own normal. However few quads are asked for, the output is
// valid: VSA's patches split four-sided (W115) or the triangles split in three (W114), with
// the reason.
TEST(Remesh, FoldedQuadsOfAComponentAreNotTheOutput) {
  PolyMesh piece;
  piece.positions = {
      {-6, 1.625, -1.25},          {-6, 0.875, -1.25},          {-6, 1.61222, -1.15294},
      {-6, 1.57476, -1.0625},      {-6, 1.51517, -0.984835},    {-6, 1.4375, -0.92524},
      {-6, 1.34706, -0.887778},    {-6, 1.25, -0.875},          {-6, 1.15294, -0.887778},
      {-6, 1.0625, -0.92524},      {-6, 0.984835, -0.984835},   {-6, 0.92524, -1.0625},
      {-6, 0.887778, -1.15294},    {-5.75, 0.875, -1.25},       {-5.75, 0.875, -1.25},
      {-5.75, 0.886781, -1.15674}, {-5.75, 0.921385, -1.06934}, {-5.75, 0.976637, -0.993295},
      {-5.75, 1.04906, -0.933377}, {-5.75, 1.13412, -0.893354}, {-5.75, 1.22645, -0.87574},
      {-5.75, 1.32027, -0.881642}, {-5.75, 1.40967, -0.91069},  {-5.75, 1.48903, -0.961058},
      {-5.75, 1.55338, -1.02958},  {-5.75, 1.59867, -1.11195},  {-5.75, 1.62204, -1.203},
      {-5.75, 1.62204, -1.297},    {-5.75, 1.59867, -1.38805},  {-5.75, 1.55338, -1.47042},
      {-5.75, 1.48903, -1.53894},  {-5.75, 1.40967, -1.58931},  {-5.75, 1.32027, -1.61836},
      {-5.75, 1.22645, -1.62426},  {-5.75, 1.13412, -1.60665},  {-5.75, 1.04906, -1.56662},
      {-5.75, 0.976637, -1.50671}, {-5.75, 0.921385, -1.43066}, {-5.75, 0.886781, -1.34326},
      {-6, 0.875, -1.25},          {-6, 0.887778, -1.34706},    {-6, 0.92524, -1.4375},
      {-6, 0.984835, -1.51517},    {-6, 1.0625, -1.57476},      {-6, 1.15294, -1.61222},
      {-6, 1.25, -1.625},          {-6, 1.34706, -1.61222},     {-6, 1.4375, -1.57476},
      {-6, 1.51517, -1.51517},     {-6, 1.57476, -1.4375},      {-6, 1.61222, -1.34706}};
  for (const std::array<uint32_t, 3>& t : std::vector<std::array<uint32_t, 3>>{
           {18, 19, 9},  {17, 18, 10}, {11, 16, 17}, {16, 12, 15}, {20, 8, 19},  {6, 21, 22},
           {23, 5, 22},  {3, 24, 25},  {4, 23, 24},  {7, 20, 21},  {26, 2, 25},  {10, 11, 17},
           {18, 9, 10},  {11, 12, 16}, {1, 13, 15},  {1, 15, 12},  {9, 19, 8},   {8, 20, 7},
           {6, 22, 5},   {5, 23, 4},   {3, 4, 24},   {21, 6, 7},   {25, 2, 3},   {26, 0, 2},
           {50, 27, 28}, {49, 28, 29}, {31, 32, 46}, {29, 30, 48}, {47, 30, 31}, {40, 37, 38},
           {39, 38, 14}, {33, 34, 44}, {35, 36, 42}, {34, 35, 43}, {37, 41, 36}, {32, 33, 45},
           {28, 49, 50}, {30, 47, 48}, {29, 48, 49}, {47, 31, 46}, {27, 50, 0},  {37, 40, 41},
           {32, 45, 46}, {45, 33, 44}, {34, 43, 44}, {42, 43, 35}, {41, 42, 36}, {39, 40, 38},
           {27, 0, 26}})
    piece.add_face({t[0], t[1], t[2]});
  uint32_t mended = 0;
  for (const double quads : {1.0, 2.0, 4.0}) {
    const std::string reason = remesh_valid_or_mended(piece, quads);
    if (reason.empty()) continue;
    ++mended;
    EXPECT_NE(reason.find("scaled Jacobian"), std::string::npos) << reason;
  }
  EXPECT_GE(mended, 1u);  // the layout's one quad is folded at 1
}

// A sphere and a tetrahedron (4 faces, dropped before): both components are in the output,
// the tetrahedron as 12 quads, and the whole is valid as every remesh output is; the JSON says
// which component took that path.
TEST(Remesh, SphereAndTetrahedronKeepBothComponents) {
  PolyMesh input = test::icosphere(2);
  const uint32_t n = uint32_t(input.positions.size());
  input.positions.insert(input.positions.end(), {{3, 0, 0}, {4, 0, 0}, {3, 1, 0}, {3, 0, 1}});
  for (const std::array<uint32_t, 3>& t :
       {std::array<uint32_t, 3>{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}})
    input.add_face({n + t[0], n + t[1], n + t[2]});
  RemeshOptions o;
  o.quads = 300;
  const RemeshRun run = remesh_run(input, o);
  ASSERT_EQ(run.runs.size(), 2u);
  EXPECT_FALSE(run.runs[0].triangle_split);
  EXPECT_TRUE(run.runs[1].triangle_split);
  EXPECT_EQ(run.runs[1].quads.quads.size(), 12u);
  EXPECT_EQ(run.runs[0].area_share, 1.0);  // the whole count for the sphere
  const QualityReport q = measure_quality(run.result.quads, &input);
  EXPECT_TRUE(q.pure_quad && q.edge_manifold && q.vertex_manifold && q.oriented);
  EXPECT_TRUE(q.same_topology);
  EXPECT_EQ(q.topology.components, 2u);
  EXPECT_EQ(q.topology.euler, 4);
  EXPECT_EQ(q.sj_surface_nonpositive, 0u);
  const auto report = nlohmann::json::parse(run.result.report);
  EXPECT_EQ(report["components"][1]["triangle_split"], true);
  EXPECT_EQ(report["components"][1]["quads"], 12);
  EXPECT_EQ(report["components"][0]["triangle_split"], false);
  // Patch ids: the sphere's, then one per tetrahedron face.
  std::set<int32_t> tet_patches(run.result.quads.face_group.end() - 12,
                                run.result.quads.face_group.end());
  EXPECT_EQ(tet_patches.size(), 4u);
  EXPECT_EQ(*tet_patches.begin(), int32_t(run.runs[0].layout.charts.size()));
}

TEST(Smooth, KeepsVerticesOnTheSurfaceAndUnfolds) {
  const Remeshed r = remesh_shape(test::torus(48, 20), 0, 600);
  QuadMesh q = r.run.quads;
  const TriMesh& base = r.prep.components[0].mesh;
  auto folded = [](const QuadMesh& m) {
    PolyMesh p;
    p.positions = m.positions;
    for (const auto& f : m.quads) p.add_face({f[0], f[1], f[2], f[3]});
    return measure_quality(p, nullptr);
  };
  const QualityReport before = folded(q);
  SmoothReport report;
  SmoothOptions so;
  so.iterations = 10;
  so.edge_length = r.run.layout.edge_length;
  smooth_quads(q, base, r.run.seg.meta, so, report);
  const QualityReport after = folded(q);
  EXPECT_EQ(report.iterations, 10u);
  EXPECT_GT(report.moves, 0u);
  EXPECT_LE(after.sj_nonpositive, before.sj_nonpositive);
  // What smoothing is for: the worst quad is no worse and the spacing is more even (the mean
  // scaled Jacobian may move either way: averaging positions is not an angle optimizer).
  EXPECT_GE(after.sj_min, before.sj_min);
  EXPECT_LT(after.edge_cv, before.edge_cv);
  // No crease and no boundary: the meta-vertices move too.
  uint32_t meta_moved = 0;
  for (std::size_t v = 0; v < q.positions.size(); ++v) {
    EXPECT_LT(norm(position_of(base, q.surface[v]) - q.positions[v]), 1e-12);
    meta_moved +=
        q.vertex_meta_vertex[v] != kInvalid && !(q.positions[v] == r.run.quads.positions[v]);
  }
  EXPECT_GT(meta_moved, 0u);
}

// With the surface's tree, smoothing judges every quad around a moved vertex by its corners'
// scaled Jacobians against the surface normal as well as against its own normal, quad by quad:
// no quad ends below min(its value before, 0.2) by either measure, so none folds against the
// surface, and the spacing still evens out. fandisk at the default size (6,750 quads, creases):
// guarded by the quads' own normals only, the same ten iterations fold quads against the
// surface.
TEST(Smooth, GuardedByTheSurfaceFoldsNoQuad) {
  const ReadResult in = read_mesh(test::data_dir() / "fandisk.off");
  const Remeshed r = remesh_shape(in.mesh, 0, 0);
  const TriMesh& base = r.prep.components[0].mesh;
  PolyMesh reference;
  reference.positions = base.positions();
  for (const Tri& t : base.faces()) reference.add_face({t[0], t[1], t[2]});
  auto quality = [&](const QuadMesh& m) {
    PolyMesh p;
    p.positions = m.positions;
    for (const auto& f : m.quads) p.add_face({f[0], f[1], f[2], f[3]});
    return measure_quality(p, &reference);
  };
  QuadMesh q = r.run.quads;
  const QualityReport before = quality(q);
  const AabbTree tree(face_triangles(base));
  SmoothReport report;
  SmoothOptions so;
  so.iterations = 10;
  so.edge_length = r.run.layout.edge_length;
  smooth_quads(q, base, r.run.seg.meta, so, report, &tree);
  const QualityReport after = quality(q);
  EXPECT_GT(report.moves, 0u);
  EXPECT_GT(report.rejected, 0u);
  EXPECT_LE(after.sj_surface_nonpositive, before.sj_surface_nonpositive);
  EXPECT_GE(after.sj_surface_min, std::min(before.sj_surface_min, 0.2) - 1e-9);
  EXPECT_GE(after.sj_min, std::min(before.sj_min, 0.2) - 1e-9);
  EXPECT_LT(after.edge_cv, before.edge_cv);
  // Vertices on creases, and the meta-vertices where they end, stay.
  const MetaMesh& meta = r.run.seg.meta;
  std::vector<char> on_crease(meta.vertices.size(), 0);
  for (const MetaEdge& e : meta.edges)
    if (e.feature) on_crease[e.mv0] = on_crease[e.mv1] = 1;
  uint32_t held = 0;
  for (std::size_t v = 0; v < q.positions.size(); ++v) {
    EXPECT_LT(norm(position_of(base, q.surface[v]) - q.positions[v]), 1e-12);
    const uint32_t m = q.vertex_meta_vertex[v], e = q.vertex_meta_edge[v];
    if ((m != kInvalid && on_crease[m]) ||
        (m == kInvalid && e != kInvalid && meta.edges[e].feature)) {
      EXPECT_EQ(q.positions[v], r.run.quads.positions[v]);
      ++held;
    }
  }
  EXPECT_GT(held, 100u);
}

// Smoothing after the tip snapping: the corners the snapping put onto the bumps stay there,
// and no move takes the quads farther from the surface than they were or 0.1 h, so the
// two-sided distance does not grow. Unguarded by distance (`far` infinite), the same sweeps pull
// the quads off the rim (4.3% -> 6.1% of the diagonal when this was written).
TEST(Smooth, ComesNoFartherFromTheSurfaceAndKeepsSnappedCorners) {
  // A flat ellipsoid (its rim's radius of curvature a third of a quad) with bumps.
  PolyMesh bumpy = test::icosphere(4);
  for (std::size_t v = 0; v < bumpy.positions.size(); v += 97)
    bumpy.positions[v] = 1.12 * bumpy.positions[v];
  for (Vec3& x : bumpy.positions) x[2] *= 0.25;
  const Remeshed r = remesh_shape(bumpy, 0, 300);
  const std::vector<uint32_t>& snapped = r.run.snap_report.moved;
  ASSERT_GT(snapped.size(), 0u);
  const TriMesh& base = r.prep.components[0].mesh;
  const PolyMesh reference = component_as_poly(base);
  auto smoothed = [&](double far, const std::vector<uint32_t>& pinned, SmoothReport& report) {
    QuadMesh q = r.run.quads;
    SmoothOptions so;
    so.iterations = 10;
    so.edge_length = r.run.layout.edge_length;
    so.far = far;
    smooth_quads(q, base, r.run.seg.meta, so, report, nullptr, pinned);
    return q;
  };
  SmoothReport pinned, guarded, loose;
  const QuadMesh q = smoothed(0.1, snapped, pinned);
  const QuadMesh unpinned = smoothed(0.1, {}, guarded);
  const QuadMesh unguarded = smoothed(INFINITY, {}, loose);
  EXPECT_GT(pinned.moves, 0u);
  EXPECT_GT(guarded.rejected, loose.rejected);
  for (const uint32_t v : snapped) EXPECT_EQ(q.positions[v], r.run.quads.positions[v]);
  const QualityReport before = measure_quality(as_poly(r.run.quads), &reference);
  Box3 box;
  for (const Vec3& x : reference.positions) box.add(x);
  const double bound =
      std::max(before.hausdorff, 0.1 * r.run.layout.edge_length / norm(box.hi - box.lo));
  for (const QuadMesh* m : {&q, &unpinned}) {
    const QualityReport after = measure_quality(as_poly(*m), &reference);
    EXPECT_LE(after.hausdorff, 1.01 * bound);
    EXPECT_EQ(after.sj_nonpositive, 0u);
    EXPECT_LT(after.edge_cv, before.edge_cv);
  }
  EXPECT_GT(measure_quality(as_poly(unguarded), &reference).hausdorff, 1.2 * before.hausdorff);
}

// In the pipeline, smoothing is the component's last pass: the same quads as without it, the
// corners the tip snapping moved where it put them, the others moved by it on the component's
// surface, and the mesh more even.
TEST(Smooth, IsTheLastPassOfAComponent) {
  PolyMesh bumpy = test::icosphere(4);
  for (std::size_t v = 0; v < bumpy.positions.size(); v += 97)
    bumpy.positions[v] = 1.12 * bumpy.positions[v];
  for (Vec3& x : bumpy.positions) x[2] *= 0.25;
  const PreparedMesh prep = prepare(bumpy);
  PipelineOptions o;
  o.quads = 300;
  EXPECT_EQ(o.smooth, 3u);  // the default
  o.smooth = 0;
  const ComponentRun plain = run_component(prep, 0, o);
  o.smooth = 3;
  const ComponentRun smoothed = run_component(prep, 0, o);
  EXPECT_EQ(plain.smooth_report.iterations, 0u);
  EXPECT_EQ(smoothed.smooth_report.iterations, 3u);
  EXPECT_GT(smoothed.smooth_report.moves, 0u);
  ASSERT_EQ(smoothed.quads.quads, plain.quads.quads);
  ASSERT_GT(plain.snap_report.moved.size(), 0u);
  EXPECT_EQ(smoothed.snap_report.moved, plain.snap_report.moved);
  for (const uint32_t v : plain.snap_report.moved)
    EXPECT_EQ(smoothed.quads.positions[v], plain.quads.positions[v]);
  const TriMesh& mesh = prep.components[0].mesh;
  uint32_t moved = 0;
  for (std::size_t v = 0; v < plain.quads.positions.size(); ++v) {
    EXPECT_LT(norm(position_of(mesh, smoothed.quads.surface[v]) - smoothed.quads.positions[v]),
              1e-12);
    moved += !(smoothed.quads.positions[v] == plain.quads.positions[v]);
  }
  EXPECT_GT(moved, plain.quads.positions.size() / 4);
  const PolyMesh reference = component_as_poly(mesh);
  const QualityReport before = measure_quality(as_poly(plain.quads), &reference);
  const QualityReport after = measure_quality(as_poly(smoothed.quads), &reference);
  EXPECT_EQ(after.sj_invalid, 0u);
  EXPECT_GT(after.sj_mean, before.sj_mean);
  EXPECT_LT(after.edge_cv, before.edge_cv);
}

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

TEST(Pipeline, CoarseComponentsAreSubdividedWithExactProvenance) {
  const PreparedMesh prep = prepare(test::subdivided_cube(2));  // 48 triangles, edges ~0.5
  const PreparedComponent& comp = prep.components[0];
  uint32_t features = 0;
  for (uint32_t e = 0; e < comp.mesh.num_edges(); ++e) features += comp.feature[e] != 0;
  ASSERT_GT(features, 0u);  // the cube's 12 creases
  EdgeData<char> feature;
  uint32_t levels = 0;
  // Quads of edge h: area / h^2 of them; 8 triangles each needs 16 x 48 faces or more.
  const double h = std::sqrt(surface_area(comp.mesh) / 40.0);
  const RefinedMesh r = subdivide_coarse(comp.mesh, comp.feature, h, 8, feature, levels);
  EXPECT_EQ(levels, 2u);  // 48 -> 192 -> 768 faces, at least 8 x 40 = 320
  EXPECT_EQ(r.mesh.num_faces(), 16 * comp.mesh.num_faces());
  // Every vertex is reproduced by its provenance in the component.
  for (uint32_t v = 0; v < r.mesh.num_vertices(); ++v) {
    EXPECT_LT(norm(position_of(comp.mesh, r.vertex_origin(v)) - r.mesh.position(v)), 1e-14);
  }
  // Creases are inherited by both halves, four times as many edges after two levels.
  uint32_t sub_features = 0;
  for (uint32_t e = 0; e < r.mesh.num_edges(); ++e) sub_features += feature[e] != 0;
  EXPECT_EQ(sub_features, 4 * features);
  // Already fine enough: untouched.
  const RefinedMesh same = subdivide_coarse(comp.mesh, comp.feature, 4 * h, 8, feature, levels);
  EXPECT_EQ(levels, 0u);
  EXPECT_EQ(same.mesh.num_faces(), comp.mesh.num_faces());
  // A tiny h asks for millions of faces: levels stop while the surface stays under 250,000
  // (48 x 4^4 = 12,288 ... 48 x 4^6 = 196,608; the next would be 786,432).
  const RefinedMesh capped =
      subdivide_coarse(comp.mesh, comp.feature, h / 1000, 8, feature, levels);
  EXPECT_EQ(levels, 6u);
  EXPECT_EQ(capped.mesh.num_faces(), 4096 * comp.mesh.num_faces());
}

TEST(Pipeline, QuadVerticesOnASubdividedSurfaceAreExpressedInTheInput) {
  const PreparedMesh prep = prepare(test::subdivided_cube(1));  // 12 triangles
  PipelineOptions o;
  o.quads = 600;
  const ComponentRun run = run_component(prep, 0, o);
  EXPECT_GT(run.subdivisions, 0u);
  const TriMesh& base = prep.components[0].mesh;
  ASSERT_EQ(run.quads.surface.size(), run.quads.positions.size());
  for (std::size_t v = 0; v < run.quads.positions.size(); ++v) {
    const SurfacePoint& s = run.quads.surface[v];
    ASSERT_LT(s.face, base.num_faces());
    EXPECT_LT(norm(position_of(base, s) - run.quads.positions[v]), 1e-12);
  }
}
