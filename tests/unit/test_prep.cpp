#include <gtest/gtest.h>
#include <chrono>
#include <cmath>
#include <map>

#include <numbers>
#include <numeric>
#include <set>

#include "corpus.hpp"
#include "io/read_mesh.hpp"
#include "isoquad/error.hpp"
#include "metrics/aabb_tree.hpp"
#include "prep/prepare.hpp"
#include "prep/steps.hpp"
#include "shapes.hpp"

using namespace isoquad;

namespace {

double signed_volume(const TriMesh& m) {
  double v = 0;
  for (const Tri& t : m.faces())
    v += dot(m.position(t[0]), cross(m.position(t[1]), m.position(t[2])));
  return v / 6;
}

PolyMesh triangulated_cube() {
  const PolyMesh q = test::cube_quads();
  PolyMesh t;
  t.positions = q.positions;
  for (std::size_t f = 0; f < q.num_faces(); ++f) {
    const auto v = q.face(f);
    t.add_face({v[0], v[1], v[2]});
    t.add_face({v[0], v[2], v[3]});
  }
  return t;
}

// An 8 x 1 rectangle with 17 vertices on each long side, triangulated the way CAD exports
// triangulate planar faces: two fans of needles, from the top-left and the bottom-right corner.
// Tilted out of every coordinate plane.
PolyMesh needle_plate() {
  PolyMesh m;
  const int n = 16;
  auto place = [](double x, double y) {
    return Vec3{0.8 * x, 0.36 * x + 0.8 * y, 0.48 * x - 0.6 * y};  // orthonormal columns
  };
  for (int i = 0; i <= n; ++i) m.positions.push_back(place(8.0 * i / n, 0));  // bottom: i
  for (int i = 0; i <= n; ++i) m.positions.push_back(place(8.0 * i / n, 1));  // top: n + 1 + i
  const uint32_t top = n + 1;
  for (uint32_t i = 0; i < n; ++i) m.add_face({top, i, i + 1});
  for (uint32_t i = 0; i < n; ++i) m.add_face({n, top + i + 1, top + i});
  return m;
}

double smallest_angle_deg(const TriMesh& m) {
  double least = 180;
  for (const Tri& t : m.faces())
    for (int i = 0; i < 3; ++i) {
      const Vec3 u = m.position(t[(i + 1) % 3]) - m.position(t[i]);
      const Vec3 v = m.position(t[(i + 2) % 3]) - m.position(t[i]);
      least = std::min(least, std::atan2(norm(cross(u, v)), dot(u, v)) * 180 / std::numbers::pi);
    }
  return least;
}

// Every corner angle, ascending, rounded to 1e-9 (a triangle the flips kept may list its corners
// from another one and differ in the last bits).
std::vector<double> sorted_angles(const TriMesh& m) {
  std::vector<double> a;
  for (const Tri& t : m.faces())
    for (int i = 0; i < 3; ++i) {
      const Vec3 u = m.position(t[(i + 1) % 3]) - m.position(t[i]);
      const Vec3 v = m.position(t[(i + 2) % 3]) - m.position(t[i]);
      a.push_back(std::round(1e9 * std::atan2(norm(cross(u, v)), dot(u, v))) * 1e-9);
    }
  std::sort(a.begin(), a.end());
  return a;
}

}  // namespace

TEST(Prepare, NeedleFansOfAFlatFaceAreFlippedAway) {
  const PolyMesh plate = needle_plate();
  const PreparedMesh p = prepare(plate);
  const ComponentReport& r = p.report.components[0];
  const TriMesh& m = p.components[0].mesh;
  EXPECT_LT(r.min_angle_deg, 2.0);  // the input's needles
  EXPECT_GT(r.flat_flips, 0u);
  EXPECT_GT(smallest_angle_deg(m), 10.0);  // no needle left
  std::vector<Tri> again = m.faces();
  EXPECT_EQ(prep::flip_flat_edges(m.positions(), again, prep::kFlatTolerance), 0u);
  // The same vertices, faces and surface: the flips only change which vertices are joined.
  EXPECT_EQ(m.num_vertices(), plate.positions.size());
  EXPECT_EQ(m.num_faces(), plate.num_faces());
  EXPECT_EQ(m.euler_characteristic(), 1);
  EXPECT_NEAR(r.area, 8.0, 1e-12);
  for (uint32_t f = 0; f < m.num_faces(); ++f)
    EXPECT_NEAR(dot(m.face_normal(f), Vec3{-0.6, 0.48, 0.64}), 1.0, 1e-12);  // none turned over
  // The note says what was done.
  const auto note = std::find_if(p.report.issues.begin(), p.report.issues.end(),
                                 [](const InputIssue& i) { return i.code == "W111"; });
  ASSERT_NE(note, p.report.issues.end());
  EXPECT_EQ(note->count, r.flat_flips);

  const PreparedMesh kept = prepare(plate, {.flip_flat = false});
  EXPECT_EQ(kept.report.components[0].flat_flips, 0u);
  EXPECT_LT(smallest_angle_deg(kept.components[0].mesh), 2.0);
}

