// Quad extraction from the integer lattice: the cube's grids, the certificate's fallback, counts
// and valences, local refinement, vertices on the input surface and on a subdivided one.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>

#include "extract/extract.hpp"
#include "extract/surface_walk.hpp"
#include "metrics/quality.hpp"
#include "pipeline/pipeline.hpp"
#include "pipeline/sizing.hpp"
#include "prep/prepare.hpp"
#include "quad_checks.hpp"
#include "remesh_shape.hpp"
#include "shapes.hpp"

using namespace isoquad;
using namespace isoquad::test;

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
    expect_valid_quad_mesh(q);
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
  expect_valid_quad_mesh(q);
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
