#include "seg/quad_split.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <optional>

#include <Eigen/Sparse>

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

// Whether a patch was cut or is to be refined first.
enum class WedgeResult { cut, refine_patch };

// A cut path: vertex ids, where ids from the mesh's vertex count on are new vertices (the edge
// points of the cut, in their order).
using Path = std::vector<uint32_t>;

// The cut being built: new vertices on edges and straight cuts across faces.
struct Cuts {
  std::vector<EdgePoint> points;
  std::vector<Chord> chords;
};

// Per-element scratch, kInvalid between patches.
struct Scratch {
  std::vector<uint32_t> local;     // vertex -> index in the patch's map
  std::vector<uint32_t> face_ray;  // face -> the ray through it
};

// The cut paths of one patch, from its centre to its side midpoints (`targets`, CCW), drawn in
// a convex map of the patch (see quad_split.hpp): along mesh edges inside the rays' cells when
// that fits, else along the straight rays (their edge points and chords added to `cuts`).
// Appends the paths to `paths`, or asks for the patch to be refined (a pinched boundary, a
// neighbour outside the patch, numerical trouble). Chooses the centre when `centre` is
// kInvalid. `inside(v)`: v is an interior vertex of the patch; `faces`: the patch's faces;
// `scratch` is clean on entry and on return.
WedgeResult wedge_paths(const TriMesh& mesh, const FaceData<uint32_t>& labels, uint32_t patch,
                        const MetaMesh& meta, uint32_t& centre,
                        const std::vector<uint32_t>& targets, const std::vector<uint32_t>& faces,
                        const std::function<bool(uint32_t)>& inside, Scratch& scratch, Cuts& cuts,
                        std::vector<Path>& paths) {
  const MetaFace& face = meta.faces[patch];
  std::vector<uint32_t>& local = scratch.local;
  std::vector<uint32_t>& face_ray = scratch.face_ray;
  // The boundary loop in CCW order, then the interior vertices.
  std::vector<uint32_t> loop, verts;
  for (const BoundaryItem& it : face.cycle) {
    std::vector<uint32_t> part = meta.edges[it.edge].vertices;
    if (!it.forward) std::reverse(part.begin(), part.end());
    loop.insert(loop.end(), part.begin(), part.end() - 1);
  }
  auto clear = [&] {
    for (const uint32_t v : loop) local[v] = kInvalid;
    for (const uint32_t v : verts) local[v] = kInvalid;
  };
  for (uint32_t i = 0; i < loop.size(); ++i) {
    if (local[loop[i]] != kInvalid) {  // a pinched loop has no circle map
      for (uint32_t j = 0; j < i; ++j) local[loop[j]] = kInvalid;
      return WedgeResult::refine_patch;
    }
    local[loop[i]] = i;
  }
  const uint32_t nb = uint32_t(loop.size());
  for (const uint32_t f : faces)
    for (const uint32_t v : mesh.face(f))
      if (local[v] == kInvalid && inside(v))
        local[v] = nb + uint32_t(verts.size()), verts.push_back(v);
  std::vector<std::array<double, 2>> at(nb + verts.size());
  // The loop on the unit circle with the midpoints evenly spaced (arc length in between), so
  // that seen from the middle of the map the rays are evenly spread whatever the sides' lengths.
  const uint32_t m = uint32_t(targets.size());
  const uint32_t first = local[targets[0]];
  std::vector<double> arc(nb + 1, 0.0);  // from the first midpoint, CCW
  for (uint32_t i = 0; i < nb; ++i)
    arc[i + 1] = arc[i] + norm(mesh.position(loop[(first + i + 1) % nb]) -
                               mesh.position(loop[(first + i) % nb]));
  for (uint32_t k = 0; k < m; ++k) {
    const uint32_t a = (local[targets[k]] + nb - first) % nb;
    const uint32_t b = k + 1 < m ? (local[targets[k + 1]] + nb - first) % nb : nb;
    for (uint32_t i = a; i < b; ++i) {
      const double t = 2 * M_PI * (k + (arc[i] - arc[a]) / (arc[b] - arc[a])) / m;
      at[(first + i) % nb] = {std::cos(t), std::sin(t)};
    }
  }
  // Floater's mean value map: x_i = sum_j w_ij x_j / sum_j w_ij with the positive mean value
  // weights w_ij = (tan(a/2) + tan(b/2)) / |x_j - x_i| (a, b: the angles at i next to edge ij),
  // an embedding like Tutte's uniform map but closer to the surface's own shape.
  const Eigen::Index n = Eigen::Index(verts.size());
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 2);
  bool closed = true;
  for (Eigen::Index i = 0; i < n; ++i) {
    const uint32_t vi = verts[i];
    const Vec3 xi = mesh.position(vi);
    double total = 0;
    auto add = [&](uint32_t vj, double w) {
      const uint32_t j = local[vj];
      total += w;
      if (j == kInvalid)
        closed = false;  // a neighbour outside the patch: not a disk
      else if (j < nb)
        rhs(i, 0) += w * at[j][0], rhs(i, 1) += w * at[j][1];
      else
        entries.emplace_back(i, Eigen::Index(j - nb), -w);
    };
    mesh.for_each_outgoing(vi, [&](uint32_t h) {
      const uint32_t vj = mesh.to(h), vk = mesh.to(TriMesh::next(h));
      const Vec3 a = mesh.position(vj) - xi, b = mesh.position(vk) - xi;
      const double la = std::max(norm(a), 1e-300), lb = std::max(norm(b), 1e-300);
      const double half = 0.5 * angle_between(a, b);
      const double t = std::max(std::tan(half), 1e-12);
      add(vj, t / la);
      add(vk, t / lb);
    });
    entries.emplace_back(i, i, total);
  }
  if (!closed) {
    clear();
    return WedgeResult::refine_patch;
  }
  if (n > 0) {
    Eigen::SparseMatrix<double> A(n, n);
    A.setFromTriplets(entries.begin(), entries.end());
    Eigen::SparseLU<Eigen::SparseMatrix<double>> solver(A);
    const Eigen::MatrixXd x = solver.solve(rhs);
    for (Eigen::Index i = 0; i < n; ++i) at[nb + i] = {x(i, 0), x(i, 1)};
  }
  if (centre == kInvalid) {  // the interior vertex nearest to the middle of the map
    double best = INFINITY;
    for (uint32_t i = 0; i < verts.size(); ++i)
      if (const double d = std::hypot(at[nb + i][0], at[nb + i][1]); d < best)
        best = d, centre = verts[i];
  }
  const std::array<double, 2> c = at[local[centre]];
  // First try paths along mesh edges, each inside the cell of its ray (the interior vertices
  // nearer to that ray than to any other): cells are disjoint, connected and contain their ray
  // (towards its nearest point on the ray, a point's distance to the ray falls faster than to
  // any other), so on a fine enough mesh this needs no new vertex.
  {
    auto distance_to_ray = [&](const std::array<double, 2>& q, uint32_t k) {
      const std::array<double, 2>& e = at[local[targets[k]]];
      const double dx = e[0] - c[0], dy = e[1] - c[1], qx = q[0] - c[0], qy = q[1] - c[1];
      const double t =
          std::clamp((qx * dx + qy * dy) / std::max(dx * dx + dy * dy, 1e-300), 0.0, 1.0);
      return std::hypot(qx - t * dx, qy - t * dy);
    };
    std::vector<uint32_t> cell(verts.size());
    for (uint32_t i = 0; i < verts.size(); ++i) {
      double best = INFINITY;
      for (uint32_t k = 0; k < m; ++k)
        if (const double d = distance_to_ray(at[nb + i], k); d < best) best = d, cell[i] = k;
    }
    std::vector<Path> edge_paths;
    for (uint32_t k = 0; k < m; ++k) {
      const uint32_t target = targets[k];
      const ShortestPaths sp = vertex_dijkstra(
          mesh, {centre},
          [&](uint32_t v, uint32_t) {
            return v == target || (v != centre && local[v] >= nb && cell[local[v] - nb] == k);
          },
          [&](uint32_t v) { return v == target; });
      const std::vector<uint32_t> path = sp.path_to(target);
      if (path.size() < 2) break;
      edge_paths.push_back(path);
    }
    if (edge_paths.size() == m) {
      for (Path& path : edge_paths) paths.push_back(std::move(path));
      clear();
      return WedgeResult::cut;
    }
  }
  // Otherwise cut along the rays themselves. Each ray, from the centre to its midpoint, is a
  // straight segment of the map (the map is convex, so it stays inside and meets the loop only
  // at its end), and in each triangle the map is affine, so the ray is straight on the surface
  // too. It is traced through the triangles: every edge it crosses gets a new vertex there and
  // every triangle it crosses a chord; rays never cross each other, so the cut always fits (a
  // triangle or edge crossed by several rays is cut several times). Numerical trouble (no fan
  // triangle, a step out of the patch, a triangle crossed twice by one ray) refines the patch.
  auto P = [&](uint32_t v) { return at[local[v]]; };
  auto orient = [](const std::array<double, 2>& a, const std::array<double, 2>& b,
                   const std::array<double, 2>& q) {
    return (b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0]);
  };
  const uint32_t nv = mesh.num_vertices();
  const std::size_t points_before = cuts.points.size(), chords_before = cuts.chords.size();
  std::vector<uint32_t> touched_faces;
  bool failed = false;
  std::vector<Path> found;
  const uint32_t max_steps = 4 * uint32_t(faces.size()) + 16;
  auto trace = [&](uint32_t k) {
    const uint32_t target = targets[k];
    const std::array<double, 2> T = P(target), S = c;
    Path path{centre};
    auto fail = [&] {
      failed = true;
      return false;
    };
    auto take_face = [&](uint32_t f) {
      if (face_ray[f] == k) return false;
      face_ray[f] = k;
      touched_faces.push_back(f);
      return true;
    };
    // The new vertex where the ray crosses halfedge h at fraction s from its start.
    auto cross_at = [&](uint32_t h, double s) {
      const uint32_t e = mesh.edge(h);
      const double t =
          std::clamp(mesh.from(mesh.edge_halfedge(e)) == mesh.from(h) ? s : 1 - s, 1e-6, 1 - 1e-6);
      cuts.points.push_back({e, t});
      return nv + uint32_t(cuts.points.size() - 1);
    };
    // The triangle (centre, a, b) by which the ray leaves the centre.
    uint32_t h_out = kInvalid;
    mesh.for_each_outgoing(centre, [&](uint32_t h) {
      const uint32_t a = mesh.to(h), b = mesh.to(TriMesh::next(h));
      if (h_out == kInvalid && orient(S, P(a), T) >= 0 && orient(S, P(b), T) < 0) h_out = h;
    });
    if (h_out == kInvalid) return fail();
    if (mesh.to(h_out) == target) {  // the target is a neighbour of the centre
      path.push_back(target);
      found.push_back(std::move(path));
      return true;
    }
    uint32_t face = TriMesh::face_of(h_out), from = centre, steps = 0;
    take_face(face);
    // Walk across triangles: the ray leaves `face` through halfedge x, from R (right of the
    // ray) to L (left).
    uint32_t x = TriMesh::next(h_out);
    while (true) {
      if (++steps > max_steps) return fail();
      const uint32_t R = mesh.from(x), L = mesh.to(x);
      const double oR = orient(S, T, P(R)), oL = orient(S, T, P(L));
      const uint32_t q = cross_at(x, oR / (oR - oL));
      cuts.chords.push_back({face, from, q});
      path.push_back(q);
      const uint32_t y = mesh.twin(x);
      if (y == kInvalid || labels[TriMesh::face_of(y)] != patch) return fail();
      face = TriMesh::face_of(y), from = q;
      if (!take_face(face)) return fail();
      const uint32_t w = mesh.to(TriMesh::next(y));  // y = L -> R, then R -> w, w -> L
      if (w == target) {
        cuts.chords.push_back({face, q, target});
        path.push_back(target);
        break;
      }
      x = orient(S, T, P(w)) > 0 ? TriMesh::next(y) : TriMesh::next(TriMesh::next(y));
    }
    found.push_back(std::move(path));
    return true;
  };
  for (uint32_t k = 0; k < m && !failed; ++k) trace(k);
  for (const uint32_t f : touched_faces) face_ray[f] = kInvalid;
  clear();
  if (failed) {
    cuts.points.resize(points_before), cuts.chords.resize(chords_before);
    return WedgeResult::refine_patch;
  }
  for (Path& path : found) paths.push_back(std::move(path));
  return WedgeResult::cut;
}