TEST(Prepare, QuadsBentBeyondTheToleranceAreNotFlipped) {
  // Two triangles across the long diagonal of a thin rhombus: not Delaunay (the angles opposite
  // the diagonal sum to nearly 2 pi). Flat, they flip; with the middle vertices lifted, no.
  for (const double lift : {0.0, 1e-3}) {
    PolyMesh m;
    m.positions = {{0, 0, 0}, {4, 0, 0}, {2, 0.2, lift}, {2, -0.2, lift}};
    m.add_face({0, 1, 2});
    m.add_face({1, 0, 3});
    const PreparedMesh p = prepare(m);
    EXPECT_EQ(p.report.components[0].flat_flips, lift == 0 ? 1u : 0u) << "lift " << lift;
    EXPECT_NEAR(p.report.components[0].area, 0.8, 1e-4);
  }
}

// rotor (a CAD mesh with needle fans on its flat faces): the flips leave no edge that would flip
// again, raise the sorted angles and keep the input's surface (every triangle's centroid on it).
// fandisk, also CAD but without needles, keeps its triangulation.
TEST(Prepare, FlatFlipsOnCadMeshesKeepTheSurface) {
  const auto rotor = read_mesh(test::data_dir() / "rotor.off");
  const PreparedMesh p = prepare(rotor.mesh);
  const PreparedComponent& c = p.components[0];
  EXPECT_GT(p.report.components[0].flat_flips, 100u);
  std::vector<Tri> tris = c.mesh.faces();
  EXPECT_EQ(prep::flip_flat_edges(c.mesh.positions(), tris, prep::kFlatTolerance), 0u);
  const PreparedMesh unflipped = prepare(rotor.mesh, {.flip_flat = false});
  const TriMesh& u = unflipped.components[0].mesh;
  std::vector<std::array<Vec3, 3>> faces;
  for (const Tri& t : u.faces())
    faces.push_back({u.position(t[0]), u.position(t[1]), u.position(t[2])});
  const AabbTree tree(std::move(faces));
  double farthest = 0;
  for (const Tri& t : c.mesh.faces()) {
    const Vec3 centroid =
        (c.mesh.position(t[0]) + c.mesh.position(t[1]) + c.mesh.position(t[2])) / 3.0;
    farthest = std::max(farthest, tree.closest(centroid).distance);
  }
  EXPECT_LT(farthest, 1e-7);
  EXPECT_NEAR(p.report.components[0].area, unflipped.report.components[0].area,
              1e-9 * unflipped.report.components[0].area);
  EXPECT_EQ(c.mesh.euler_characteristic(), u.euler_characteristic());
  // Each Delaunay flip raises the sorted list of angles (Lawson): so do all of them together.
  const std::vector<double> before = sorted_angles(u), after = sorted_angles(c.mesh);
  EXPECT_TRUE(
      std::lexicographical_compare(before.begin(), before.end(), after.begin(), after.end()));

  const auto fandisk = read_mesh(test::data_dir() / "fandisk.off");
  const PreparedMesh f = prepare(fandisk.mesh);
  EXPECT_EQ(f.report.components[0].flat_flips, 0u);
  EXPECT_EQ(f.components[0].mesh.faces(),
            prepare(fandisk.mesh, {.flip_flat = false}).components[0].mesh.faces());
}

