// The library's remesh around the stages: the Eigen entry point, extreme scales, options out of
// range, components remeshed apart and merged, the default size's budget, components too small
// for patches, the alternatives when quads fold, progress (isoquad::Progress) and the topology
// check on each component's quads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include <array>
#include <functional>
#include <nlohmann/json.hpp>
#include <set>
#include "corpus.hpp"
#include "io/read_mesh.hpp"
#include "isoquad/error.hpp"
#include "isoquad/remesh.hpp"
#include "metrics/aabb_tree.hpp"
#include "metrics/quality.hpp"
#include "pipeline/pipeline.hpp"
#include "pipeline/remesh.hpp"
#include "pipeline/sizing.hpp"
#include "prep/prepare.hpp"
#include "quad_checks.hpp"
#include "remesh_shape.hpp"
#include "shapes.hpp"

namespace {

using namespace isoquad;
using namespace isoquad::test;

// The stage names in the order of their first report, as remesh.hpp documents them.
const std::vector<std::string> kStages = {"prepare", "segment", "layout",  "map",
                                          "extract", "repair",  "quality", "done"};

std::vector<std::string> first_reports(const std::vector<Progress>& calls) {
  std::vector<std::string> stages;
  for (const Progress& p : calls)
    if (std::find(stages.begin(), stages.end(), p.stage) == stages.end()) stages.push_back(p.stage);
  return stages;
}

Topology topology(const PolyMesh& m) {
  return topology_of(m, nullptr, nullptr, nullptr, nullptr, nullptr);
}

// A quad torus: n x n quads around both circles.
PolyMesh quad_torus(uint32_t n) {
  PolyMesh m;
  for (uint32_t i = 0; i < n; ++i)
    for (uint32_t j = 0; j < n; ++j) {
      const double u = 2 * M_PI * i / n, v = 2 * M_PI * j / n;
      m.positions.push_back(
          {(2 + std::cos(v)) * std::cos(u), (2 + std::cos(v)) * std::sin(u), std::sin(v)});
    }
  const auto id = [n](uint32_t i, uint32_t j) { return (i % n) * n + j % n; };
  for (uint32_t i = 0; i < n; ++i)
    for (uint32_t j = 0; j < n; ++j)
      m.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  return m;
}

PolyMesh without_last_face(const PolyMesh& m) {
  PolyMesh out;
  out.positions = m.positions;
  for (std::size_t f = 0; f + 1 < m.num_faces(); ++f) {
    out.add_face(m.face(f));
  }
  return out;
}

PolyMesh twice(const PolyMesh& m) {
  PolyMesh out = m;
  const auto n = uint32_t(m.positions.size());
  for (const Vec3& p : m.positions) out.positions.push_back(p + Vec3{3, 0, 0});
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    std::vector<uint32_t> vs;
    for (const uint32_t v : m.face(f)) vs.push_back(v + n);
    out.add_face(vs);
  }
  return out;
}

}  // namespace

TEST(Remesh, ProgressReportsEveryStageInOrderAndNeverGoesDown) {
  const PolyMesh sphere = read_mesh(test::data_dir() / "sphere.off").mesh;
  for (const std::string segmentation : {"vsa", "field"}) {
    SCOPED_TRACE(segmentation);
    RemeshOptions o;
    o.quads = 300;
    o.segmentation = segmentation;
    std::vector<Progress> calls;
    const std::thread::id caller = std::this_thread::get_id();
    bool on_caller = true;
    remesh_run(sphere, o, false, {}, [&](const Progress& p) {
      on_caller = on_caller && std::this_thread::get_id() == caller;
      calls.push_back(p);
    });
    ASSERT_FALSE(calls.empty());
    EXPECT_TRUE(on_caller);
    EXPECT_EQ(first_reports(calls), kStages);
    for (std::size_t k = 1; k < calls.size(); ++k)
      EXPECT_GE(calls[k].fraction, calls[k - 1].fraction)
          << calls[k - 1].stage << " -> " << calls[k].stage;
    EXPECT_EQ(calls.front().fraction, 0);
    EXPECT_EQ(calls.back().fraction, 1);
    EXPECT_EQ(calls.back().stage, "done");
    // Each stage begun is reported once with no message, then lines said with one.
    EXPECT_TRUE(std::any_of(calls.begin(), calls.end(), [](const Progress& p) {
      return p.message.rfind("component 0: segment", 0) == 0;
    }));
  }
}

