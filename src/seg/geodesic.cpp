#include "seg/geodesic.hpp"

#include <algorithm>
#include <cmath>
#include <queue>

namespace isoquad {

std::vector<uint32_t> ShortestPaths::path_to(uint32_t target) const {
  std::vector<uint32_t> path;
  if (!(distance[target] < INFINITY)) return path;
  for (uint32_t v = target; v != kInvalid; v = predecessor[v]) path.push_back(v);
  std::reverse(path.begin(), path.end());
  return path;
}

namespace {

// Generic Dijkstra: `distance` (INFINITY where not reached yet) is updated in place;
// reached(node, from) runs whenever a node gets a shorter distance (from kInvalid at a source);
// neighbours(node, visit(next, length)); the search ends when stop(node) holds for a settled
// node.
template <class Neighbours, class Stop, class Reached>
void dijkstra(std::vector<double>& distance, const std::vector<uint32_t>& sources,
              Neighbours&& neighbours, Stop&& stop, Reached&& reached) {
  using Item = std::pair<double, uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  for (uint32_t s : sources) {
    if (distance[s] == 0) continue;
    distance[s] = 0;
    reached(s, kInvalid);
    queue.push({0.0, s});
  }
  while (!queue.empty()) {
    const auto [d, u] = queue.top();
    queue.pop();
    if (d > distance[u]) continue;
    if (stop(u)) break;
    neighbours(u, [&](uint32_t v, double len) {
      const double nd = d + len;
      if (nd < distance[v]) {
        distance[v] = nd;
        reached(v, u);
        queue.push({nd, v});
      }
    });
  }
}

template <class Neighbours, class Stop>
ShortestPaths shortest_paths(std::size_t n, const std::vector<uint32_t>& sources,
                             Neighbours&& neighbours, Stop&& stop) {
  ShortestPaths r;
  r.distance.assign(n, INFINITY);
  r.predecessor.assign(n, kInvalid);
  r.source.assign(n, kInvalid);
  dijkstra(r.distance, sources, neighbours, stop, [&](uint32_t v, uint32_t from) {
    r.predecessor[v] = from;
    r.source[v] = from == kInvalid ? v : r.source[from];
  });
  return r;
}

// The vertex graph's neighbours of u that `allowed(v, edge)` lets in, with their distances.
auto vertex_neighbours(const TriMesh& mesh, const auto& allowed) {
  return [&mesh, &allowed](uint32_t u, auto&& visit) {
    auto go = [&](uint32_t v, uint32_t h) {
      if (allowed(v, mesh.edge(h))) visit(v, norm(mesh.position(v) - mesh.position(u)));
    };
    mesh.for_each_outgoing(u, [&](uint32_t h) { go(mesh.to(h), h); });
    // The last neighbour of a boundary fan is reached only through the incoming boundary edge.
    if (mesh.is_boundary_vertex(u)) {
      uint32_t last = mesh.outgoing(u);
      mesh.for_each_outgoing(u, [&](uint32_t g) { last = g; });
      go(mesh.from(TriMesh::prev(last)), TriMesh::prev(last));
    }
  };
}

}  // namespace

ShortestPaths vertex_dijkstra(const TriMesh& mesh, const std::vector<uint32_t>& sources,
                              const std::function<bool(uint32_t, uint32_t)>& allowed,
                              const std::function<bool(uint32_t)>& stop) {
  return shortest_paths(mesh.num_vertices(), sources, vertex_neighbours(mesh, allowed),
                        [&](uint32_t v) { return stop && stop(v); });
}

std::vector<uint32_t> vertex_path(const TriMesh& mesh, uint32_t a, uint32_t b,
                                  const std::function<bool(uint32_t, uint32_t)>& allowed,
                                  PathScratch& scratch, double& length) {
  const uint32_t nv = mesh.num_vertices();
  if (scratch.distance.size() != nv) {
    scratch.distance.assign(nv, INFINITY);
    scratch.predecessor.assign(nv, kInvalid);
  }
  scratch.touched.clear();
  dijkstra(
      scratch.distance, {a}, vertex_neighbours(mesh, allowed), [&](uint32_t v) { return v == b; },
      [&](uint32_t v, uint32_t from) {
        if (scratch.predecessor[v] == kInvalid && v != a) scratch.touched.push_back(v);
        scratch.predecessor[v] = from;
      });
  length = scratch.distance[b];
  std::vector<uint32_t> path;
  if (length < INFINITY)
    for (uint32_t v = b; v != kInvalid; v = scratch.predecessor[v]) path.push_back(v);
  std::reverse(path.begin(), path.end());
  for (const uint32_t v : scratch.touched) {
    scratch.distance[v] = INFINITY;
    scratch.predecessor[v] = kInvalid;
  }
  scratch.distance[a] = INFINITY;
  return path;
}

double geodesic_distance(const TriMesh& mesh, uint32_t a, uint32_t b,
                         const std::function<bool(uint32_t)>& face_allowed) {
  // A local search (it stops at b): distances live in a per-thread array that is reset only
  // where the search went, not allocated and filled over the whole mesh for every call.
  thread_local std::vector<double> distance;
  thread_local std::vector<uint32_t> touched;
  if (distance.size() < mesh.num_vertices()) distance.assign(mesh.num_vertices(), INFINITY);
  touched.clear();
  auto neighbours = [&](uint32_t u, auto&& visit) {
    mesh.for_each_outgoing(u, [&](uint32_t h) {
      const uint32_t f = TriMesh::face_of(h);
      if (!face_allowed(f)) return;
      // Mesh edges u->v and v's predecessor in the face (both edges of face f at u).
      visit(mesh.to(h), norm(mesh.position(mesh.to(h)) - mesh.position(u)));
      const uint32_t w = mesh.from(TriMesh::prev(h));
      visit(w, norm(mesh.position(w) - mesh.position(u)));
      // Across the opposite edge: the far vertex of the neighbouring face, unfolded.
      const uint32_t opp = TriMesh::next(h), t = mesh.twin(opp);
      if (t == kInvalid || !face_allowed(TriMesh::face_of(t))) return;
      const uint32_t x = mesh.from(TriMesh::prev(t));
      const Vec3 p = mesh.position(u), q = mesh.position(mesh.to(h)), r = mesh.position(w),
                 s = mesh.position(x);
      // Unfold face (q, w, x) into the plane of (u, q, w) around edge q-w: the angle at q
      // (and at w) is the sum of the two faces' angles; below pi on both ends the straight
      // segment stays inside the two faces. Sums via cos/sin products, without trigonometry.
      struct CosSin {
        double c, s;
      };
      auto cs = [](Vec3 d1, Vec3 d2) {
        const double l = norm(d1) * norm(d2);
        return l > 0 ? CosSin{dot(d1, d2) / l, norm(cross(d1, d2)) / l} : CosSin{1, 0};
      };
      const CosSin q1 = cs(p - q, r - q), q2 = cs(s - q, r - q);
      const CosSin r1 = cs(p - r, q - r), r2 = cs(s - r, q - r);
      if (q1.s * q2.c + q1.c * q2.s <= 0 || r1.s * r2.c + r1.c * r2.s <= 0) return;
      const double cos_q = q1.c * q2.c - q1.s * q2.s;
      const double lq = norm(p - q), lx = norm(s - q);
      const double d2 = lq * lq + lx * lx - 2 * lq * lx * cos_q;
      visit(x, std::sqrt(std::max(d2, 0.0)));
    });
  };
  // A*: the straight distance to b never overestimates what is left (a step's length, along an
  // edge or across two unfolded faces, is at least the chord between its ends), so the search
  // settles b at the same distance as Dijkstra would, after a band around the path instead of a
  // disk of its length around a.
  const Vec3 target = mesh.position(b);
  auto left = [&](uint32_t v) { return norm(target - mesh.position(v)); };
  using Item = std::pair<double, uint32_t>;  // (distance + left, vertex)
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  distance[a] = 0;
  touched.push_back(a);
  queue.push({left(a), a});
  while (!queue.empty()) {
    const auto [f, u] = queue.top();
    queue.pop();
    const double g = distance[u];
    if (f > g + left(u)) continue;  // a stale entry
    if (u == b) break;
    neighbours(u, [&](uint32_t v, double len) {
      const double nd = g + len;
      if (nd < distance[v]) {
        if (distance[v] == INFINITY) touched.push_back(v);
        distance[v] = nd;
        queue.push({nd + left(v), v});
      }
    });
  }
  const double result = distance[b];
  for (const uint32_t v : touched) distance[v] = INFINITY;
  return result;
}

ShortestPaths face_dijkstra(const TriMesh& mesh, const std::vector<uint32_t>& sources,
                            const std::function<bool(uint32_t)>& crossable) {
  auto centroid = [&](uint32_t f) {
    const Tri& t = mesh.face(f);
    return (mesh.position(t[0]) + mesh.position(t[1]) + mesh.position(t[2])) / 3.0;
  };
  return shortest_paths(
      mesh.num_faces(), sources,
      [&](uint32_t f, auto&& visit) {
        for (uint32_t i = 0; i < 3; ++i) {
          const uint32_t h = 3 * f + i;
          if (mesh.twin(h) == kInvalid || !crossable(h)) continue;
          const uint32_t g = TriMesh::face_of(mesh.twin(h));
          visit(g, norm(centroid(g) - centroid(f)));
        }
      },
      [](uint32_t) { return false; });
}

}  // namespace isoquad