TEST(Prepare, NonManifoldEdgeIsRejectedOrDetached) {
  // Three fans of two triangles each around edge 0-1: six faces on one edge.
  PolyMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}};
  for (int k = 0; k < 3; ++k) {
    const double a = 2.1 * k;
    m.positions.push_back({0.5, std::cos(a), std::sin(a)});
  }
  m.add_face({0, 1, 2});
  m.add_face({1, 0, 3});
  m.add_face({0, 1, 4});
  try {
    prepare(m);
    FAIL() << "accepted a non-manifold edge";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), "E101");
    EXPECT_EQ(e.kind(), ErrorKind::invalid_input);
    EXPECT_NE(std::string(e.what()).find("input vertices 0-1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--repair"), std::string::npos);
    EXPECT_EQ(e.context().faces, (std::vector<uint32_t>{0, 1, 2}));
  }
  const PreparedMesh p = prepare(m, {.repair = true});
  EXPECT_EQ(p.report.non_manifold_edges, 1u);
  ASSERT_EQ(p.components.size(), 2u);  // the pair that stays glued, and the detached face
  EXPECT_EQ(p.components[0].mesh.num_faces(), 2u);
  EXPECT_EQ(p.components[0].mesh.euler_characteristic(), 1);
  EXPECT_EQ(p.components[1].mesh.num_faces(), 1u);
  EXPECT_EQ(p.components[1].mesh.euler_characteristic(), 1);
}

TEST(Prepare, BowTieVertexIsSplit) {
  PolyMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  m.add_face({0, 1, 2});
  m.add_face({0, 3, 4});
  const PreparedMesh p = prepare(m);
  EXPECT_EQ(p.report.split_vertices, 1u);
  ASSERT_EQ(p.components.size(), 2u);
  EXPECT_EQ(p.components[0].mesh.num_vertices() + p.components[1].mesh.num_vertices(), 6u);
  EXPECT_EQ(p.components[1].input_vertex[0], 0u);  // both copies remember input vertex 0
}

TEST(Prepare, MobiusStripIsRejectedAsNonOrientable) {
  const PolyMesh m = test::mobius_strip(24);
  try {
    prepare(m);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), "E102");
    EXPECT_EQ(e.kind(), ErrorKind::unsupported_topology);
    EXPECT_EQ(e.context().vertices.size(), 2u);
  }
  const PreparedMesh p = prepare(m, {.diagnose = true});
  EXPECT_TRUE(p.components.empty());
  ASSERT_EQ(p.report.components.size(), 1u);
  const ComponentReport& c = p.report.components[0];
  EXPECT_FALSE(c.orientable);
  EXPECT_EQ(c.euler, 0);
  EXPECT_EQ(c.boundary_loops, 1u);
  EXPECT_EQ(c.genus, 1);  // one crosscap
  EXPECT_TRUE(p.report.has_errors());
}

TEST(Prepare, StlCubeIsWelded) {
  const PolyMesh soup = test::stl_soup(triangulated_cube());
  ASSERT_EQ(soup.num_vertices(), 36u);
  const PreparedMesh p = prepare(soup, {.weld_all = true});
  ASSERT_EQ(p.components.size(), 1u);
  const TriMesh& m = p.components[0].mesh;
  EXPECT_EQ(m.num_vertices(), 8u);
  EXPECT_EQ(m.num_faces(), 12u);
  EXPECT_EQ(m.euler_characteristic(), 2);
  EXPECT_EQ(m.components()[0].genus(), 0);
  EXPECT_EQ(p.report.welded_vertices, 28u);
  // Every edge of the cube is a 90 degree crease; the face diagonals are flat.
  EXPECT_EQ(p.report.components[0].feature_edges, 12u);
  EXPECT_EQ(
      prepare(soup, {.weld_all = true, .feature_angle_deg = 0}).report.components[0].feature_edges,
      0u);
}