TEST(Remesh, ProgressChangesNothingInTheOutput) {
  const PolyMesh sphere = read_mesh(test::data_dir() / "sphere.off").mesh;
  RemeshOptions o;
  o.quads = 300;
  o.quality = false;
  const PolyMesh with = remesh_polymesh(sphere, o, false, {}, [](const Progress&) {}).quads;
  const PolyMesh without = remesh_polymesh(sphere, o).quads;
  EXPECT_EQ(with.positions, without.positions);
  EXPECT_EQ(with.face_group, without.face_group);
  ASSERT_EQ(with.num_faces(), without.num_faces());
  for (std::size_t f = 0; f < with.num_faces(); ++f)
    EXPECT_TRUE(std::equal(with.face(f).begin(), with.face(f).end(), without.face(f).begin()));
}

TEST(Remesh, TopologyChangeSaysWhatChanged) {
  const PolyMesh cube = test::cube_quads();
  const Topology closed = topology(cube), open = topology(without_last_face(cube));
  EXPECT_EQ(topology_change(closed, closed), "");
  EXPECT_EQ(topology_change(open, closed), "boundary loops 1 -> 0");  // a hole closed
  EXPECT_EQ(topology_change(closed, open), "boundary loops 0 -> 1");
  EXPECT_EQ(topology_change(closed, topology(quad_torus(6))), "genus 0 -> 1");
  EXPECT_EQ(topology_change(closed, topology(twice(cube))), "connected pieces 1 -> 2");
  EXPECT_EQ(topology_change(topology(quad_torus(6)), open), "genus 1 -> 0, boundary loops 0 -> 1");
}

TEST(Remesh, TopologyChangeIsAnErrorUnlessAllowed) {
  const PolyMesh cube = test::cube_quads();
  const Topology closed = topology(cube), open = topology(without_last_face(cube));
  EXPECT_FALSE(check_component_topology(2, closed, closed, false));
  EXPECT_FALSE(check_component_topology(2, closed, closed, true));
  try {
    check_component_topology(2, open, closed, false);
    FAIL() << "a hole closed passed";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), "E603");
    EXPECT_EQ(e.kind(), ErrorKind::extraction);
    const std::string what = e.what();
    EXPECT_NE(what.find("component 2:"), std::string::npos) << what;
    EXPECT_NE(what.find("boundary loops 1 -> 0"), std::string::npos) << what;
    EXPECT_NE(what.find("--allow-topology-change"), std::string::npos) << what;
  }
  const auto allowed = check_component_topology(2, open, closed, true);
  ASSERT_TRUE(allowed);
  EXPECT_EQ(allowed->code, "W113");
  EXPECT_EQ(allowed->severity, InputIssue::Severity::warning);
  EXPECT_NE(allowed->message.find("component 2:"), std::string::npos) << allowed->message;
  EXPECT_NE(allowed->message.find("boundary loops 1 -> 0"), std::string::npos);
}

TEST(Remesh, AllowTopologyChangeIsEchoedInTheReport) {
  const PolyMesh sphere = read_mesh(test::data_dir() / "sphere.off").mesh;
  RemeshOptions o;
  o.quads = 300;
  o.quality = false;
  EXPECT_NE(remesh_polymesh(sphere, o).report.find("\"allow_topology_change\": false"),
            std::string::npos);
  o.allow_topology_change = true;
  const std::string report = remesh_polymesh(sphere, o).report;
  EXPECT_NE(report.find("\"allow_topology_change\": true"), std::string::npos);
  EXPECT_EQ(report.find("W113"), std::string::npos);  // the sphere's quads keep its topology
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
  expect_valid_quad_mesh(q);
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
