#include "field/field_segment.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <queue>

#include "core/face_regions.hpp"
#include "isoquad/error.hpp"
#include "layout/divide_split.hpp"
#include "layout/flow.hpp"
#include "layout/quantize.hpp"
#include "seg/disk_patches.hpp"
#include "seg/patch_topology.hpp"

namespace isoquad {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// An edge point this close to an end of its edge (in fractions of the edge) is that vertex: a
// closer cut would leave a sliver triangle the locked map cannot certify.
constexpr double kSnap = 0.02;

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
      const bool source = k == 0, edge = other.on_edge[k].edge != kInvalid;
      const bool node = other.end == TraceEnd::node && k + 1 == other.points.size();
      if (!source && !edge && !node) continue;
      const double d = norm(position_on(cf.surface, other.points[k]) - x);
      if (d >= nearest) continue;
      nearest = d;
      best = source ? other.source : node ? other.end_vertex : nodes.of(other.on_edge[k]);
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
  std::vector<uint32_t> seam_trace;                  // per seam, its trace
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
      if (t.end == TraceEnd::node && k + 1 == t.points.size()) {
        path.push_back(t.end_vertex);
        continue;
      }
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
      out.seam_trace.push_back(uint32_t(id));
      if (!along_an_edge(m, nodes, t.faces[k], a, b)) chords.push_back({t.faces[k], a, b});
    }
    out.nodes.push_back(path.front());
    out.nodes.push_back(path.back());
    out.sources.push_back(path.front());
    // A connection ends at a node: every sector there is a quarter, as at a source.
    if (t.end == TraceEnd::node) {
      out.sources.push_back(path.back());
      continue;
    }
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
EdgeData<char> seam_edges(const TriMesh& m, const std::vector<std::pair<uint32_t, uint32_t>>& seams,
                          const std::vector<uint32_t>& seam_trace,
                          std::vector<std::pair<uint32_t, uint32_t>>& vertex_traces) {
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
  for (std::size_t k = 0; k < seams.size(); ++k) {
    const auto [a, b] = seams[k];
    // The straight run from a to b along mesh edges: from a, the edge most nearly towards b.
    uint32_t at = a;
    vertex_traces.push_back({a, seam_trace[k]});
    vertex_traces.push_back({b, seam_trace[k]});
    for (int guard = 0; at != b && guard < 1000; ++guard) {
      if (at != a) vertex_traces.push_back({at, seam_trace[k]});
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
  std::sort(vertex_traces.begin(), vertex_traces.end());
  vertex_traces.erase(std::unique(vertex_traces.begin(), vertex_traces.end()), vertex_traces.end());
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

  TraceTurns(const TriMesh& m, const FaceData<uint32_t>& l, const Embedded& em,
             const std::vector<uint32_t>& partial)
      : mesh(m), labels(l), source(m.num_vertices(), 0), stems(m.num_vertices()) {
    for (uint32_t v : em.sources) source[v] = 1;
    // A node with a deleted ray has a sector of two quarters: the angles tell which.
    for (uint32_t v : partial) source[v] = 0;
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

// The field's quarter turn at vertex v, as an angle on `mesh`: a right angle on a feature or the
// boundary (the field follows them), else the cone angle (the sum of the triangle angles at v)
// over the field's arm count there, 4 - 4 I_v (three arms of 120 degrees at a +1/4 singularity
// of a flat surface, five of 72 at a -1/4 one).
double quarter_angle(const TriMesh& mesh, const EdgeData<char>& feature,
                     const VertexData<int32_t>& index4, uint32_t v) {
  constexpr double kRight = std::numbers::pi / 2;
  if (mesh.is_boundary_vertex(v)) return kRight;
  bool on_feature = false;
  double cone = 0;
  mesh.for_each_outgoing(v, [&](uint32_t he) {
    on_feature = on_feature || feature[mesh.edge(he)];
    const Vec3 e1 = mesh.position(mesh.to(he)) - mesh.position(v);
    const Vec3 e2 = mesh.position(mesh.from(TriMesh::prev(he))) - mesh.position(v);
    cone += std::atan2(norm(cross(e1, e2)), dot(e1, e2));
  });
  const int32_t arms = v < index4.size() ? 4 - index4[v] : 4;
  return on_feature || arms <= 0 ? kRight : cone / arms;
}

// Per patch, the cycle items at which it turns by a quarter (its corners); kFreeCorners for a
// patch the disk repair changed, or that is not four-cornered in the field's sense. Two readings
// of each turn: the traces' rules (TraceTurns, where they say something) and the patch's angle
// between its two sides at a distance of about h/2 (or half the side; a traced side bends at the
// scale of a triangle where it meets a track, so the triangles' angle at the vertex says little),
// in the field's quarters there. The rules hold where the traces met as the field says; where a
// stem met its track obliquely (two traces of one family converging near a singularity) or a
// singularity's arm was merged, they miscount and the angles do not. The rules decide when they
// give four corners, else the angles when they give four and no reflex turn.
struct PatchCorners {
  std::vector<std::array<uint32_t, 4>> corners;
  std::vector<char> by_angles;
};

PatchCorners patch_corners(const TriMesh& mesh, const FaceData<uint32_t>& labels,
                           const MetaMesh& meta, double h, const TraceTurns& turns,
                           const std::vector<char>& repaired, const EdgeData<char>& feature,
                           const VertexData<int32_t>& index4) {
  PatchCorners out;
  out.corners.assign(meta.faces.size(), kFreeCorners);
  out.by_angles.assign(meta.faces.size(), 0);
  for (uint32_t p = 0; p < meta.faces.size(); ++p) {
    if (repaired[p]) continue;
    const MetaFace& face = meta.faces[p];
    const std::size_t n = face.cycle.size();
    std::vector<uint32_t> by_rules, by_angles;
    bool rules_reflex = false, angles_reflex = false;
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t v = meta.vertices[face.start_vertex(i, meta.edges)].vertex;
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
      const long q = std::lround(angle / quarter_angle(mesh, feature, index4, v));
      angles_reflex = angles_reflex || q >= 3;
      if (q <= 1) by_angles.push_back(i);
      const int known = turns(v, p);
      rules_reflex = rules_reflex || (!known && q >= 3);
      if (known ? known == 1 : q <= 1) by_rules.push_back(i);
    }
    if (by_rules.size() == 4 && !rules_reflex) {
      std::copy(by_rules.begin(), by_rules.end(), out.corners[p].begin());
    } else if (by_angles.size() == 4 && !angles_reflex) {
      std::copy(by_angles.begin(), by_angles.end(), out.corners[p].begin());
      out.by_angles[p] = 1;
    }
  }
  return out;
}

// Which patches of `after` are not one traced patch of `before`, face for face.
std::vector<char> changed_patches(const FaceData<uint32_t>& before, uint32_t n_before,
                                  const FaceData<uint32_t>& after, uint32_t n_after) {
  std::vector<uint32_t> was(n_after, kInvalid), now(n_before, kInvalid);
  std::vector<char> changed(n_after, 0);
  for (uint32_t f = 0; f < after.size(); ++f) {
    const uint32_t a = after[f], b = before[f];
    if (was[a] == kInvalid) was[a] = b;
    if (now[b] == kInvalid) now[b] = a;
    if (was[a] != b) changed[a] = 1;
    if (now[b] != a) changed[a] = changed[now[b]] = 1;
  }
  return changed;
}

// Seeds for the patches that are not disks (FIELD_LAYOUT.md §4), at most kMaxSeeded of them: in
// each, the vertex farthest from its boundary (or, with no boundary, from its first vertex), and
// the vertex farthest from that one, both regular interior vertices of the field's surface off
// the features. Their traces close loops around the handle or join the two seeds, in pairs far
// apart, so that no patch borders itself.
std::vector<uint32_t> handle_seeds(const TriMesh& cut, const FaceData<uint32_t>& labels,
                                   uint32_t patches, const EdgeData<char>& feature,
                                   const CrossField& cf) {
  constexpr uint32_t kMaxSeeded = 8;
  const std::vector<PatchTopology> topo = patch_topology(cut, labels, patches);
  std::vector<uint32_t> seeds;
  uint32_t seeded = 0;
  const uint32_t base_vertices = cf.surface.num_vertices();
  for (uint32_t p = 0; p < patches; ++p) {
    if (topo[p].is_disk() || topo[p].faces == 0) continue;
    if (++seeded > kMaxSeeded) return {};
    // Vertices inside p: every face around them in p, no feature edge at them.
    auto inside = [&](uint32_t v) {
      if (cut.is_boundary_vertex(v)) return false;
      bool in = true;
      cut.for_each_outgoing(v, [&](uint32_t he) {
        in = in && labels[TriMesh::face_of(he)] == p && !feature[cut.edge(he)];
      });
      return in;
    };
    auto farthest = [&](const std::vector<uint32_t>& from) {
      std::vector<double> dist(cut.num_vertices(), INFINITY);
      using Item = std::pair<double, uint32_t>;
      std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
      for (uint32_t v : from) queue.push({dist[v] = 0, v});
      while (!queue.empty()) {
        const auto [d, v] = queue.top();
        queue.pop();
        if (d > dist[v]) continue;
        cut.for_each_outgoing(v, [&](uint32_t he) {
          if (labels[TriMesh::face_of(he)] != p) return;
          const uint32_t w = cut.to(he);
          const double dw = d + norm(cut.position(w) - cut.position(v));
          if (dw < dist[w]) queue.push({dist[w] = dw, w});
        });
      }
      uint32_t best = kInvalid;
      for (uint32_t v = 0; v < base_vertices; ++v)
        if (dist[v] < INFINITY && cf.index4[v] == 0 && inside(v) &&
            (best == kInvalid || dist[v] > dist[best]))
          best = v;
      return best;
    };
    std::vector<uint32_t> edge_of_patch;
    uint32_t first = kInvalid;
    for (uint32_t f = 0; f < cut.num_faces(); ++f) {
      if (labels[f] != p) continue;
      for (uint32_t v : cut.face(f)) {
        if (first == kInvalid || v < first) first = v;
        if (!inside(v)) edge_of_patch.push_back(v);
      }
    }
    if (edge_of_patch.empty()) edge_of_patch.push_back(first);
    const uint32_t a = farthest(edge_of_patch);
    if (a == kInvalid) continue;
    seeds.push_back(a);
    if (const uint32_t b = farthest({a}); b != kInvalid && b != a) seeds.push_back(b);
  }
  std::sort(seeds.begin(), seeds.end());
  seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
  return seeds;
}

// One traced layout: the segmentation, the traces, and the trace each seam vertex of the
// segmentation's mesh lies on.
struct Traced {
  FieldSegmentation out;
  TraceResult tr;
  std::vector<std::pair<uint32_t, uint32_t>> vertex_traces;  // (vertex, trace), sorted
};

// The traces of `to` embedded, traced again with seeds if some patch is not a disk, made disks,
// and given their meta-mesh and corners. log.failure says why where it cannot be used.
Traced trace_layout(const RefinedMesh& base, const CrossField& cf, TraceOptions to, double h,
                    FieldLayoutLog& log) {
  Traced traced;
  FieldSegmentation& out = traced.out;
  SegmentResult& seg = out.seg;
  TraceResult& tr = traced.tr;
  std::optional<Embedded> em;
  EdgeData<char> seam;
  to.seeds.clear();
  log.failure.clear();
  for (int pass = 0; pass < 2; ++pass) {
    auto t0 = Clock::now();
    tr = trace_separatrices(cf, to);
    log.nodes = uint32_t(tr.nodes.size());
    log.traces = uint32_t(tr.traces.size());
    log.t_junctions = 0;
    for (const Trace& t : tr.traces) log.t_junctions += t.end == TraceEnd::track;
    log.connections = tr.connections;
    log.deleted = tr.deleted;
    log.rounds = tr.rounds;
    log.trace_seconds += seconds_since(t0);

    t0 = Clock::now();
    em = embed(base, cf, tr, log.failure);
    if (!em) return traced;
    const TriMesh& cut = em->refined.mesh;
    traced.vertex_traces.clear();
    seam = seam_edges(cut, em->seams, em->seam_trace, traced.vertex_traces);
    std::vector<uint32_t> region;
    seg.num_patches = face_regions(
        cut, [&](uint32_t he) { return !seam[cut.edge(he)] && !em->feature[cut.edge(he)]; },
        [](uint32_t) { return true; }, region);
    seg.labels = FaceData<uint32_t>(std::move(region));
    log.embed_seconds += seconds_since(t0);
    if (pass > 0) break;
    to.seeds = handle_seeds(cut, seg.labels, seg.num_patches, em->feature, cf);
    log.seeds = uint32_t(to.seeds.size());
    if (to.seeds.empty()) break;
  }
  const auto t0 = Clock::now();
  const TriMesh& cut = em->refined.mesh;
  // Patches that are not disks (a handle no trace crossed), pinched, or too small for four
  // corners (between two traces that nearly met) are made disks as VSA's are.
  const FaceData<uint32_t> labels_traced = seg.labels;
  const uint32_t traced_patches = seg.num_patches;
  try {
    seg.num_patches = make_disk_patches(cut, seg.labels, seg.repair);
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::unsupported_topology) throw;
    log.failure = fmt::format("the traced patches cannot be made disks: {}", e.what());
    seg.refined = std::move(em->refined);
    seg.feature = std::move(em->feature);
    return traced;
  }
  log.patches = seg.num_patches;
  const std::vector<char> repaired =
      changed_patches(labels_traced, traced_patches, seg.labels, seg.num_patches);
  log.repaired_patches = uint32_t(std::count(repaired.begin(), repaired.end(), 1));

  MetaMeshOptions mo;
  // The traces' ends, where they still lie on a patch boundary (the disk repair may have merged
  // the patches on both sides of a trace).
  for (uint32_t v : em->nodes) {
    uint32_t first = kInvalid;
    bool on_seam = cut.is_boundary_vertex(v);
    cut.for_each_outgoing(v, [&](uint32_t he) {
      const uint32_t l = seg.labels[TriMesh::face_of(he)];
      if (first == kInvalid) first = l;
      on_seam = on_seam || l != first;
    });
    if (on_seam) mo.forced.push_back(v);
  }
  std::sort(mo.forced.begin(), mo.forced.end());
  mo.forced.erase(std::unique(mo.forced.begin(), mo.forced.end()), mo.forced.end());
  seg.refined = std::move(em->refined);
  seg.feature = std::move(em->feature);
  // Splitting appends vertices: the seam vertices keep their ids.
  seg.dividing_splits = split_dividing_edges(seg.refined, seg.labels, seg.feature);
  try {
    seg.meta = build_meta_mesh(seg.refined.mesh, seg.labels, seg.num_patches, seg.feature, mo);
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::layout) throw;
    log.failure = fmt::format("the traced patches give no meta-mesh: {}", e.what());
    return traced;
  }
  try {
    check_meta_mesh(seg.refined.mesh, seg.labels, seg.meta);
  } catch (const Error& e) {
    // A seam loop without a node, or a patch bordering itself: a layout the tracing should not
    // have made, reported as such (the JSON's fallback reason) rather than stopping the run.
    log.failure = fmt::format("the traced patches give an inconsistent meta-mesh: {}", e.what());
    return traced;
  }
  measure_geodesic_lengths(seg.refined.mesh, seg.labels, seg.meta);
  seg.vsa_labels = seg.labels;
  const TraceTurns turns(seg.refined.mesh, seg.labels, *em, tr.partial_nodes);
  PatchCorners pc = patch_corners(seg.refined.mesh, seg.labels, seg.meta, h, turns, repaired,
                                  seg.feature, cf.index4);
  out.corners = std::move(pc.corners);
  out.quarter_turns.resize(seg.meta.vertices.size(), 0);
  for (uint32_t mv = 0; mv < seg.meta.vertices.size(); ++mv) {
    const uint32_t v = seg.meta.vertices[mv].vertex;
    if (v >= cf.index4.size()) continue;  // a vertex the embedding made: regular
    out.quarter_turns[mv] = (seg.refined.mesh.is_boundary_vertex(v) ? 2 : 4) - cf.index4[v];
  }
  out.preferred = std::move(pc.by_angles);
  log.angle_corner_patches = uint32_t(std::count(out.preferred.begin(), out.preferred.end(), 1));
  log.free_corner_patches =
      uint32_t(std::count(out.corners.begin(), out.corners.end(), kFreeCorners));
  log.embed_seconds += seconds_since(t0);
  return traced;
}

// How far the integer layout of traced patches is from their shapes. Each patch with corners
// has a chart of W x H quads under the integer lengths that best fit the meta-edges' geodesic
// lengths (the length program without the corner program: a patch without corners only gives
// its meta-edges, and where the given corners admit no lengths the patches of the meta-edges
// forced to zero count as such); its stretch s = (W / its mean target width) / (H / its mean
// target height) is what the map must squeeze into each quad. Misfit: the area-weighted mean of
// |log s| (log 2 for a patch without corners, at most log 8) plus the patches' bending beyond
// kBending.
struct LayoutFit {
  double misfit = INFINITY;
  std::vector<double> badness;  // per patch, |log s|
  std::vector<double> bending;  // per patch, by how much its net curvature passes kBending
  // Per patch with corners, 1 where it is narrower than a quad or smaller than two in its
  // targets: its meta-edges, stretched to whole quads, force their lengths on every patch the
  // strips through them cross (FIELD_LAYOUT.md §5: such traces are deleted first).
  std::vector<char> small;
};

// A patch whose net Gaussian curvature (on the field's smoothed surface) passes this cannot be
// mapped onto a rectangle without quads crowding where it bends (FIELD_LAYOUT.md §5:
// near-developable patches; net rather than absolute, since a scan's noise adds up in |K|).
// Each multiple beyond it counts in the misfit as a stretch of e.
constexpr double kBending = std::numbers::pi / 3;

constexpr double kWorst = 2.0794415416798357;  // log 8

// The angle defect 2 pi - (sum of the corner angles) of every interior vertex of `mesh` (0 on
// the boundary).
std::vector<double> angle_defects(const TriMesh& mesh) {
  std::vector<double> angles(mesh.num_vertices(), 0.0);
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
    const Tri& tri = mesh.face(f);
    for (int i = 0; i < 3; ++i) {
      const Vec3 a = mesh.position(tri[(i + 1) % 3]) - mesh.position(tri[i]);
      const Vec3 b = mesh.position(tri[(i + 2) % 3]) - mesh.position(tri[i]);
      angles[tri[i]] += std::atan2(norm(cross(a, b)), dot(a, b));
    }
  }
  for (uint32_t v = 0; v < mesh.num_vertices(); ++v)
    angles[v] = mesh.is_boundary_vertex(v) ? 0 : 2 * std::numbers::pi - angles[v];
  return angles;
}