TEST(Prepare, CoincidentInteriorVerticesAreNotWelded) {
  // Two spheres touching at one point, each with its own vertex there (like cow.off): welding
  // them would pinch the surface, so they stay apart.
  const PolyMesh s = test::icosphere(1);
  PolyMesh m = s;
  const Vec3 p0 = s.positions[0];
  for (const Vec3& p : s.positions) m.positions.push_back(2.0 * p0 - p);
  const uint32_t n = uint32_t(s.num_vertices());
  for (std::size_t f = 0; f < s.num_faces(); ++f)
    m.add_face({s.face(f)[0] + n, s.face(f)[2] + n, s.face(f)[1] + n});
  const PreparedMesh p = prepare(m);
  EXPECT_EQ(p.report.welded_vertices, 0u);
  ASSERT_EQ(p.components.size(), 2u);
  EXPECT_EQ(p.components[0].mesh.euler_characteristic(), 2);
  EXPECT_EQ(p.components[1].mesh.euler_characteristic(), 2);
}

// Welding coincident boundary vertices that changes the topology is a repair: done with
// --repair only (a mesh with 106 holes had 105 after it, without a word). A plate whose hole
// is filled by a lid with its own vertices: welding closes the hole (3 boundary loops -> 1).
TEST(Prepare, WeldThatClosesAHoleIsDoneOnlyWithRepair) {
  const PolyMesh grid = test::grid_plate(10, 10);
  PolyMesh m;
  m.positions = grid.positions;
  std::map<uint32_t, uint32_t> lid;  // the lid's own copy of each of its vertices
  for (std::size_t f = 0; f < grid.num_faces(); ++f) {
    Vec3 c;
    for (const uint32_t v : grid.face(f)) c += grid.positions[v] / 3.0;
    std::vector<uint32_t> vs(grid.face(f).begin(), grid.face(f).end());
    if (std::fabs(c.x - 0.5) < 0.2 && std::fabs(c.y - 0.5) < 0.2)
      for (uint32_t& v : vs) {
        if (!lid.count(v)) {
          lid[v] = uint32_t(m.positions.size());
          m.positions.push_back(grid.positions[v]);
        }
        v = lid[v];
      }
    m.add_face(vs);
  }
  const auto loops = [](const PreparedMesh& p) {
    uint32_t n = 0;
    for (const ComponentReport& c : p.report.components) n += c.boundary_loops;
    return n;
  };
  const PreparedMesh kept = prepare(m);
  EXPECT_EQ(kept.components.size(), 2u);
  EXPECT_EQ(loops(kept), 3u);
  EXPECT_EQ(kept.report.welded_vertices, 0u);
  ASSERT_FALSE(kept.report.issues.empty());
  EXPECT_EQ(kept.report.issues[0].code, "W112") << kept.report.issues[0].message;
  for (const InputIssue& i : kept.report.issues) EXPECT_NE(i.code, "W104") << i.message;
  const PreparedMesh welded = prepare(m, {.repair = true});
  EXPECT_EQ(welded.components.size(), 1u);
  EXPECT_EQ(loops(welded), 1u);
  EXPECT_GT(welded.report.welded_vertices, 0u);
}

// Two holes touching at a point, the point a vertex of each cell beside it (coincident copies):
// the hole count stays as it came, the copies stay apart, and that is said (W112).
TEST(Prepare, HolesTouchingAtCoincidentVerticesKeepTheirCount) {
  const PolyMesh grid = test::grid_plate(4, 4);
  PolyMesh m;
  m.positions = grid.positions;
  const uint32_t p = 2 * 5 + 2;  // (0.5, 0.5), where the holes touch
  m.positions.push_back(grid.positions[p]);
  const uint32_t copy = uint32_t(m.positions.size() - 1);
  for (std::size_t f = 0; f < grid.num_faces(); ++f) {
    const uint32_t cell = uint32_t(f / 2), i = cell % 4, j = cell / 4;
    if ((i == 1 && j == 1) || (i == 2 && j == 2)) continue;  // the two holes
    std::vector<uint32_t> vs(grid.face(f).begin(), grid.face(f).end());
    if (i == 2 && j == 1)
      for (uint32_t& v : vs)
        if (v == p) v = copy;
    m.add_face(vs);
  }
  const PreparedMesh kept = prepare(m);
  ASSERT_EQ(kept.components.size(), 1u);
  EXPECT_EQ(kept.report.components[0].boundary_loops, 2u);  // the outer one and the holes'
  EXPECT_EQ(kept.report.welded_vertices, 0u);
  EXPECT_EQ(kept.report.split_vertices, 0u);
  ASSERT_EQ(kept.report.issues.size(), 1u);
  EXPECT_EQ(kept.report.issues[0].code, "W112");
}

