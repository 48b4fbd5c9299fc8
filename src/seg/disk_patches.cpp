#include "seg/disk_patches.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <map>

#include "core/face_regions.hpp"
#include "core/union_find.hpp"
#include "isoquad/error.hpp"
#include "seg/geodesic.hpp"
#include "seg/patch_topology.hpp"

namespace isoquad {

uint32_t compact_labels(FaceData<uint32_t>& labels) {
  std::map<uint32_t, uint32_t> remap;
  for (uint32_t& l : labels) {
    auto [it, inserted] = remap.try_emplace(l, uint32_t(remap.size()));
    l = it->second;
  }
  return uint32_t(remap.size());
}

namespace {

bool same_patch(const TriMesh& m, const FaceData<uint32_t>& labels, uint32_t h) {
  return m.twin(h) != kInvalid &&
         labels[TriMesh::face_of(m.twin(h))] == labels[TriMesh::face_of(h)];
}

// Every connected piece of a label becomes its own label.
uint32_t split_disconnected(const TriMesh& m, FaceData<uint32_t>& labels, uint32_t n,
                            DiskRepairLog& log) {
  std::vector<uint32_t> region;
  const uint32_t count = face_regions(
      m, [&](uint32_t h) { return same_patch(m, labels, h); }, region);
  log.disconnected_split += count - std::min(count, n);
  labels = FaceData<uint32_t>(std::move(region));
  return count;
}

// A patch seen in two wedges at one vertex touches itself there. The smaller such wedge joins
// the neighbouring patch it shares most edges with. Returns the number of wedges moved.
uint32_t fix_pinches(const TriMesh& m, FaceData<uint32_t>& labels) {
  uint32_t fixed = 0;
  for (uint32_t v = 0; v < m.num_vertices(); ++v) {
    auto w = wedges_at(m, labels, v);
    uint32_t moves_here = 0;  // a vertex is settled in a few moves; the cap only guards cycles
    for (std::size_t i = 0; i < w.size() && moves_here < 16; ++i) {
      std::size_t smallest = i;
      bool repeated = false;
      for (std::size_t j = 0; j < w.size(); ++j)
        if (j != i && w[j].patch == w[i].patch) {
          repeated = true;
          if (w[j].faces.size() < w[smallest].faces.size()) smallest = j;
        }
      if (!repeated) continue;
      // Count shared edges of the wedge's faces with each other patch.
      std::map<uint32_t, uint32_t> shared;
      for (uint32_t f : w[smallest].faces)
        for (uint32_t k = 0; k < 3; ++k) {
          const uint32_t t = m.twin(3 * f + k);
          if (t != kInvalid && labels[TriMesh::face_of(t)] != w[smallest].patch)
            ++shared[labels[TriMesh::face_of(t)]];
        }
      if (shared.empty()) continue;
      const auto best = std::max_element(shared.begin(), shared.end(), [](auto& a, auto& b) {
        return a.second < b.second || (a.second == b.second && a.first > b.first);
      });
      for (uint32_t f : w[smallest].faces) labels[f] = best->first;
      ++fixed;
      ++moves_here;
      w = wedges_at(m, labels, v);
      i = std::size_t(-1);  // re-scan this vertex
    }
  }
  return fixed;
}

// Patches too small to hold four corners (fewer than 4 boundary edges or 3 faces) join the
// neighbour they share most edges with. Returns how many were merged.
uint32_t merge_tiny(const TriMesh& m, FaceData<uint32_t>& labels, uint32_t n) {
  const auto topo = patch_topology(m, labels, n);
  uint32_t merged = 0;
  for (uint32_t p = 0; p < n; ++p) {
    if (topo[p].faces >= 3 && topo[p].boundary_edges >= 4) continue;
    std::map<uint32_t, uint32_t> shared;
    for (uint32_t f = 0; f < m.num_faces(); ++f) {
      if (labels[f] != p) continue;
      for (uint32_t k = 0; k < 3; ++k) {
        const uint32_t t = m.twin(3 * f + k);
        if (t != kInvalid && labels[TriMesh::face_of(t)] != p)
          ++shared[labels[TriMesh::face_of(t)]];
      }
    }
    if (shared.empty()) continue;  // a whole tiny component: nothing to merge with
    const auto best = std::max_element(shared.begin(), shared.end(), [](auto& a, auto& b) {
      return a.second < b.second || (a.second == b.second && a.first > b.first);
    });
    for (uint32_t& l : labels)
      if (l == p) l = best->first;
    ++merged;
  }
  return merged;
}

// The boundary loops of patch p, as halfedge cycles (patch on the left).
std::vector<std::vector<uint32_t>> loops_of(const TriMesh& m, const FaceData<uint32_t>& labels,
                                            uint32_t p) {
  std::vector<std::vector<uint32_t>> loops;
  std::vector<char> visited(m.num_halfedges(), 0);
  for (uint32_t h0 = 0; h0 < m.num_halfedges(); ++h0) {
    if (visited[h0] || labels[TriMesh::face_of(h0)] != p || !is_patch_boundary(m, labels, h0))
      continue;
    loops.emplace_back();
    for (uint32_t h = h0; !visited[h]; h = next_patch_boundary_halfedge(m, labels, h)) {
      visited[h] = 1;
      loops.back().push_back(h);
    }
  }
  return loops;
}

// The faces of patch p on the left of a path of vertices (a cycle if `closed`): at every inner
// vertex w (from u, to x) the faces turning counterclockwise from w->x to w->u; at an open path's
// ends, on the patch boundary, the whole fan on the left, so that the rest is not pinched there.
// Empty where an edge of the path is missing or a turn does not end.
std::vector<uint32_t> left_faces(const TriMesh& m, const FaceData<uint32_t>& labels, uint32_t p,
                                 const std::vector<uint32_t>& path, bool closed) {
  std::vector<uint32_t> faces;
  const std::size_t k = path.size();
  const auto halfedge = [&](uint32_t a, uint32_t b) {
    uint32_t found = kInvalid;
    m.for_each_outgoing(a, [&](uint32_t h) {
      if (m.to(h) == b) found = h;
    });
    return found;
  };
  const auto in_p = [&](uint32_t h) { return h != kInvalid && labels[TriMesh::face_of(h)] == p; };
  for (std::size_t i = 0; i < k; ++i) {
    const bool first = !closed && i == 0, last = !closed && i + 1 == k;
    const uint32_t u = path[(i + k - 1) % k], x = path[(i + 1) % k];
    uint32_t o = last ? halfedge(path[i], u) : halfedge(path[i], x);
    if (o == kInvalid) return {};
    for (uint32_t turns = 0;; ++turns) {
      if (turns > 256) return {};
      if (last) {  // clockwise from w->u while in p
        const uint32_t t = m.twin(o);
        if (!in_p(t)) break;
        faces.push_back(TriMesh::face_of(t));
        o = TriMesh::next(t);
      } else {  // counterclockwise from w->x, to w->u or while in p at the first vertex
        if ((!first && m.to(o) == u) || !in_p(o)) break;
        faces.push_back(TriMesh::face_of(o));
        o = m.twin(TriMesh::prev(o));
        if (o == kInvalid) break;
      }
    }
    if (!first && !last && m.to(o) != u) return {};
  }
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return faces;
}

// Two-path cut of a patch with several boundary loops (DESIGN.md §2.2c): the shortest path from
// a hole to the outer loop, and a second one as far from the first as possible, cut the patch
// into two (an annulus into two disks: long strips along a tube, not rings). With `strip`, round a
// hole too small for a second path two edges away from the first, the faces along the first
// become a patch of their own: a strip from the hole to the outer loop.
bool two_path_cut(const TriMesh& m, FaceData<uint32_t>& labels, uint32_t p, uint32_t& n,
                  bool strip) {
  auto loops = loops_of(m, labels, p);
  if (loops.size() < 2) return false;
  auto length = [&](const std::vector<uint32_t>& loop) {
    double l = 0;
    for (uint32_t h : loop) l += norm(m.position(m.to(h)) - m.position(m.from(h)));
    return l;
  };
  std::stable_sort(loops.begin(), loops.end(),
                   [&](auto& x, auto& y) { return length(x) > length(y); });
  const auto& outer = loops.front();
  const auto& hole = loops.back();
  std::vector<char> in_p(m.num_vertices(), 0), on_boundary(m.num_vertices(), 0),
      on_outer(m.num_vertices(), 0);
  double edge_sum = 0;
  uint32_t edge_count = 0;
  for (uint32_t f = 0; f < m.num_faces(); ++f)
    if (labels[f] == p)
      for (uint32_t k = 0; k < 3; ++k) {
        in_p[m.face(f)[k]] = 1;
        edge_sum += norm(m.position(m.to(3 * f + k)) - m.position(m.from(3 * f + k)));
        ++edge_count;
      }
  for (const auto& loop : loops)
    for (uint32_t h : loop) on_boundary[m.from(h)] = 1;
  for (uint32_t h : outer) on_outer[m.from(h)] = 1;
  std::vector<uint32_t> hole_vertices;
  for (uint32_t h : hole) hole_vertices.push_back(m.from(h));
  auto interior_edge = [&](uint32_t e) {
    const uint32_t h = m.edge_halfedge(e);
    return m.twin(h) != kInvalid && labels[TriMesh::face_of(h)] == p &&
           labels[TriMesh::face_of(m.twin(h))] == p;
  };
  auto interior_vertex = [&](uint32_t v) { return in_p[v] && !on_boundary[v]; };
  auto first_outer = [&](const ShortestPaths& d) {
    uint32_t best = kInvalid;
    for (uint32_t h : outer) {
      const uint32_t v = m.from(h);
      if (d.distance[v] < INFINITY && (best == kInvalid || d.distance[v] < d.distance[best]))
        best = v;
    }
    return best;
  };
  const ShortestPaths d1 = vertex_dijkstra(
      m, hole_vertices,
      [&](uint32_t v, uint32_t e) {
        return interior_edge(e) && (interior_vertex(v) || on_outer[v]);
      },
      [&](uint32_t v) { return on_outer[v] != 0; });
  const uint32_t end1 = first_outer(d1);
  if (end1 == kInvalid) return false;
  const std::vector<uint32_t> g1 = d1.path_to(end1);
  const ShortestPaths away =
      vertex_dijkstra(m, g1, [&](uint32_t v, uint32_t) { return in_p[v] != 0; });
  const double clearance = 2.0 * edge_sum / std::max(edge_count, 1u);
  const auto strip_cut = [&] {
    FaceData<uint32_t> trial = labels;
    std::vector<uint32_t> faces;
    for (uint32_t f = 0; f < m.num_faces(); ++f)
      if (labels[f] == p) faces.push_back(f);
    for (uint32_t f : left_faces(m, labels, p, g1, false)) trial[f] = n;
    const auto topo = local_patch_topology(m, trial, faces, {p, n});
    const PatchTopology before = local_patch_topology(m, labels, faces, {p})[0];
    // The strip a disk, the rest one hole fewer and no handle more.
    if (!topo[1].is_disk() || topo[0].boundary_loops + 1 != before.boundary_loops ||
        topo[0].euler() != before.euler() + 1)
      return false;
    labels = std::move(trial);
    ++n;
    return true;
  };
  uint32_t start2 = kInvalid;
  for (uint32_t v : hole_vertices)
    if (away.distance[v] < INFINITY &&
        (start2 == kInvalid || away.distance[v] > away.distance[start2]))
      start2 = v;
  if (start2 == kInvalid || away.distance[start2] < clearance) return strip && strip_cut();
  const ShortestPaths d2 = vertex_dijkstra(
      m, {start2},
      [&](uint32_t v, uint32_t e) {
        return interior_edge(e) && (interior_vertex(v) || on_outer[v]) &&
               away.distance[v] >= clearance;
      },
      [&](uint32_t v) { return on_outer[v] != 0; });
  const uint32_t end2 = first_outer(d2);
  if (end2 == kInvalid) return strip && strip_cut();
  const std::vector<uint32_t> g2 = d2.path_to(end2);

  // Flood the patch without crossing the two paths.
  std::vector<char> cut(m.num_edges(), 0);
  for (const auto* g : {&g1, &g2})
    for (std::size_t i = 0; i + 1 < g->size(); ++i)
      m.for_each_outgoing((*g)[i], [&](uint32_t h) {
        if (m.to(h) == (*g)[i + 1]) cut[m.edge(h)] = 1;
      });
  std::vector<uint32_t> piece;
  const uint32_t pieces = face_regions(
      m, [&](uint32_t h) { return same_patch(m, labels, h) && !cut[m.edge(h)]; },
      [&](uint32_t f) { return labels[f] == p; }, piece);
  if (pieces < 2) return false;
  for (uint32_t f = 0; f < m.num_faces(); ++f)
    if (labels[f] == p && piece[f] > 0) labels[f] = n + piece[f] - 1;
  n += pieces - 1;
  return true;
}

// A patch with a handle: the faces along one side of a short non-separating cycle become a new
// patch, a ring round the handle, which the two-path cut then cuts into disks. The cycle is found
// by tree-cotree (Erickson and Whittlesey 2005): a shortest-path tree T over the patch's interior
// vertices, every boundary loop capped by one dual node, and a maximum spanning tree C of the
// dual graph by the length of each edge's cycle through T; an edge in neither closes a cycle that
// C does not cross, so the patch stays connected when cut along it. Of those edges the one with
// the shortest cycle is taken. A Voronoi split cannot separate a handle far smaller than its
// cells; this cut does, whatever the handle's size. True if a handle was cut.
bool cut_handle(const TriMesh& m, FaceData<uint32_t>& labels, uint32_t p, uint32_t& n) {
  const auto loops = loops_of(m, labels, p);
  std::vector<uint32_t> loop_of(m.num_halfedges(), kInvalid);
  std::vector<char> on_boundary(m.num_vertices(), 0);
  for (uint32_t l = 0; l < loops.size(); ++l)
    for (uint32_t h : loops[l]) {
      loop_of[h] = l;
      on_boundary[m.from(h)] = 1;
    }
  std::vector<uint32_t> faces, local(m.num_faces(), kInvalid);
  for (uint32_t f = 0; f < m.num_faces(); ++f)
    if (labels[f] == p) {
      local[f] = uint32_t(faces.size());
      faces.push_back(f);
    }
  uint32_t root = kInvalid;
  for (uint32_t f : faces)
    for (uint32_t v : m.face(f))
      if (!on_boundary[v]) root = std::min(root, v);
  if (root == kInvalid) return false;
  const ShortestPaths tree = vertex_dijkstra(m, {root}, [&](uint32_t v, uint32_t e) {
    const uint32_t h = m.edge_halfedge(e);
    return !on_boundary[v] && m.twin(h) != kInvalid && labels[TriMesh::face_of(h)] == p &&
           labels[TriMesh::face_of(m.twin(h))] == p;
  });
  const auto in_tree = [&](uint32_t h) {
    return tree.predecessor[m.to(h)] == m.from(h) || tree.predecessor[m.from(h)] == m.to(h);
  };
  // The dual edges: one per edge of the patch outside T, to the cap of its loop on the boundary.
  struct Dual {
    double cycle;
    uint32_t h, a, b;
  };
  std::vector<Dual> duals;
  for (uint32_t f : faces)
    for (uint32_t k = 0; k < 3; ++k) {
      const uint32_t h = 3 * f + k, t = m.twin(h);
      const bool boundary = loop_of[h] != kInvalid;
      if (in_tree(h) || (!boundary && h > t)) continue;
      const double cycle = tree.distance[m.from(h)] + tree.distance[m.to(h)] +
                           norm(m.position(m.to(h)) - m.position(m.from(h)));
      duals.push_back(
          {cycle, h, local[f],
           boundary ? uint32_t(faces.size()) + loop_of[h] : local[TriMesh::face_of(t)]});
    }
  std::stable_sort(duals.begin(), duals.end(),
                   [](const Dual& x, const Dual& y) { return x.cycle > y.cycle; });
  UnionFind cotree(faces.size() + loops.size());
  const Dual* shortest = nullptr;
  for (const Dual& d : duals) {
    if (cotree.find(d.a) != cotree.find(d.b)) {
      cotree.unite(d.a, d.b);
    } else if (d.cycle < INFINITY) {
      shortest = &d;  // the list runs from long to short cycles
    }
  }
  if (!shortest) return false;
  // The cycle: from the two paths' last common vertex through one end, the edge, the other end.
  const std::vector<uint32_t> pa = tree.path_to(m.from(shortest->h));
  const std::vector<uint32_t> pb = tree.path_to(m.to(shortest->h));
  std::size_t common = 0;
  while (common + 1 < pa.size() && common + 1 < pb.size() && pa[common + 1] == pb[common + 1])
    ++common;
  std::vector<uint32_t> cycle(pa.begin() + std::ptrdiff_t(common), pa.end());
  cycle.insert(cycle.end(), pb.rbegin(), pb.rend() - std::ptrdiff_t(common) - 1);
  if (cycle.size() < 3) return false;
  // The ring: the faces on the cycle's left.
  const std::vector<uint32_t> ring = left_faces(m, labels, p, cycle, true);
  if (ring.empty()) return false;
  FaceData<uint32_t> trial = labels;
  for (uint32_t f : ring) trial[f] = n;
  const auto genus = [](const PatchTopology& t) { return 2 - t.euler() - t.boundary_loops; };
  const auto topo = local_patch_topology(m, trial, faces, {p, n});
  if (topo[1].euler() != 0 || topo[1].boundary_loops != 2 ||
      genus(topo[0]) >= genus(local_patch_topology(m, labels, faces, {p})[0]))
    return false;
  labels = std::move(trial);
  ++n;
  return true;
}

// A hole of patch p that one other patch fills entirely (an island: a disk whose whole boundary is
// that hole's loop) joins p. Where the ring round an island is too narrow for two cuts, p becomes
// a disk this way. True if an island was merged.
bool merge_island(const TriMesh& m, FaceData<uint32_t>& labels, uint32_t p, uint32_t n) {
  const auto topo = patch_topology(m, labels, n);
  for (const auto& loop : loops_of(m, labels, p)) {
    uint32_t q = kInvalid;
    bool single = true;
    for (uint32_t h : loop) {
      const uint32_t t = m.twin(h);
      const uint32_t across = t == kInvalid ? kInvalid : labels[TriMesh::face_of(t)];
      if (across == kInvalid || (q != kInvalid && across != q)) {
        single = false;
        break;
      }
      q = across;
    }
    if (!single || q == kInvalid || !topo[q].is_disk() ||
        topo[q].boundary_edges != uint32_t(loop.size()))
      continue;
    for (uint32_t& l : labels)
      if (l == q) l = p;
    return true;
  }
  return false;
}

// Geodesic Voronoi split of patch p into k cells seeded by farthest-point sampling on the dual
// graph; accepted for the first k whose cells are all disks. Where no k up to 24 gives only
// disks (a handle or a hole far smaller than a cell stays inside one) and `piecewise`, the k
// whose cells that are not disks hold the fewest faces is taken: those cells are smaller than p,
// and the next round of make_disk_patches cuts them again, so the repair still ends in disks.
bool voronoi_split(const TriMesh& m, FaceData<uint32_t>& labels, uint32_t p, uint32_t& n,
                   bool piecewise) {
  std::vector<uint32_t> faces;
  for (uint32_t f = 0; f < m.num_faces(); ++f)
    if (labels[f] == p) faces.push_back(f);
  auto inside = [&](uint32_t h) { return same_patch(m, labels, h); };
  std::vector<uint32_t> seeds;
  {
    const ShortestPaths d = face_dijkstra(m, {faces.front()}, inside);
    seeds.push_back(*std::max_element(faces.begin(), faces.end(), [&](uint32_t a, uint32_t b) {
      return d.distance[a] < d.distance[b] || (d.distance[a] == d.distance[b] && a > b);
    }));
  }
  FaceData<uint32_t> fewest;  // the trial whose non-disk cells hold the fewest faces
  uint32_t fewest_k = 0, fewest_faces = uint32_t(faces.size());
  const auto take_fewest = [&] {
    if (!piecewise || fewest_k == 0) return false;
    labels = std::move(fewest);
    n += fewest_k - 1;
    return true;
  };
  for (uint32_t k = 2; k <= 24; ++k) {
    ShortestPaths d = face_dijkstra(m, seeds, inside);
    const uint32_t far = *std::max_element(faces.begin(), faces.end(), [&](uint32_t a, uint32_t b) {
      return d.distance[a] < d.distance[b] || (d.distance[a] == d.distance[b] && a > b);
    });
    if (d.distance[far] == 0) return take_fewest();  // no face left to seed
    seeds.push_back(far);
    d = face_dijkstra(m, seeds, inside);
    FaceData<uint32_t> trial = labels;
    for (uint32_t f : faces) {
      const auto it = std::find(seeds.begin(), seeds.end(), d.source[f]);
      trial[f] = it == seeds.begin() ? p : n + uint32_t(it - seeds.begin()) - 1;
    }
    const auto topo = patch_topology(m, trial, n + k - 1);
    uint32_t not_disk = topo[p].is_disk() ? 0 : topo[p].faces;
    for (uint32_t c = n; c < n + k - 1; ++c) not_disk += topo[c].is_disk() ? 0 : topo[c].faces;
    if (not_disk == 0) {
      labels = std::move(trial);
      n += k - 1;
      return true;
    }
    if (not_disk < fewest_faces) {
      fewest = std::move(trial);
      fewest_k = k;
      fewest_faces = not_disk;
    }
  }
  return take_fewest();
}

}  // namespace

uint32_t make_disk_patches(const TriMesh& m, FaceData<uint32_t>& labels, DiskRepairLog& log,
                           bool piecewise) {
  uint32_t n = compact_labels(labels);
  for (log.rounds = 1; log.rounds <= 64; ++log.rounds) {
    n = split_disconnected(m, labels, n, log);
    const uint32_t tiny = merge_tiny(m, labels, n);
    log.tiny_merged += tiny;
    if (tiny > 0) {
      n = compact_labels(labels);
      continue;
    }
    const uint32_t pinches = fix_pinches(m, labels);
    log.pinches_fixed += pinches;
    if (pinches > 0) {
      n = compact_labels(labels);
      continue;  // relabelling may have disconnected something
    }
    const auto topo = patch_topology(m, labels, n);
    bool changed = false;
    for (uint32_t p = 0; p < topo.size(); ++p) {
      if (topo[p].is_disk()) continue;
      if (topo[p].boundary_loops >= 2 && two_path_cut(m, labels, p, n, false)) {
        ++log.two_path_cuts;
        changed = true;
        continue;
      }
      if (topo[p].boundary_loops >= 2 && merge_island(m, labels, p, n)) {
        ++log.islands_merged;
        changed = true;
        break;  // the labels changed under topo
      }
      if (voronoi_split(m, labels, p, n, false)) {
        ++log.voronoi_splits;
        changed = true;
        continue;
      }
      // A hole or a handle far smaller than a Voronoi cell: a strip from the hole to the outer
      // loop, or a ring round the handle, however thin.
      if (topo[p].boundary_loops >= 2 && two_path_cut(m, labels, p, n, true)) {
        ++log.strips_cut;
        changed = true;
        continue;
      }
      if (topo[p].euler() + topo[p].boundary_loops < 2 && cut_handle(m, labels, p, n)) {
        ++log.handles_cut;
        changed = true;
        continue;
      }
      if (!piecewise || !voronoi_split(m, labels, p, n, true))
        throw Error(
            ErrorKind::unsupported_topology, "E201",
            fmt::format(
                "patch {} ({} faces, {} boundary loops, euler {}) could not be made a disk; "
                "use more --patches",
                p, topo[p].faces, topo[p].boundary_loops, topo[p].euler()));
      ++log.voronoi_splits;
      changed = true;
    }
    if (!changed) return compact_labels(labels);
  }
  throw Error(ErrorKind::internal, "E700", "patch topology repair did not converge in 64 rounds");
}

}  // namespace isoquad
