#include "seg/disk_patches.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <map>

#include "core/face_regions.hpp"
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

// Two-path cut of a patch with several boundary loops (DESIGN.md §2.2c): the shortest path from
// a hole to the outer loop, and a second one as far from the first as possible, cut the patch
// into two (an annulus into two disks: long strips along a tube, not rings).
bool two_path_cut(const TriMesh& m, FaceData<uint32_t>& labels, uint32_t p, uint32_t& n) {
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
  uint32_t start2 = kInvalid;
  for (uint32_t v : hole_vertices)
    if (away.distance[v] < INFINITY &&
        (start2 == kInvalid || away.distance[v] > away.distance[start2]))
      start2 = v;
  if (start2 == kInvalid || away.distance[start2] < clearance) return false;
  const ShortestPaths d2 = vertex_dijkstra(
      m, {start2},
      [&](uint32_t v, uint32_t e) {
        return interior_edge(e) && (interior_vertex(v) || on_outer[v]) &&
               away.distance[v] >= clearance;
      },
      [&](uint32_t v) { return on_outer[v] != 0; });
  const uint32_t end2 = first_outer(d2);
  if (end2 == kInvalid) return false;
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
      if (topo[p].boundary_loops >= 2 && two_path_cut(m, labels, p, n)) {
        ++log.two_path_cuts;
        changed = true;
        continue;
      }
      if (topo[p].boundary_loops >= 2 && merge_island(m, labels, p, n)) {
        ++log.islands_merged;
        changed = true;
        break;  // the labels changed under topo
      }
      if (!voronoi_split(m, labels, p, n, piecewise))
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
