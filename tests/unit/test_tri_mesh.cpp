#include <gtest/gtest.h>

#include <algorithm>
#include <tuple>

#include "core/edge_groups.hpp"
#include "core/tri_mesh.hpp"
#include "isoquad/error.hpp"
#include "shapes.hpp"

using namespace isoquad;

namespace {

TriMesh to_tri_mesh(const PolyMesh& m) {
  std::vector<Tri> faces;
  for (std::size_t f = 0; f < m.num_faces(); ++f)
    faces.push_back({m.face(f)[0], m.face(f)[1], m.face(f)[2]});
  return TriMesh(m.positions, faces);
}

void expect_consistent_connectivity(const TriMesh& m) {
  for (uint32_t h = 0; h < m.num_halfedges(); ++h) {
    const uint32_t t = m.twin(h);
    if (t == kInvalid) continue;
    EXPECT_EQ(m.twin(t), h);
    EXPECT_EQ(m.from(t), m.to(h));
    EXPECT_EQ(m.edge(t), m.edge(h));
  }
  uint32_t sum_valence = 0;
  for (uint32_t v = 0; v < m.num_vertices(); ++v) {
    uint32_t fan = 0;
    m.for_each_outgoing(v, [&](uint32_t h) {
      EXPECT_EQ(m.from(h), v);
      ++fan;
    });
    EXPECT_EQ(m.valence(v), fan + (m.is_boundary_vertex(v) ? 1 : 0));
    sum_valence += m.valence(v);
  }
  EXPECT_EQ(sum_valence, 2 * m.num_edges());  // handshake lemma
}

}  // namespace

TEST(TriMesh, IcosphereTopology) {
  const TriMesh m = to_tri_mesh(test::icosphere(2));
  EXPECT_EQ(m.num_vertices(), 162u);
  EXPECT_EQ(m.num_faces(), 320u);
  EXPECT_EQ(m.num_edges(), 480u);
  EXPECT_EQ(m.euler_characteristic(), 2);
  ASSERT_EQ(m.num_components(), 1u);
  EXPECT_EQ(m.components()[0].genus(), 0);
  EXPECT_TRUE(m.boundary_loops().empty());
  expect_consistent_connectivity(m);
}

TEST(TriMesh, TorusHasGenusOne) {
  const TriMesh m = to_tri_mesh(test::torus(24, 12));
  EXPECT_EQ(m.euler_characteristic(), 0);
  EXPECT_EQ(m.components()[0].genus(), 1);
  expect_consistent_connectivity(m);
}

TEST(TriMesh, PlateBoundaryLoop) {
  const TriMesh m = to_tri_mesh(test::grid_plate(5, 3));
  ASSERT_EQ(m.boundary_loops().size(), 1u);
  EXPECT_EQ(m.boundary_loops()[0].size(), 2u * (5 + 3));
  for (uint32_t h : m.boundary_loops()[0]) {
    EXPECT_TRUE(m.is_boundary_halfedge(h));
    EXPECT_TRUE(m.is_boundary_vertex(m.from(h)));
  }
  EXPECT_EQ(m.components()[0].euler(), 1);
  EXPECT_EQ(m.components()[0].genus(), 0);
  expect_consistent_connectivity(m);
}

TEST(TriMesh, WithPositionsKeepsTheConnectivity) {
  const TriMesh m = to_tri_mesh(test::grid_plate(5, 3));
  std::vector<Vec3> moved = m.positions();
  for (Vec3& p : moved) p = 2.0 * p + Vec3{0, 0, p.x * p.y};
  const TriMesh w = m.with_positions(moved);
  EXPECT_EQ(w.positions(), moved);
  EXPECT_EQ(w.faces(), m.faces());
  const TriMesh rebuilt(moved, m.faces());
  for (uint32_t h = 0; h < m.num_halfedges(); ++h) {
    EXPECT_EQ(w.twin(h), rebuilt.twin(h));
    EXPECT_EQ(w.edge(h), rebuilt.edge(h));
  }
  EXPECT_EQ(w.boundary_loops(), rebuilt.boundary_loops());
  expect_consistent_connectivity(w);
  moved.pop_back();
  EXPECT_THROW((void)m.with_positions(moved), Error);
}

TEST(TriMesh, CylinderHasTwoLoopsAndComponentsAreSeparate) {
  PolyMesh two = test::open_cylinder(16, 4);
  const PolyMesh sphere = test::icosphere(1);
  const uint32_t base = uint32_t(two.positions.size());
  for (const Vec3& p : sphere.positions) two.positions.push_back(p + Vec3{5, 0, 0});
  for (std::size_t f = 0; f < sphere.num_faces(); ++f)
    two.add_face({sphere.face(f)[0] + base, sphere.face(f)[1] + base, sphere.face(f)[2] + base});
  const TriMesh m = to_tri_mesh(two);
  ASSERT_EQ(m.num_components(), 2u);
  EXPECT_EQ(m.components()[0].boundary_loops, 2u);
  EXPECT_EQ(m.components()[0].euler(), 0);
  EXPECT_EQ(m.components()[1].euler(), 2);
  EXPECT_EQ(m.component_of_vertex(base), 1u);
}

TEST(TriMesh, RejectsViolatedPreconditions) {
  const std::vector<Vec3> P = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  auto code = [&](std::vector<Tri> faces) {
    try {
      TriMesh(P, faces);
    } catch (const Error& e) {
      return e.code();
    }
    return std::string("accepted");
  };
  EXPECT_EQ(code({{0, 1, 2}, {1, 0, 3}, {0, 1, 4}, {2, 3, 4}}), "E100");  // edge with 3 faces
  EXPECT_EQ(code({{0, 1, 2}, {0, 1, 3}, {2, 3, 4}}), "E100");  // inconsistent orientation
  EXPECT_EQ(code({{0, 1, 1}}), "E100");                        // repeated vertex
  EXPECT_EQ(code({{0, 1, 2}}), "E100");                        // vertices 3, 4 unused
  EXPECT_EQ(code({{0, 1, 2}, {0, 3, 4}}), "E100");             // bow tie at vertex 0
}

TEST(EdgeGroups, HalfedgesSortedByEdgeThenHalfedge) {
  // A fan of 40 triangles around vertex 0 (its bucket is sorted the long way), a strip, and a
  // triangle repeated (three halfedges on one edge): the order must be (lo, hi, h) exactly.
  std::vector<std::array<uint32_t, 3>> tris;
  for (uint32_t i = 1; i <= 40; ++i) tris.push_back({0, 40 - i + 1, (40 - i + 1) % 40 + 1});
  for (uint32_t i = 50; i < 60; ++i) tris.push_back({i, i + 1, i + 2});
  tris.push_back({70, 71, 72});
  tris.push_back({72, 71, 70});
  tris.push_back({70, 71, 73});
  const std::vector<EdgeHalfedge> keys = halfedges_by_edge(tris);
  ASSERT_EQ(keys.size(), 3 * tris.size());
  std::vector<std::tuple<uint32_t, uint32_t, uint32_t>> expected;
  for (uint32_t h = 0; h < 3 * tris.size(); ++h) {
    const uint32_t a = tris[h / 3][h % 3], b = tris[h / 3][(h % 3 + 1) % 3];
    expected.push_back({std::min(a, b), std::max(a, b), h});
  }
  std::sort(expected.begin(), expected.end());
  for (std::size_t i = 0; i < keys.size(); ++i)
    EXPECT_EQ(std::make_tuple(keys[i].lo, keys[i].hi, keys[i].h), expected[i]) << i;
}
