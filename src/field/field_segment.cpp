#include "field/field_segment.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "core/face_regions.hpp"
#include "isoquad/error.hpp"
#include "layout/divide_split.hpp"
#include "seg/patch_topology.hpp"

namespace isoquad {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// An edge point this close to an end of its edge (in fractions of the edge) is that vertex.
constexpr double kSnap = 1e-6;

// The traces' points as vertices of the cut mesh: mesh vertices (sources, snapped points) or
// edge points shared by every trace that crosses the edge there.
struct Nodes {
  const TriMesh& mesh;
  std::vector<EdgePoint> points;
  std::vector<std::vector<std::pair<double, uint32_t>>> on_edge;  // per edge: (fraction, node)

  explicit Nodes(const TriMesh& m) : mesh(m), on_edge(m.num_edges()) {}

  uint32_t of(EdgePoint p) {
    const uint32_t h = mesh.edge_halfedge(p.edge);
    if (p.fraction < kSnap) return mesh.from(h);
    if (p.fraction > 1 - kSnap) return mesh.to(h);
    for (const auto& [t, id] : on_edge[p.edge])
      if (std::abs(t - p.fraction) < 1e-9) return id;
    const uint32_t id = mesh.num_vertices() + uint32_t(points.size());
    points.push_back(p);
    on_edge[p.edge].push_back({p.fraction, id});
    return id;
  }