// --weld-eps 1e-30 is a valid fraction, but coordinates over such a cell size overflowed int64
// (undefined behaviour, UBSan reports it): the cells are clamped, and the weld is that of exact
// duplicates.
TEST(Prepare, TinyWeldDistanceWeldsOnlyCoincidentVertices) {
  PolyMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1e-20, 0}};
  m.add_face({0, 1, 2});
  m.add_face({3, 5, 4});
  uint32_t welded = 0;
  const std::vector<uint32_t> weld = prep::weld_map(m, false, 1e-30, welded);
  EXPECT_EQ(welded, 2u);
  EXPECT_EQ(weld[3], weld[1]);
  EXPECT_EQ(weld[4], weld[2]);
  EXPECT_NE(weld[5], weld[1]);
}

// A polygon that winds twice, the second turn a hair inside the first: every corner of the
// first turn holds its twin, so the first ear is far down the list after every clip. Testing
// every corner again after each clip made that cubic (a 12 KB OFF file with a 400-gon took 6 s
// in the fuzz build; this 4000-gon 21 s in release; the fuzz step's timeout catches a return of
// it, not this test, since times are for benchmarks). It is cut into n - 2 triangles, each of
// three distinct corners of the polygon.
TEST(Prepare, PolygonWithLateEarsIsTriangulated) {
  const uint32_t k = 2000;
  PolyMesh m;
  std::vector<uint32_t> polygon;
  for (const double r : {1.0, 1 - 1e-5})
    for (uint32_t i = 0; i < k; ++i) {
      const double a = 2 * std::numbers::pi * i / k;
      polygon.push_back(uint32_t(m.positions.size()));
      m.positions.push_back({r * std::cos(a), r * std::sin(a), 0});
    }
  m.add_face(polygon);
  std::vector<uint32_t> no_weld(m.num_vertices());
  std::iota(no_weld.begin(), no_weld.end(), 0u);
  InputReport report;
  const prep::Soup s = prep::triangulate(m, no_weld, report);
  EXPECT_EQ(s.tris.size(), 2 * k - 2);
  for (const auto& t : s.tris) {
    EXPECT_TRUE(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
    for (const auto v : t) EXPECT_LT(v, 2 * k);
  }
}

TEST(Prepare, OrientationIsMadeConsistentAndOutward) {
  PolyMesh m = test::icosphere(2);
  PolyMesh flipped;
  flipped.positions = m.positions;
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    const auto v = m.face(f);
    if (f % 10 < 3)
      flipped.add_face({v[0], v[2], v[1]});  // 30% of the faces
    else
      flipped.add_face({v[0], v[1], v[2]});
  }
  const PreparedMesh p = prepare(flipped);
  EXPECT_EQ(p.report.flipped_faces, 96u);
  EXPECT_GT(signed_volume(p.components[0].mesh), 0);

  PolyMesh inside_out;
  inside_out.positions = m.positions;
  for (std::size_t f = 0; f < m.num_faces(); ++f)
    inside_out.add_face({m.face(f)[0], m.face(f)[2], m.face(f)[1]});
  const PreparedMesh q = prepare(inside_out);
  EXPECT_EQ(q.report.flipped_faces, 320u);
  EXPECT_GT(signed_volume(q.components[0].mesh), 0);
}

TEST(Prepare, OpenSurfaceKeepsTheMajorityOrientation) {
  PolyMesh m = test::grid_plate(4, 4);
  std::swap(m.face_vertices[1], m.face_vertices[2]);  // flip face 0
  const PreparedMesh p = prepare(m);
  EXPECT_EQ(p.report.flipped_faces, 1u);
  EXPECT_GT(p.components[0].mesh.face_normal(5).z, 0);
}