// `defect`: angle_defects of the field's smoothed surface, whose vertices the cut mesh keeps (the
// vertices it adds lie on edges or in faces, and are flat).
LayoutFit layout_fit(const Traced& t, const std::vector<double>& defect, double h) {
  LayoutFit fit;
  const SegmentResult& seg = t.out.seg;
  const MetaMesh& meta = seg.meta;
  const uint32_t np = uint32_t(meta.faces.size());
  // What a patch is where the lengths cannot be measured: the worst.
  fit.badness.assign(np, kWorst);
  fit.bending.assign(np, 0.0);
  fit.small.assign(np, 0);
  std::vector<std::array<uint32_t, 4>> corners = t.out.corners;
  std::vector<char> free(np, 0);
  for (uint32_t p = 0; p < np; ++p) {
    if (corners[p] != kFreeCorners) continue;
    const uint32_t n = uint32_t(meta.faces[p].cycle.size());
    if (n < 4) return fit;
    free[p] = 1;
    corners[p] = {0, n / 4, n / 2, 3 * n / 4};
  }
  const std::vector<std::vector<uint8_t>> sides = item_sides(meta, corners);
  const std::vector<SideRow> all = side_equations(meta, sides);
  // Where the given corners admit no lengths (the layout then slides or chooses corners), the
  // patches of the meta-edges forced to zero count as patches without corners.
  std::vector<SideRow> rows;
  for (int round = 0;; ++round) {
    rows.clear();
    for (uint32_t p = 0; p < np; ++p)
      if (!free[p]) rows.push_back(all[2 * p]), rows.push_back(all[2 * p + 1]);
    const Feasibility f = check_feasibility(uint32_t(meta.edges.size()), rows);
    if (f.feasible) break;
    if (round == 8 || f.forced_zero.empty()) {
      fit.misfit = kWorst;
      return fit;
    }
    for (uint32_t e : f.forced_zero)
      for (uint32_t p : {meta.edges[e].left, meta.edges[e].right})
        if (p != kInvalid) free[p] = 1;
  }
  std::vector<double> c(meta.edges.size());
  for (uint32_t e = 0; e < c.size(); ++e) c[e] = meta.edges[e].geodesic / h;
  std::vector<double> area(np, 0.0);
  const TriMesh& mesh = seg.refined.mesh;
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) area[seg.labels[f]] += mesh.face_area(f);
  double total = 0;
  for (double a : area) total += a;
  fit.badness.assign(np, std::log(2.0));
  std::vector<int64_t> x;
  if (auto flow = solve_lengths_flow(c, rows)) {
    x = std::move(flow->x);
  } else {
    try {
      x = solve_lengths(c, rows, 2.0).x;
    } catch (const Error& e) {
      if (e.kind() != ErrorKind::solver) throw;
      return fit;
    }
  }
  // Per patch, the angle defects of the interior vertices inside it.
  for (uint32_t v = 0; v < defect.size(); ++v) {
    if (defect[v] == 0 || mesh.is_boundary_vertex(v)) continue;
    uint32_t patch = kInvalid;
    bool inside = true;
    mesh.for_each_outgoing(v, [&](uint32_t he) {
      const uint32_t l = seg.labels[TriMesh::face_of(he)];
      if (patch == kInvalid) patch = l;
      inside = inside && l == patch;
    });
    if (inside && patch != kInvalid) fit.bending[patch] += defect[v];
  }
  for (double& b : fit.bending) b = std::max(0.0, std::abs(b) / kBending - 1);
  double sum = 0;
  for (uint32_t p = 0; p < np; ++p) {
    sum += area[p] * fit.bending[p];
    if (!free[p]) {
      double len[4] = {0, 0, 0, 0}, target[4] = {0, 0, 0, 0};
      for (uint32_t i = 0; i < meta.faces[p].cycle.size(); ++i) {
        const uint32_t e = meta.faces[p].cycle[i].edge;
        len[sides[p][i]] += double(x[e]);
        target[sides[p][i]] += c[e];
      }
      const double a = 0.5 * (target[0] + target[2]), b = 0.5 * (target[1] + target[3]);
      fit.small[p] = std::min(a, b) < 1 || a * b < 2;
      fit.badness[p] = a > 0 && b > 0 && len[0] > 0 && len[1] > 0
                           ? std::min(kWorst, std::abs(std::log((len[0] / a) / (len[1] / b))))
                           : kWorst;
    }
    sum += area[p] * fit.badness[p];
  }
  fit.misfit = total > 0 ? sum / total : 0;
  return fit;
}