  // The edge a node lies on (kInvalid for a mesh vertex) and its fraction there.
  std::pair<uint32_t, double> where(uint32_t node) const {
    if (node < mesh.num_vertices()) return {kInvalid, 0};
    const EdgePoint& p = points[node - mesh.num_vertices()];
    return {p.edge, p.fraction};
  }
};

// The node a trace ending inside face f (on trace `on`) ends at: the nearer end, on an edge of
// f or at a vertex, of `on`'s passage through f.
std::optional<uint32_t> junction_node(const CrossField& cf, const TraceResult& tr, const Trace& t,
                                      uint32_t on, Nodes& nodes) {
  const uint32_t f = t.faces.back();
  const Vec3 x = position_on(cf.surface, t.points.back());
  const Trace& other = tr.traces[on];
  if (other.faces.empty()) return other.source;  // it met the other head-on as it left its source
  std::optional<uint32_t> best;
  double nearest = INFINITY;
  for (std::size_t j = 0; j < other.faces.size(); ++j) {
    if (other.faces[j] != f) continue;
    for (const std::size_t k : {j, j + 1}) {
      const bool vertex = k == 0, edge = other.on_edge[k].edge != kInvalid;
      if (!vertex && !edge) continue;
      const double d = norm(position_on(cf.surface, other.points[k]) - x);
      if (d >= nearest) continue;
      nearest = d;
      best = vertex ? other.source : nodes.of(other.on_edge[k]);
    }
  }
  return best;
}

// Whether nodes a and b lie on one edge of face f (a chord between them would run along it).
bool along_an_edge(const TriMesh& m, const Nodes& nodes, uint32_t f, uint32_t a, uint32_t b) {
  for (uint32_t i = 0; i < 3; ++i) {
    const uint32_t h = 3 * f + i, e = m.edge(h);
    auto on = [&](uint32_t n) {
      return n == m.from(h) || n == m.to(h) || nodes.where(n).first == e;
    };
    if (on(a) && on(b)) return true;
  }
  return false;
}

struct Embedded {
  RefinedMesh refined;
  EdgeData<char> feature;
  std::vector<std::pair<uint32_t, uint32_t>> seams;  // node pairs joined by a trace
  std::vector<uint32_t> nodes;  // the traces' sources and ends, as vertices of `refined`
  std::vector<uint32_t> sources;
  // The last step of each trace that ends on a track, a feature or the boundary: its end and the
  // node before it. A trace joined head-on to another continues it straight.
  struct Stem {
    uint32_t end, before;
    bool straight;
  };
  std::vector<Stem> stems;
};

std::optional<Embedded> embed(const RefinedMesh& base, const CrossField& cf, const TraceResult& tr,
                              std::string& failure) {
  const TriMesh& m = base.mesh;
  Nodes nodes(m);
  std::vector<Chord> chords;
  Embedded out;
  for (std::size_t id = 0; id < tr.traces.size(); ++id) {
    const Trace& t = tr.traces[id];
    if (t.end == TraceEnd::cap || t.end == TraceEnd::sink) {
      failure = fmt::format("trace {} from vertex {} found no end", id, t.source);
      return std::nullopt;
    }
    std::vector<uint32_t> path{t.source};
    for (std::size_t k = 1; k < t.points.size(); ++k) {
      if (t.on_edge[k].edge != kInvalid) {
        path.push_back(nodes.of(t.on_edge[k]));
        continue;
      }
      const auto j = junction_node(cf, tr, t, t.end_trace, nodes);
      if (!j) {
        failure = fmt::format("trace {} ends inside a face its track does not cross", id);
        return std::nullopt;
      }
      path.push_back(*j);
    }
    for (std::size_t k = 0; k + 1 < path.size(); ++k) {
      const uint32_t a = path[k], b = path[k + 1];
      if (a == b) continue;
      out.seams.push_back({a, b});
      if (!along_an_edge(m, nodes, t.faces[k], a, b)) chords.push_back({t.faces[k], a, b});
    }
    out.nodes.push_back(path.front());
    out.nodes.push_back(path.back());
    out.sources.push_back(path.front());
    // The last step that moved (a trace may end where it entered its last face).
    std::size_t last = path.size() - 1;
    while (last > 0 && path[last - 1] == path.back()) --last;
    if (last > 0) {
      const bool joined = t.end == TraceEnd::track && t.end_trace != kInvalid &&
                          tr.traces[t.end_trace].end_trace == id;
      out.stems.push_back({path.back(), path[last - 1], joined});
    }
  }
  out.feature = cf.feature;
  out.refined = cut_along_chords(base, nodes.points, chords, nullptr, &out.feature);
  return out;
}

// The cut mesh's edges on the traces: each seam pair is an edge, or a run of pieces of one split
// edge (when the trace ran along an edge of the mesh).
EdgeData<char> seam_edges(const TriMesh& m,
                          const std::vector<std::pair<uint32_t, uint32_t>>& seams) {
  EdgeData<char> seam(m.num_edges(), 0);
  auto edge_between = [&](uint32_t a, uint32_t b) {
    uint32_t found = kInvalid;
    m.for_each_outgoing(a, [&](uint32_t h) {
      if (m.to(h) == b) found = m.edge(h);
    });
    if (found == kInvalid)
      m.for_each_outgoing(b, [&](uint32_t h) {
        if (m.to(h) == a) found = m.edge(h);
      });
    return found;
  };
  for (const auto& [a, b] : seams) {
    // The straight run from a to b along mesh edges: from a, the edge most nearly towards b.
    uint32_t at = a;
    for (int guard = 0; at != b && guard < 1000; ++guard) {
      if (const uint32_t e = edge_between(at, b); e != kInvalid) {
        seam[e] = 1;
        break;
      }
      const Vec3 to_b = normalized(m.position(b) - m.position(at));
      uint32_t next = kInvalid;
      double best = 1 - 1e-9;
      auto consider = [&](uint32_t w) {
        const double c = dot(normalized(m.position(w) - m.position(at)), to_b);
        if (c > best) best = c, next = w;
      };
      m.for_each_outgoing(at, [&](uint32_t h) { consider(m.to(h)); });
      if (m.is_boundary_vertex(at)) {
        // The boundary edge into `at` is not an outgoing halfedge of it.
        m.for_each_outgoing(at, [&](uint32_t h) {
          if (m.twin(TriMesh::prev(h)) == kInvalid) consider(m.from(TriMesh::prev(h)));
        });
      }
      if (next == kInvalid) break;
      seam[edge_between(at, next)] = 1;
      at = next;
    }
  }
  return seam;
}

// The point at arc length `reach` along a polyline of mesh vertices (its far end if shorter).
Vec3 point_along(const TriMesh& mesh, const std::vector<uint32_t>& path, bool reverse,
                 double reach) {
  const std::size_t n = path.size();
  auto at = [&](std::size_t k) { return mesh.position(path[reverse ? n - 1 - k : k]); };
  double left = reach;
  for (std::size_t k = 0; k + 1 < n; ++k) {
    const double len = norm(at(k + 1) - at(k));
    if (len >= left) return at(k) + (left / len) * (at(k + 1) - at(k));
    left -= len;
  }
  return at(n - 1);
}

// How many quarter turns patch p makes at vertex v, where the traces say it: 1 at a trace's
// source (every sector between consecutive rays of a node is a quarter), at a stem's end 1 on
// the two sides of the stem and 2 on the track's far side, 2 where two traces of one separatrix
// were joined. 0 where the traces say nothing.
struct TraceTurns {
  const TriMesh& mesh;
  const FaceData<uint32_t>& labels;
  std::vector<char> source;
  std::vector<std::vector<Embedded::Stem>> stems;  // per vertex