struct Cut {
  RefinedMesh refined;  // the surface with the rays' crossings split
  EdgeData<char> feature;
  FaceData<uint32_t> labels;
  uint32_t num_patches = 0;
  std::vector<uint32_t> forced;  // meta-vertices of the split meta-mesh
};

// The cut of every patch along paths from its centre to its side midpoints; nothing if some
// side has no midpoint, some patch no centre, or some path is blocked.
// `centres` keeps each patch's centre across refinements (vertex ids survive edge splits).
std::optional<Cut> cut_patches(const RefinedMesh& refined, const FaceData<uint32_t>& labels,
                               const EdgeData<char>& feature, const MetaMesh& meta,
                               std::vector<uint32_t>& centres, std::vector<uint32_t>& refine,
                               uint32_t& dropped) {
  const TriMesh& mesh = refined.mesh;
  const std::vector<char> keep = kept_meta_vertices(meta, dropped);
  std::vector<uint32_t> side_of;
  const std::vector<Side> sides = sides_of(mesh, meta, keep, side_of);
  // Where something does not fit, `refine` collects the edges to split before the next try.
  auto edge_between = [&](uint32_t a, uint32_t b) {  // either way: on the mesh boundary
    uint32_t e = kInvalid;                           // only one halfedge exists
    mesh.for_each_outgoing(a, [&](uint32_t h) {
      if (mesh.to(h) == b) e = mesh.edge(h);
    });
    mesh.for_each_outgoing(b, [&](uint32_t h) {
      if (mesh.to(h) == a) e = mesh.edge(h);
    });
    return e;
  };
  for (const Side& s : sides)
    if (s.midpoint == kInvalid)  // a side of one mesh edge: split it
      refine.push_back(edge_between(s.vertices.front(), s.vertices.back()));
  if (!refine.empty()) return std::nullopt;
  std::vector<std::vector<uint32_t>> patch_faces(meta.faces.size());
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) patch_faces[labels[f]].push_back(f);
  auto refine_patch = [&](uint32_t p) {
    for (const uint32_t f : patch_faces[p])
      for (uint32_t i = 0; i < 3; ++i) refine.push_back(mesh.edge(3 * f + i));
  };
  // Interior vertices and their patch.
  const uint32_t nv = mesh.num_vertices();
  std::vector<uint32_t> patch_of(nv, kInvalid);
  for (uint32_t f = 0; f < mesh.num_faces(); ++f)
    for (const uint32_t v : mesh.face(f)) patch_of[v] = labels[f];
  Scratch scratch{std::vector<uint32_t>(nv, kInvalid),
                  std::vector<uint32_t>(mesh.num_faces(), kInvalid)};
  auto interior = [&](uint32_t v) {
    return meta.vertex_meta_vertex[v] == kInvalid && meta.vertex_meta_edge[v] == kInvalid &&
           !mesh.is_boundary_vertex(v);
  };
  Cut cut;
  for (uint32_t v = 0; v < meta.vertices.size(); ++v)
    if (keep[v]) cut.forced.push_back(meta.vertices[v].vertex);
  for (const Side& s : sides) cut.forced.push_back(s.midpoint);
  std::vector<Path> paths;
  Cuts cuts;
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
    const auto inside = [&](uint32_t v) { return interior(v) && patch_of[v] == p; };
    if (std::none_of(patch_faces[p].begin(), patch_faces[p].end(), [&](uint32_t f) {
          const Tri& t = mesh.face(f);
          return inside(t[0]) || inside(t[1]) || inside(t[2]);
        })) {  // no interior vertex to be the centre
      refine_patch(p);
      continue;
    }
    uint32_t& centre = centres[p];
    switch (wedge_paths(mesh, labels, p, meta, centre, targets, patch_faces[p], inside, scratch,
                        cuts, paths)) {
      case WedgeResult::cut:
        cut.forced.push_back(centre);
        break;
      case WedgeResult::refine_patch:
        refine_patch(p);
        break;
    }
  }
  if (!refine.empty()) return std::nullopt;
  // Cut the crossed triangles, then mark the paths' edges.
  cut.labels = labels;
  cut.feature = feature;
  cut.refined = cut_along_chords(refined, cuts.points, cuts.chords, &cut.labels, &cut.feature);
  const TriMesh& out = cut.refined.mesh;
  std::vector<char> cut_edge(out.num_edges(), 0);
  for (const Path& path : paths)
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
      uint32_t e = kInvalid;
      out.for_each_outgoing(path[i], [&](uint32_t h) {
        if (out.to(h) == path[i + 1]) e = out.edge(h);
      });
      if (e == kInvalid)
        throw Error(
            ErrorKind::internal, "E403",
            fmt::format("a cut path has no edge from vertex {} to {}", path[i], path[i + 1]));
      cut_edge[e] = 1;
    }
  // The sectors: faces of one patch connected without crossing a cut.
  std::vector<uint32_t> region;
  cut.num_patches = face_regions(
      out,
      [&](uint32_t h) {
        return !cut_edge[out.edge(h)] &&
               cut.labels[TriMesh::face_of(h)] == cut.labels[TriMesh::face_of(out.twin(h))];
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
    std::optional<Cut> cut = cut_patches(seg.refined, seg.labels, seg.feature, seg.meta, centres,
                                         refine, report.dropped_inserted);
    if (cut) {
      seg.refined = std::move(cut->refined);
      seg.feature = std::move(cut->feature);
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
    if (level == 12 || seg.refined.mesh.num_faces() > 1000000)
      throw Error(ErrorKind::layout, "E403",
                  fmt::format("the patches could not be cut into four-sided ones even after {} "
                              "refinements; use more --patches",
                              level));
    // Refine where the cut did not fit and rebuild the same meta-mesh.
    std::vector<uint32_t> forced;
    for (const MetaVertex& mv : seg.meta.vertices) forced.push_back(mv.vertex);
    std::sort(refine.begin(), refine.end());
    refine.erase(std::unique(refine.begin(), refine.end()), refine.end());
    while (!refine.empty() && refine.back() == kInvalid) refine.pop_back();
    if (refine.empty())
      throw Error(
          ErrorKind::internal, "E403",
          "the patches could not be cut into four-sided ones and nothing is left to refine");
    seg.refined = split_edges(seg.refined, refine, &seg.labels, &seg.feature);
    seg.meta = build_meta_mesh(seg.refined.mesh, seg.labels, seg.num_patches, seg.feature,
                               fixed_meta_vertices(forced));
    ++report.refinements;
  }
}

}  // namespace isoquad
