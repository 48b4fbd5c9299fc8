#include "core/tri_mesh.hpp"

#include <fmt/format.h>
#include <algorithm>

#include "core/edge_groups.hpp"
#include "isoquad/error.hpp"

namespace isoquad {

namespace {

[[noreturn]] void reject(const std::string& what, std::initializer_list<uint32_t> vertices,
                         std::initializer_list<uint32_t> faces) {
  ErrorContext ctx;
  ctx.vertices = vertices;
  ctx.faces = faces;
  throw Error(ErrorKind::invalid_input, "E100", "TriMesh precondition violated: " + what, ctx);
}

// Pairs each halfedge with its opposite: O(F log F), no hashing, deterministic.
std::vector<uint32_t> pair_twins(const std::vector<Tri>& faces) {
  std::vector<uint32_t> twin(3 * faces.size(), kInvalid);
  for_each_edge_group(halfedges_by_edge(faces), [&](std::span<const EdgeHalfedge> g) {
    if (g.size() > 2)
      reject(fmt::format("edge {}-{} has {} faces", g[0].lo, g[0].hi, g.size()), {g[0].lo, g[0].hi},
             {g[0].h / 3, g[1].h / 3, g[2].h / 3});
    if (g.size() < 2) return;
    const uint32_t h0 = g[0].h, h1 = g[1].h;
    if (faces[h0 / 3][h0 % 3] == faces[h1 / 3][h1 % 3])
      reject(fmt::format("faces {} and {} are oriented inconsistently across edge {}-{}", h0 / 3,
                         h1 / 3, g[0].lo, g[0].hi),
             {g[0].lo, g[0].hi}, {h0 / 3, h1 / 3});
    twin[h0] = h1;
    twin[h1] = h0;
  });
  return twin;
}

}  // namespace

TriMesh::TriMesh(std::vector<Vec3> positions, std::vector<Tri> faces)
    : positions_(std::move(positions)), faces_(std::move(faces)) {
  const uint32_t nv = num_vertices(), nf = num_faces(), nh = num_halfedges();
  for (uint32_t f = 0; f < nf; ++f) {
    const Tri& t = faces_[f];
    for (uint32_t c : t)
      if (c >= nv) reject(fmt::format("face {} references vertex {} of {}", f, c, nv), {c}, {f});
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
      reject(fmt::format("face {} repeats a vertex", f), {t[0], t[1], t[2]}, {f});
  }
  twin_ = pair_twins(faces_);

  halfedge_edge_.assign(nh, kInvalid);
  for (uint32_t h = 0; h < nh; ++h) {
    if (twin_[h] != kInvalid && twin_[h] < h) continue;
    halfedge_edge_[h] = static_cast<uint32_t>(edge_halfedge_.size());
    if (twin_[h] != kInvalid) halfedge_edge_[twin_[h]] = halfedge_edge_[h];
    edge_halfedge_.push_back(h);
  }

  // Outgoing halfedge per vertex, the boundary one where there is one.
  outgoing_.assign(nv, kInvalid);
  std::vector<uint32_t> fan_size(nv, 0);
  for (uint32_t h = 0; h < nh; ++h) {
    const uint32_t v = from(h);
    ++fan_size[v];
    if (outgoing_[v] == kInvalid || twin_[h] == kInvalid) {
      if (twin_[h] == kInvalid && outgoing_[v] != kInvalid && twin_[outgoing_[v]] == kInvalid)
        reject(fmt::format("vertex {} has two boundary fans (non-manifold vertex)", v), {v}, {});
      outgoing_[v] = h;
    }
  }
  for (uint32_t v = 0; v < nv; ++v) {
    if (outgoing_[v] == kInvalid) reject(fmt::format("vertex {} has no face", v), {v}, {});
    uint32_t visited = 0;
    for_each_outgoing(v, [&](uint32_t) { ++visited; });
    if (visited != fan_size[v])
      reject(fmt::format("vertex {} has {} faces but its fan reaches only {} (non-manifold vertex)",
                         v, fan_size[v], visited),
             {v}, {});
  }

  // Components: flood faces through twins.
  face_component_.assign(nf, kInvalid);
  std::vector<uint32_t> stack;
  for (uint32_t seed = 0; seed < nf; ++seed) {
    if (face_component_[seed] != kInvalid) continue;
    const uint32_t c = static_cast<uint32_t>(component_topology_.size());
    component_topology_.emplace_back();
    face_component_[seed] = c;
    stack.push_back(seed);
    while (!stack.empty()) {
      const uint32_t f = stack.back();
      stack.pop_back();
      for (uint32_t i = 0; i < 3; ++i) {
        const uint32_t t = twin_[3 * f + i];
        if (t != kInvalid && face_component_[t / 3] == kInvalid) {
          face_component_[t / 3] = c;
          stack.push_back(t / 3);
        }
      }
    }
  }
  for (uint32_t f = 0; f < nf; ++f) ++component_topology_[face_component_[f]].faces;
  for (uint32_t v = 0; v < nv; ++v) ++component_topology_[component_of_vertex(v)].vertices;
  for (uint32_t e = 0; e < num_edges(); ++e)
    ++component_topology_[face_component_[face_of(edge_halfedge_[e])]].edges;

  // Boundary loops: after boundary halfedge a->b comes the boundary halfedge leaving b.
  std::vector<char> on_loop(nh, 0);
  for (uint32_t h0 = 0; h0 < nh; ++h0) {
    if (twin_[h0] != kInvalid || on_loop[h0]) continue;
    std::vector<uint32_t> loop;
    for (uint32_t h = h0; !on_loop[h]; h = outgoing_[to(h)]) {
      on_loop[h] = 1;
      loop.push_back(h);
    }
    ++component_topology_[face_component_[face_of(h0)]].boundary_loops;
    boundary_loops_.push_back(std::move(loop));
  }
}

uint32_t TriMesh::valence(uint32_t v) const {
  uint32_t n = 0;
  for_each_outgoing(v, [&](uint32_t) { ++n; });
  return n + (is_boundary_vertex(v) ? 1 : 0);
}

TriMesh TriMesh::with_positions(std::vector<Vec3> positions) const {
  if (positions.size() != positions_.size())
    throw Error(
        ErrorKind::internal, "E700",
        fmt::format("{} positions for a mesh of {} vertices", positions.size(), positions_.size()));
  TriMesh m = *this;
  m.positions_ = std::move(positions);
  return m;
}

Vec3 TriMesh::face_normal(uint32_t f) const {
  const Tri& t = faces_[f];
  return normalized(
      cross(positions_[t[1]] - positions_[t[0]], positions_[t[2]] - positions_[t[0]]));
}

double TriMesh::face_area(uint32_t f) const {
  const Tri& t = faces_[f];
  return 0.5 *
         norm(cross(positions_[t[1]] - positions_[t[0]], positions_[t[2]] - positions_[t[0]]));
}

Box3 TriMesh::bounding_box() const {
  Box3 box;
  for (const Vec3& p : positions_) box.add(p);
  return box;
}

}  // namespace isoquad