  TraceTurns(const TriMesh& m, const FaceData<uint32_t>& l, const Embedded& em)
      : mesh(m), labels(l), source(m.num_vertices(), 0), stems(m.num_vertices()) {
    for (uint32_t v : em.sources) source[v] = 1;
    for (const Embedded::Stem& s : em.stems) stems[s.end].push_back(s);
  }

  int operator()(uint32_t v, uint32_t p) const {
    if (source[v]) return 1;
    if (stems[v].empty()) return 0;
    for (const Embedded::Stem& s : stems[v])
      if (s.straight) return 2;
    // The stem's edge at v: the edge from v most nearly towards the node before the end.
    for (const Embedded::Stem& s : stems[v]) {
      const Vec3 to = normalized(mesh.position(s.before) - mesh.position(v));
      uint32_t best = kInvalid;
      double cos = -2;
      mesh.for_each_outgoing(v, [&](uint32_t h) {
        const double c = dot(normalized(mesh.position(mesh.to(h)) - mesh.position(v)), to);
        if (c > cos) cos = c, best = h;
      });
      if (best == kInvalid) continue;
      const uint32_t tw = mesh.twin(best);
      if (labels[TriMesh::face_of(best)] == p ||
          (tw != kInvalid && labels[TriMesh::face_of(tw)] == p))
        return 1;
    }
    return 2;
  }
};

// Per patch, the cycle items at which it turns by a quarter (its corners), or empty if some
// patch does not have exactly four or turns by three quarters somewhere. A patch's angle at a
// meta-vertex is measured between its two sides at a distance of about h/2 (or half the side):
// a traced side bends at the scale of a triangle where it meets a track, so the angle of the
// triangles at the vertex says little.
std::optional<std::vector<std::array<uint32_t, 4>>> patch_corners(const TriMesh& mesh,
                                                                  const FaceData<uint32_t>& labels,
                                                                  const MetaMesh& meta, double h,
                                                                  const TraceTurns& turns,
                                                                  std::string& failure) {
  std::vector<std::array<uint32_t, 4>> corners(meta.faces.size());
  for (uint32_t p = 0; p < meta.faces.size(); ++p) {
    const MetaFace& face = meta.faces[p];
    const std::size_t n = face.cycle.size();
    std::vector<uint32_t> found;
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t v = meta.vertices[face.start_vertex(i, meta.edges)].vertex;
      if (const int known = turns(v, p)) {
        if (known == 1) found.push_back(i);
        continue;
      }
      const BoundaryItem& out = face.cycle[i];
      const BoundaryItem& in = face.cycle[(i + n - 1) % n];
      const MetaEdge& eo = meta.edges[out.edge];
      const MetaEdge& ei = meta.edges[in.edge];
      const Vec3 x = mesh.position(v);
      const Vec3 b =
          point_along(mesh, eo.vertices, !out.forward, std::min(h / 2, eo.length / 2)) - x;
      const Vec3 a = point_along(mesh, ei.vertices, in.forward, std::min(h / 2, ei.length / 2)) - x;
      Vec3 normal;
      mesh.for_each_outgoing(v, [&](uint32_t he) {
        const uint32_t f = TriMesh::face_of(he);
        if (labels[f] == p) normal += mesh.face_area(f) * mesh.face_normal(f);
      });
      // The patch lies to the left of its cycle: its angle turns from b counter-clockwise to a.
      double angle = std::atan2(dot(normalized(normal), cross(b, a)), dot(b, a));
      if (angle <= 0) angle += 2 * std::numbers::pi;
      const long q = std::lround(angle / (std::numbers::pi / 2));
      if (q >= 3) {
        failure = fmt::format("patch {} turns by {} quarters at vertex {}", p, q, v);
        return std::nullopt;
      }
      if (q <= 1) found.push_back(i);
    }
    if (found.size() != 4) {
      failure = fmt::format("patch {} has {} corners", p, found.size());
      return std::nullopt;
    }
    std::copy(found.begin(), found.end(), corners[p].begin());
  }
  return corners;
}

}  // namespace