TEST(Prepare, DegenerateAndDuplicateFacesAreDroppedWithACount) {
  PolyMesh soup = test::stl_soup(triangulated_cube());
  soup.positions.push_back(soup.positions[0]);  // a facet whose corners collapse when welded
  soup.positions.push_back(soup.positions[0]);
  soup.positions.push_back(soup.positions[1]);
  soup.add_face({36, 37, 38});
  for (uint32_t k = 0; k < 3; ++k)
    soup.positions.push_back(soup.positions[k]);  // a duplicate of facet 0
  soup.add_face({39, 40, 41});
  const PreparedMesh p = prepare(soup, {.weld_all = true});
  EXPECT_EQ(p.report.degenerate_faces, 1u);
  EXPECT_EQ(p.report.duplicate_faces, 1u);
  EXPECT_EQ(p.components[0].mesh.num_faces(), 12u);
  EXPECT_EQ(p.components[0].mesh.euler_characteristic(), 2);
}

TEST(Prepare, PolygonsAreTriangulatedWithoutLosingArea) {
  PolyMesh l;  // an L-shaped (non-convex) hexagon
  l.positions = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
  l.add_face({0, 1, 2, 3, 4, 5});
  const PreparedMesh p = prepare(l);
  const TriMesh& m = p.components[0].mesh;
  EXPECT_EQ(m.num_faces(), 4u);
  EXPECT_NEAR(p.report.components[0].area, 3.0, 1e-12);
  for (uint32_t f = 0; f < m.num_faces(); ++f) EXPECT_GT(m.face_normal(f).z, 0.99);
  EXPECT_EQ(m.boundary_loops()[0].size(), 6u);
}

// Small components are kept (the pipeline splits their triangles into quads); they were dropped
// under 10 faces, and a lone triangle was E103.
TEST(Prepare, TinyComponentsAreKept) {
  PolyMesh m = test::icosphere(1);
  const uint32_t n = uint32_t(m.positions.size());
  m.positions.insert(m.positions.end(), {{5, 0, 0}, {6, 0, 0}, {5, 1, 0}});
  m.add_face({n, n + 1, n + 2});
  const PreparedMesh p = prepare(m);
  ASSERT_EQ(p.components.size(), 2u);
  EXPECT_TRUE(p.report.components[1].kept);
  EXPECT_EQ(p.components[1].mesh.num_faces(), 1u);
  EXPECT_TRUE(p.report.issues.empty());
  PolyMesh single;
  single.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  single.add_face({0, 1, 2});
  EXPECT_EQ(prepare(single).components.size(), 1u);
}

// A component without area for its size has no surface for quads: collinear faces beside a
// sphere (remesh crashed, SIGSEGV), or a sphere with one vertex at 1e100 (CLP aborted) or 1e20
// (E501 after the layout), which `info` accepted. Rejected as E103, naming the component and
// the vertex farthest from its centroid; listed when diagnosing. A vertex at 1e3 leaves area.
TEST(Prepare, ComponentWithoutAreaIsRejected) {
  PolyMesh m = test::icosphere(2);
  const uint32_t n = uint32_t(m.positions.size());
  for (uint32_t i = 0; i < 15; ++i) m.positions.push_back({5.0 + i, 0, 0});
  for (uint32_t i = 0; i < 13; ++i) m.add_face({n + i, n + i + 1, n + i + 2});
  try {
    prepare(m);
    FAIL() << "accepted a component without area";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), "E103");
    EXPECT_NE(std::string(e.what()).find("component 1 has no area"), std::string::npos) << e.what();
    ASSERT_EQ(e.context().vertices.size(), 1u);
    const uint32_t end = e.context().vertices[0];
    EXPECT_TRUE(end == n || end == n + 14) << end;  // an end of the line
  }
  const PreparedMesh listed = prepare(m, {.diagnose = true});
  EXPECT_EQ(listed.components.size(), 1u);  // the sphere
  EXPECT_FALSE(listed.report.components.at(1).kept);
  ASSERT_TRUE(listed.report.has_errors());
  for (const double far : {1e20, 1e100}) {
    PolyMesh spike = test::icosphere(2);
    spike.positions[7] = {far, 0, 0};
    try {
      prepare(spike);
      FAIL() << "accepted a sphere with a vertex at " << far;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), "E103") << far;
      EXPECT_NE(std::string(e.what()).find("input vertex 7 at ("), std::string::npos) << e.what();
      EXPECT_EQ(e.context().vertices, (std::vector<uint32_t>{7}));
    }
  }
  PolyMesh near = test::icosphere(2);
  near.positions[7] = {1e3, 0, 0};
  EXPECT_EQ(prepare(near).components.size(), 1u);
}