// The traces the coarse layout would delete first: those bounding small patches, then those
// bounding patches whose charts are stretched by more than 1.5 (or have no corners), each
// weighted by the patches' urgency times the share of their perimeter it bounds, heaviest first
// (ties by trace id). A connection, a
// feature or the boundary is never a candidate.
std::vector<uint32_t> coarse_candidates(const Traced& t, const LayoutFit& fit) {
  const MetaMesh& meta = t.out.seg.meta;
  const auto& vt = t.vertex_traces;
  auto traces_at = [&](uint32_t v) {
    const auto lo = std::lower_bound(vt.begin(), vt.end(), std::make_pair(v, 0u));
    std::vector<uint32_t> out;
    for (auto it = lo; it != vt.end() && it->first == v; ++it) out.push_back(it->second);
    return out;
  };
  // The trace a meta-edge lies on: the one every vertex of it lies on.
  std::vector<uint32_t> edge_trace(meta.edges.size(), kInvalid);
  for (uint32_t e = 0; e < meta.edges.size(); ++e) {
    const MetaEdge& me = meta.edges[e];
    if (me.feature || me.right == kInvalid || me.vertices.empty()) continue;
    std::vector<uint32_t> common = traces_at(me.vertices.front());
    for (std::size_t k = 1; k < me.vertices.size() && !common.empty(); ++k) {
      const std::vector<uint32_t> here = traces_at(me.vertices[k]);
      std::vector<uint32_t> both;
      std::set_intersection(common.begin(), common.end(), here.begin(), here.end(),
                            std::back_inserter(both));
      common = std::move(both);
    }
    for (uint32_t id : common)
      if (t.tr.traces[id].end != TraceEnd::node) {
        edge_trace[e] = id;
        break;
      }
  }
  std::vector<double> weight(t.tr.traces.size(), 0.0);
  for (uint32_t p = 0; p < meta.faces.size(); ++p) {
    const double urgency = fit.small[p] ? kWorst + fit.badness[p] : fit.badness[p];
    if (urgency < std::log(1.5)) continue;
    double perimeter = 0;
    for (const BoundaryItem& it : meta.faces[p].cycle) perimeter += meta.edges[it.edge].geodesic;
    if (!(perimeter > 0)) continue;
    for (const BoundaryItem& it : meta.faces[p].cycle)
      if (edge_trace[it.edge] != kInvalid)
        weight[edge_trace[it.edge]] += urgency * meta.edges[it.edge].geodesic / perimeter;
  }
  std::vector<uint32_t> out;
  for (uint32_t id = 0; id < weight.size(); ++id)
    if (weight[id] > 0) out.push_back(id);
  std::stable_sort(out.begin(), out.end(),
                   [&](uint32_t a, uint32_t b) { return weight[a] > weight[b]; });
  return out;
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

  TraceOptions to;
  to.edge_length = h;
  Traced best = trace_layout(base, cf, to, h, log);
  if (!log.failure.empty()) return std::move(best.out);

  // The coarse layout (FIELD_LAYOUT.md §5): traces bounding stretched patches are deleted, a
  // batch at a time, while the layout's misfit drops; a batch that does not help is halved,
  // and a single trace that does not help is kept for good.
  t0 = Clock::now();
  const std::vector<double> defect = angle_defects(cf.surface);
  LayoutFit fit = layout_fit(best, defect, h);
  log.misfit_traced = fit.misfit;
  log.patches_traced = log.patches;
  log.free_corner_patches_traced = log.free_corner_patches;
  auto ray_of = [](const Trace& t) { return RayId{t.source, t.first_face, t.first_arm}; };
  std::vector<RayId> refused;  // single rays whose deletion did not help: not tried again
  std::size_t batch = 0;
  for (uint32_t evaluation = 0;
       evaluation < kCoarseEvaluations && std::isfinite(fit.misfit) && fit.misfit > 0;
       ++evaluation) {
    std::vector<RayId> batch_rays;
    for (uint32_t id : coarse_candidates(best, fit)) {
      const RayId ray = ray_of(best.tr.traces[id]);
      if (std::find(refused.begin(), refused.end(), ray) == refused.end())
        batch_rays.push_back(ray);
    }
    if (batch_rays.empty()) break;
    if (batch == 0) batch = (batch_rays.size() + 1) / 2;
    batch_rays.resize(std::min(batch, batch_rays.size()));
    TraceOptions trial = to;
    trial.removed.insert(trial.removed.end(), batch_rays.begin(), batch_rays.end());
    FieldLayoutLog trial_log = log;
    Traced next = trace_layout(base, cf, trial, h, trial_log);
    ++log.coarse_evaluations;
    LayoutFit next_fit;
    if (trial_log.failure.empty()) next_fit = layout_fit(next, defect, h);
    // Every patch stays four-cornered and a disk: no more patches left to the corner program
    // or made disks by the repair than before.
    const bool kept_shape = trial_log.free_corner_patches <= log.free_corner_patches &&
                            trial_log.repaired_patches <= log.repaired_patches;
    if (kept_shape && next_fit.misfit < fit.misfit - kCoarseGain) {
      // The rays of the batch that are gone (the rule of neighbouring rays may keep some).
      for (const RayId& ray : batch_rays)
        log.coarse_deleted += std::none_of(next.tr.traces.begin(), next.tr.traces.end(),
                                           [&](const Trace& t) { return ray_of(t) == ray; });
      trial_log.coarse_evaluations = log.coarse_evaluations;
      trial_log.coarse_deleted = log.coarse_deleted;
      log = trial_log;
      to = std::move(trial);
      best = std::move(next);
      fit = std::move(next_fit);
    } else if (batch > 1) {
      batch = (batch + 1) / 2;
    } else {
      refused.push_back(batch_rays.front());
    }
  }
  log.misfit = fit.misfit;
  log.coarse_seconds = seconds_since(t0);
  return std::move(best.out);
}

}  // namespace isoquad