FieldSegmentation field_segment(const TriMesh& mesh, const EdgeData<char>& feature, double h,
                                FieldLayoutLog& log) {
  auto t0 = Clock::now();
  EdgeData<char> split_feature = feature;
  const RefinedMesh base = split_constraint_conflicts(identity_refinement(mesh), split_feature);
  CrossFieldOptions fo;
  fo.edge_length = h;
  const CrossField cf = compute_cross_field(base.mesh, split_feature, fo);
  log.singularities = uint32_t(cf.singular.size());
  log.field_seconds = seconds_since(t0);

  t0 = Clock::now();
  const TraceResult tr = trace_separatrices(cf, {.edge_length = h});
  log.nodes = uint32_t(tr.nodes.size());
  log.traces = uint32_t(tr.traces.size());
  for (const Trace& t : tr.traces) log.t_junctions += t.end == TraceEnd::track;
  log.trace_seconds = seconds_since(t0);

  t0 = Clock::now();
  FieldSegmentation out;
  std::optional<Embedded> em = embed(base, cf, tr, log.failure);
  if (!em) return out;
  const TriMesh& cut = em->refined.mesh;
  const EdgeData<char> seam = seam_edges(cut, em->seams);
  SegmentResult& seg = out.seg;
  std::vector<uint32_t> region;
  seg.num_patches = face_regions(
      cut, [&](uint32_t he) { return !seam[cut.edge(he)] && !em->feature[cut.edge(he)]; },
      [](uint32_t) { return true; }, region);
  seg.labels = FaceData<uint32_t>(std::move(region));
  log.patches = seg.num_patches;
  const std::vector<PatchTopology> topo = patch_topology(cut, seg.labels, seg.num_patches);
  for (uint32_t p = 0; p < seg.num_patches; ++p)
    if (!topo[p].is_disk()) {
      log.failure = fmt::format("patch {} is not a disk ({} boundary loops, euler {})", p,
                                topo[p].boundary_loops, topo[p].euler());
      seg.refined = std::move(em->refined);
      seg.feature = std::move(em->feature);
      return out;
    }

  MetaMeshOptions mo;
  mo.forced = em->nodes;
  std::sort(mo.forced.begin(), mo.forced.end());
  mo.forced.erase(std::unique(mo.forced.begin(), mo.forced.end()), mo.forced.end());
  seg.refined = std::move(em->refined);
  seg.feature = std::move(em->feature);
  seg.dividing_splits = split_dividing_edges(seg.refined, seg.labels, seg.feature);
  try {
    seg.meta = build_meta_mesh(seg.refined.mesh, seg.labels, seg.num_patches, seg.feature, mo);
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::layout) throw;
    log.failure = fmt::format("the traced patches give no meta-mesh: {}", e.what());
    return out;
  }
  try {
    check_meta_mesh(seg.refined.mesh, seg.labels, seg.meta);
  } catch (const Error& e) {
    // A seam loop without a node, or a patch bordering itself: a layout the tracing should not
    // have made, reported as such (the JSON's fallback reason) rather than stopping the run.
    log.failure = fmt::format("the traced patches give an inconsistent meta-mesh: {}", e.what());
    return out;
  }
  measure_geodesic_lengths(seg.refined.mesh, seg.labels, seg.meta);
  seg.vsa_labels = seg.labels;
  const TraceTurns turns(seg.refined.mesh, seg.labels, *em);
  auto corners = patch_corners(seg.refined.mesh, seg.labels, seg.meta, h, turns, log.failure);
  log.embed_seconds = seconds_since(t0);
  if (corners) out.corners = std::move(*corners);
  return out;
}

}  // namespace isoquad