TEST(Prepare, NormalizationRoundTrip) {
  PolyMesh m = test::torus(16, 8);
  for (Vec3& p : m.positions) p = 1e6 * p + Vec3{3e6, -2e5, 7};
  const PreparedMesh prep = prepare(m);
  const TriMesh& t = prep.components[0].mesh;
  EXPECT_NEAR(t.bounding_box().diagonal(), 1.0, 1e-15);
  EXPECT_NEAR(norm(t.bounding_box().center()), 0.0, 1e-15);
  for (uint32_t v = 0; v < t.num_vertices(); ++v) {
    const Vec3 orig = m.positions[prep.components[0].input_vertex[v]];
    EXPECT_LE(norm(prep.normalization.invert(t.position(v)) - orig), 1e-15 * norm(orig));
  }
}

// Squares of coordinates overflow from about 1e154 and underflow below 1e-154 (the diagonal
// was inf at 1e154, and the segmentation crashed on the NaN positions that followed). A mesh
// scaled by a power of two, here to about 1e-301, 3e150 and 1e301, normalizes to the very
// bits of the unit-scale mesh, and its report is in its own units.
TEST(Prepare, CoordinatesOfAnyFiniteMagnitudeNormalizeAlike) {
  const PolyMesh unit = test::icosphere(2);
  const PreparedMesh ref = prepare(unit);
  for (const int k : {-1000, 500, 1000}) {
    PolyMesh m = unit;
    for (Vec3& p : m.positions) p = ldexp(p, k);
    const PreparedMesh prep = prepare(m);
    ASSERT_EQ(prep.components.size(), 1u) << k;
    EXPECT_EQ(prep.components[0].mesh.positions(), ref.components[0].mesh.positions()) << k;
    EXPECT_EQ(prep.report.bounding_box.diagonal(),
              std::ldexp(ref.report.bounding_box.diagonal(), k))
        << k;
    EXPECT_EQ(prep.normalization.scale, std::ldexp(ref.normalization.scale, -k)) << k;
    // And back, as the unit-scale mesh comes back, scaled.
    const TriMesh& t = prep.components[0].mesh;
    for (uint32_t v = 0; v < t.num_vertices(); ++v)
      EXPECT_EQ(prep.normalization.invert(t.position(v)),
                ldexp(ref.normalization.invert(t.position(v)), k))
          << k << " vertex " << v;
  }
  // A decimal scale (not a power of two) at the top of the range: a unit diagonal as well.
  PolyMesh huge = unit;
  for (Vec3& p : huge.positions) p = 1e300 * p;
  const PreparedMesh prep = prepare(huge);
  EXPECT_NEAR(prep.components[0].mesh.bounding_box().diagonal(), 1.0, 1e-15);
  EXPECT_TRUE(std::isfinite(prep.report.bounding_box.diagonal()));
}

// A NaN or infinite coordinate (which a library caller can pass; the readers reject it) is
// E013 naming the vertex, whether prepare throws or diagnoses.
TEST(Prepare, NonFiniteCoordinateIsE013NamingTheVertex) {
  for (const double bad : {NAN, INFINITY, -INFINITY}) {
    PolyMesh m = test::icosphere(1);
    m.positions[5].y = bad;
    try {
      prepare(m);
      ADD_FAILURE() << "accepted " << bad;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), "E013");
      EXPECT_EQ(e.context().vertices, std::vector<uint32_t>{5});
      EXPECT_NE(std::string(e.what()).find("vertex 5"), std::string::npos) << e.what();
    }
    PrepOptions diagnose;
    diagnose.diagnose = true;
    const PreparedMesh p = prepare(m, diagnose);
    EXPECT_TRUE(p.report.has_errors());
    ASSERT_EQ(p.report.issues.size(), 1u);
    EXPECT_EQ(p.report.issues[0].code, "E013");
    EXPECT_TRUE(p.components.empty());
  }
}

namespace {
uint32_t zero_area_triangles(const TriMesh& m) {
  uint32_t n = 0;
  for (const Tri& t : m.faces())
    n += 0.5 *
             norm(cross(m.position(t[1]) - m.position(t[0]), m.position(t[2]) - m.position(t[0]))) <
         prep::kZeroArea;
  return n;
}
uint32_t issue_count(const InputReport& r, const std::string& code) {
  uint32_t n = 0;
  for (const InputIssue& i : r.issues)
    if (i.code == code) n += i.count;
  return n;
}
}  // namespace

