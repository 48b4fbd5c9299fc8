#include "seg/quad_split.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/face_regions.hpp"
#include "core/union_find.hpp"
#include "isoquad/error.hpp"
#include "layout/divide_split.hpp"
#include "seg/geodesic.hpp"

namespace isoquad {

namespace {

// A side of a patch after the merge: a polyline of mesh vertices between two kept junctions,
// made of one or more meta-edges, with the vertex that will be its midpoint.
struct Side {
  std::vector<uint32_t> vertices;
  uint32_t midpoint = kInvalid;
};

// Which meta-vertices to keep: all but inserted valence-2 ones inside the surface whose two
// patches both keep at least three junctions (so no centre gets fewer than three sectors).
std::vector<char> kept_meta_vertices(const MetaMesh& meta, uint32_t& dropped) {
  std::vector<char> keep(meta.vertices.size(), 1);
  std::vector<uint32_t> junctions(meta.faces.size());
  for (uint32_t p = 0; p < meta.faces.size(); ++p)
    junctions[p] = uint32_t(meta.faces[p].cycle.size());
  for (uint32_t v = 0; v < meta.vertices.size(); ++v) {
    const MetaVertex& mv = meta.vertices[v];
    if (!mv.inserted || mv.on_boundary || mv.wedge_patches.size() != 2) continue;
    const uint32_t a = mv.wedge_patches[0], b = mv.wedge_patches[1];
    if (a == b || junctions[a] <= 3 || junctions[b] <= 3) continue;
    keep[v] = 0;
    --junctions[a], --junctions[b];
    ++dropped;
  }
  return keep;
}

// The sides: meta-edges joined through dropped meta-vertices, each side's polyline oriented from
// its smaller end vertex, with the vertex nearest to half its length as the midpoint (kInvalid
// when it has no vertex inside). side_of[e] is the side of meta-edge e.
std::vector<Side> sides_of(const TriMesh& mesh, const MetaMesh& meta, const std::vector<char>& keep,
                           std::vector<uint32_t>& side_of) {
  const uint32_t ne = uint32_t(meta.edges.size());
  UnionFind groups(ne);
  std::vector<std::vector<uint32_t>> at(meta.vertices.size());
  for (uint32_t e = 0; e < ne; ++e) {
    at[meta.edges[e].mv0].push_back(e);
    at[meta.edges[e].mv1].push_back(e);
  }
  for (uint32_t v = 0; v < meta.vertices.size(); ++v)
    if (!keep[v] && at[v].size() == 2) groups.unite(at[v][0], at[v][1]);
  std::vector<Side> sides;
  side_of.assign(ne, kInvalid);
  std::vector<uint32_t> root_side(ne, kInvalid);
  for (uint32_t e = 0; e < ne; ++e) {
    const uint32_t r = groups.find(e);
    if (root_side[r] == kInvalid) root_side[r] = uint32_t(sides.size()), sides.emplace_back();
    side_of[e] = root_side[r];
  }
  // Chain each side's meta-edges from one kept end to the other.
  std::vector<std::vector<uint32_t>> members_of(sides.size());
  for (uint32_t e = 0; e < ne; ++e) members_of[side_of[e]].push_back(e);
  for (uint32_t s = 0; s < sides.size(); ++s) {
    const std::vector<uint32_t>& members = members_of[s];
    uint32_t start = kInvalid;
    for (const uint32_t e : members)
      for (const uint32_t v : {meta.edges[e].mv0, meta.edges[e].mv1})
        if (keep[v] && (start == kInvalid || meta.vertices[v].vertex < meta.vertices[start].vertex))
          start = v;
    std::vector<uint32_t>& poly = sides[s].vertices;
    std::vector<char> used(members.size(), 0);
    uint32_t at_mv = start;
    for (std::size_t n = 0; n < members.size(); ++n)
      for (std::size_t i = 0; i < members.size(); ++i) {
        const MetaEdge& me = meta.edges[members[i]];
        if (used[i] || (me.mv0 != at_mv && me.mv1 != at_mv)) continue;
        used[i] = 1;
        std::vector<uint32_t> part = me.vertices;
        if (me.mv0 != at_mv) std::reverse(part.begin(), part.end());
        poly.insert(poly.end(), part.begin() + (poly.empty() ? 0 : 1), part.end());
        at_mv = me.mv0 == at_mv ? me.mv1 : me.mv0;
        break;
      }
    if (poly.size() < 3) continue;
    std::vector<double> arc(poly.size(), 0);
    for (std::size_t i = 1; i < poly.size(); ++i)
      arc[i] = arc[i - 1] + norm(mesh.position(poly[i]) - mesh.position(poly[i - 1]));
    double best = INFINITY;
    for (std::size_t i = 1; i + 1 < poly.size(); ++i)
      if (std::fabs(arc[i] - 0.5 * arc.back()) < best)
        best = std::fabs(arc[i] - 0.5 * arc.back()), sides[s].midpoint = poly[i];
  }
  return sides;
}

struct Cut {
  FaceData<uint32_t> labels;
  uint32_t num_patches = 0;
  std::vector<uint32_t> forced;  // meta-vertices of the split meta-mesh
};

// The cut of every patch along paths from its centre to its side midpoints; nothing if some
// side has no midpoint, some patch no centre, or some path is blocked.
// `centres` keeps each patch's centre across refinements (vertex ids survive edge splits).
std::optional<Cut> cut_patches(const TriMesh& mesh, const FaceData<uint32_t>& labels,
                               const MetaMesh& meta, std::vector<uint32_t>& centres,
                               std::vector<uint32_t>& refine, uint32_t& dropped) {
  const std::vector<char> keep = kept_meta_vertices(meta, dropped);
  std::vector<uint32_t> side_of;
  const std::vector<Side> sides = sides_of(mesh, meta, keep, side_of);
  // Where something does not fit, `refine` collects the edges to split before the next try.
  auto edge_between = [&](uint32_t a, uint32_t b) {
    uint32_t e = kInvalid;
    mesh.for_each_outgoing(a, [&](uint32_t h) {
      if (mesh.to(h) == b) e = mesh.edge(h);
    });
    return e;
  };
  for (const Side& s : sides)
    if (s.midpoint == kInvalid)  // a side of one mesh edge: split it
      refine.push_back(edge_between(s.vertices.front(), s.vertices.back()));
  if (!refine.empty()) return std::nullopt;
  auto refine_patch = [&](uint32_t p) {
    for (uint32_t f = 0; f < mesh.num_faces(); ++f)
      if (labels[f] == p)
        for (uint32_t i = 0; i < 3; ++i) refine.push_back(mesh.edge(3 * f + i));
  };
  // Interior vertices and their patch.
  const uint32_t nv = mesh.num_vertices();
  std::vector<uint32_t> patch_of(nv, kInvalid);
  for (uint32_t f = 0; f < mesh.num_faces(); ++f)
    for (const uint32_t v : mesh.face(f)) patch_of[v] = labels[f];
  auto interior = [&](uint32_t v) {
    return meta.vertex_meta_vertex[v] == kInvalid && meta.vertex_meta_edge[v] == kInvalid &&
           !mesh.is_boundary_vertex(v);
  };
  Cut cut;
  for (uint32_t v = 0; v < meta.vertices.size(); ++v)
    if (keep[v]) cut.forced.push_back(meta.vertices[v].vertex);
  for (const Side& s : sides) cut.forced.push_back(s.midpoint);
  std::vector<char> cut_edge(mesh.num_edges(), 0), used(nv, 0);
  for (uint32_t p = 0; p < meta.faces.size(); ++p) {
    // The patch's sides in CCW order (consecutive items of one side counted once).
    std::vector<uint32_t> targets;
    std::vector<uint32_t> boundary;
    for (const BoundaryItem& it : meta.faces[p].cycle) {
      const uint32_t s = side_of[it.edge];
      if (targets.empty() ||
          (targets.back() != sides[s].midpoint && targets.front() != sides[s].midpoint))
        targets.push_back(sides[s].midpoint);
      for (const uint32_t v : meta.edges[it.edge].vertices) boundary.push_back(v);
    }
    // The centre: the interior vertex farthest from the patch's boundary.
    if (centres[p] == kInvalid) {
      const ShortestPaths from_boundary = vertex_dijkstra(
          mesh, boundary, [&](uint32_t v, uint32_t) { return interior(v) && patch_of[v] == p; });
      for (uint32_t v = 0; v < nv; ++v)
        if (interior(v) && patch_of[v] == p && from_boundary.distance[v] < INFINITY &&
            (centres[p] == kInvalid ||
             from_boundary.distance[v] > from_boundary.distance[centres[p]]))
          centres[p] = v;
    }
    const uint32_t centre = centres[p];
    if (centre == kInvalid) {  // no interior vertex at all
      refine_patch(p);
      continue;
    }
    cut.forced.push_back(centre);
    // The centre's neighbours in CCW order: path k must leave it between path k - 1 and path 0
    // (CCW), with room for the paths still to come, so the paths reach their targets in the
    // targets' order and every sector stays reachable.
    std::vector<uint32_t> ring;
    mesh.for_each_outgoing(centre, [&](uint32_t h) { ring.push_back(mesh.to(h)); });
    const uint32_t nr = uint32_t(ring.size());
    if (nr < 2 * targets.size()) {  // too few neighbours: split the edges opposite it
      mesh.for_each_outgoing(centre,
                             [&](uint32_t h) { refine.push_back(mesh.edge(TriMesh::next(h))); });
      continue;
    }
    std::vector<uint32_t> ring_index(nv, kInvalid);
    for (uint32_t i = 0; i < nr; ++i) ring_index[ring[i]] = i;

    // The paths in the targets' CCW order, starting from each target in turn until they all fit
    // (the first ones can crowd the last: then another start is tried).
    const uint32_t m = uint32_t(targets.size());
    bool done = false;
    for (uint32_t rot = 0; rot < m && !done; ++rot) {
      std::vector<uint32_t> marked, edges;
      uint32_t first0 = kInvalid, last = kInvalid;
      bool fits = true;
      for (uint32_t k = 0; k < m && fits; ++k) {
        const uint32_t target = targets[(rot + k) % m], left = m - 1 - k;
        // Ring position i is on the open CCW arc from path k - 1 to path 0 (the whole ring
        // after the first path), `left` positions short of path 0.
        auto may_leave_by = [&](uint32_t i) {
          if (k == 0) return true;
          const uint32_t arc = first0 == last ? nr : (first0 + nr - last) % nr;
          const uint32_t from_last = (i + nr - last) % nr, to_first = (first0 + nr - i) % nr;
          return from_last >= 1 && to_first >= 1 + left && from_last + to_first == arc;
        };
        const ShortestPaths sp = vertex_dijkstra(
            mesh, {centre},
            [&](uint32_t v, uint32_t e) {
              // The centre's neighbours are entered from the centre only: a path that walked
              // through one would close the wedge a later path needs.
              const uint32_t h = mesh.edge_halfedge(e);
              const uint32_t u = mesh.from(h) == v ? mesh.to(h) : mesh.from(h);
              if (ring_index[v] != kInvalid && (u != centre || !may_leave_by(ring_index[v])))
                return false;
              return v == target || (interior(v) && patch_of[v] == p && !used[v]);
            },
            [&](uint32_t v) { return v == target; });
        const std::vector<uint32_t> path = sp.path_to(target);
        if (path.size() < 2) {
          fits = false;
          break;
        }
        for (std::size_t i = 0; i + 1 < path.size(); ++i) {
          edges.push_back(edge_between(path[i], path[i + 1]));
          if (i > 0) used[path[i]] = 1, marked.push_back(path[i]);
        }
        last = ring_index[path[1]];
        if (k == 0) first0 = last;
      }
      if (fits) {
        for (const uint32_t e : edges) cut_edge[e] = 1;
        done = true;
      } else {
        for (const uint32_t v : marked) used[v] = 0;
      }
    }
    if (!done) refine_patch(p);  // too thin for its paths
    used[centre] = 1;
  }
  if (!refine.empty()) return std::nullopt;
  // The sectors: faces of one patch connected without crossing a cut.
  std::vector<uint32_t> region;
  cut.num_patches = face_regions(
      mesh,
      [&](uint32_t h) {
        return !cut_edge[mesh.edge(h)] &&
               labels[TriMesh::face_of(h)] == labels[TriMesh::face_of(mesh.twin(h))];
      },
      region);
  cut.labels = FaceData<uint32_t>(region);
  return cut;
}

MetaMeshOptions fixed_meta_vertices(std::vector<uint32_t> forced) {
  MetaMeshOptions o;
  o.forced = std::move(forced);
  o.boundary_corner_deg = 1e9;  // exactly the meta-vertices listed, no new boundary corners
  return o;
}

}  // namespace

void split_patches_into_quads(SegmentResult& seg, QuadSplitReport& report) {
  report.patches_before = seg.num_patches;
  std::vector<uint32_t> centres(seg.num_patches, kInvalid);
  for (uint32_t level = 0;; ++level) {
    std::vector<uint32_t> refine;
    report.dropped_inserted = 0;
    std::optional<Cut> cut = cut_patches(seg.refined.mesh, seg.labels, seg.meta, centres, refine,
                                         report.dropped_inserted);
    if (cut) {
      seg.labels = std::move(cut->labels);
      seg.num_patches = cut->num_patches;
      seg.dividing_splits += split_dividing_edges(seg.refined, seg.labels, seg.feature);
      MetaMeshOptions o = fixed_meta_vertices(cut->forced);
      seg.meta = build_meta_mesh(seg.refined.mesh, seg.labels, seg.num_patches, seg.feature, o);
      seg.meta.inserted_vertices = cut->forced;
      check_meta_mesh(seg.refined.mesh, seg.labels, seg.meta);
      measure_geodesic_lengths(seg.refined.mesh, seg.labels, seg.meta);
      for (uint32_t p = 0; p < seg.meta.faces.size(); ++p)
        if (seg.meta.faces[p].cycle.size() != 4)
          throw Error(ErrorKind::internal, "E403",
                      fmt::format("the split left patch {} with {} meta-vertices, not 4", p,
                                  seg.meta.faces[p].cycle.size()));
      report.patches_after = seg.num_patches;
      return;
    }
    if (level == 16 || seg.refined.mesh.num_faces() > 2000000)
      throw Error(ErrorKind::layout, "E403",
                  fmt::format("the patches could not be cut into four-sided ones even after {} "
                              "refinements; use more --patches",
                              level));
    // Refine where the cut did not fit and rebuild the same meta-mesh.
    std::vector<uint32_t> forced;
    for (const MetaVertex& mv : seg.meta.vertices) forced.push_back(mv.vertex);
    std::sort(refine.begin(), refine.end());
    refine.erase(std::unique(refine.begin(), refine.end()), refine.end());
    seg.refined = split_edges(seg.refined, refine, &seg.labels, &seg.feature);
    seg.meta = build_meta_mesh(seg.refined.mesh, seg.labels, seg.num_patches, seg.feature,
                               fixed_meta_vertices(forced));
    ++report.refinements;
  }
}

}  // namespace isoquad