// Zero-area triangles left the map's system singular (E551: a sphere with a vertex moved onto
// its neighbour). They are repaired before anything else, keeping the topology: a needle's short
// edge collapses (two triangles and a vertex fewer), a cap's long edge flips (the same counts),
// a cap on the boundary goes (its vertex joins the boundary). Each is a W116 repair.
TEST(Prepare, ZeroAreaTrianglesAreRepairedKeepingTheTopology) {
  const PolyMesh sphere = test::icosphere(3);
  const uint32_t v0 = sphere.num_vertices(), f0 = uint32_t(sphere.num_faces());
  {
    PolyMesh m = sphere;  // a vertex on its neighbour
    const auto f = m.face(7);
    m.positions[f[0]] = m.positions[f[1]];
    const PreparedMesh p = prepare(m);
    ASSERT_EQ(p.components.size(), 1u);
    const TriMesh& mesh = p.components[0].mesh;
    EXPECT_EQ(p.report.components[0].zero_area_collapsed, 1u);
    EXPECT_EQ(issue_count(p.report, "W116"), 1u);
    EXPECT_EQ(mesh.num_vertices(), v0 - 1);
    EXPECT_EQ(mesh.num_faces(), f0 - 2);
    EXPECT_EQ(mesh.euler_characteristic(), 2);
    EXPECT_EQ(zero_area_triangles(mesh), 0u);
    EXPECT_EQ(p.components[0].input_vertex.size(), mesh.num_vertices());
    EXPECT_EQ(p.components[0].input_face.size(), mesh.num_faces());
  }
  {
    PolyMesh m = sphere;  // a vertex on the middle of its opposite edge
    const auto f = m.face(7);
    m.positions[f[2]] = 0.5 * (m.positions[f[0]] + m.positions[f[1]]);
    const PreparedMesh p = prepare(m);
    const TriMesh& mesh = p.components.at(0).mesh;
    EXPECT_EQ(p.report.components[0].zero_area_flipped, 1u);
    EXPECT_EQ(issue_count(p.report, "W116"), 1u);
    EXPECT_EQ(mesh.num_vertices(), v0);
    EXPECT_EQ(mesh.num_faces(), f0);
    EXPECT_EQ(mesh.euler_characteristic(), 2);
    EXPECT_EQ(zero_area_triangles(mesh), 0u);
  }
  {
    // A plate: an interior vertex moved onto the middle of a boundary edge of its triangle.
    PolyMesh m = test::grid_plate(6, 6);
    std::set<std::pair<uint32_t, uint32_t>> directed;
    for (std::size_t f = 0; f < m.num_faces(); ++f)
      for (int k = 0; k < 3; ++k) directed.insert({m.face(f)[k], m.face(f)[(k + 1) % 3]});
    std::vector<char> on_boundary(m.num_vertices(), 0);
    for (const auto& [a, b] : directed)
      if (!directed.count({b, a})) on_boundary[a] = on_boundary[b] = 1;
    bool moved = false;
    for (std::size_t f = 0; f < m.num_faces() && !moved; ++f)
      for (int k = 0; k < 3 && !moved; ++k) {
        const uint32_t a = m.face(f)[k], b = m.face(f)[(k + 1) % 3], c = m.face(f)[(k + 2) % 3];
        if (!directed.count({b, a}) && !on_boundary[c]) {
          m.positions[c] = 0.5 * (m.positions[a] + m.positions[b]);
          moved = true;
        }
      }
    ASSERT_TRUE(moved);
    const PreparedMesh p = prepare(m);
    const TriMesh& mesh = p.components.at(0).mesh;
    EXPECT_EQ(p.report.components[0].zero_area_dropped, 1u);
    EXPECT_EQ(mesh.num_faces(), m.num_faces() - 1);
    EXPECT_EQ(mesh.euler_characteristic(), 1);
    EXPECT_EQ(mesh.boundary_loops().size(), 1u);
    EXPECT_EQ(zero_area_triangles(mesh), 0u);
  }
}
