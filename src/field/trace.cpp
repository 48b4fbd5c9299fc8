#include "field/trace.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <queue>

namespace isoquad {

namespace {

constexpr double kPi = std::numbers::pi;

struct P2 {
  double x = 0, y = 0;
};
P2 operator+(P2 a, P2 b) { return {a.x + b.x, a.y + b.y}; }
P2 operator-(P2 a, P2 b) { return {a.x - b.x, a.y - b.y}; }
P2 operator*(double s, P2 a) { return {s * a.x, s * a.y}; }
double cross(P2 a, P2 b) { return a.x * b.y - a.y * b.x; }
double dot(P2 a, P2 b) { return a.x * b.x + a.y * b.y; }
double length(P2 a) { return std::sqrt(dot(a, a)); }

// Each face's corners in its own frame (corner 0 at the origin): the isometric chart every step
// inside the face is computed in.
struct Charts {
  std::vector<std::array<P2, 3>> corner;

  Charts(const TriMesh& m, const FaceFrames& fr) : corner(m.num_faces()) {
    for (uint32_t f = 0; f < m.num_faces(); ++f) {
      const Tri& t = m.face(f);
      for (int i = 0; i < 3; ++i) {
        const Vec3 d = m.position(t[i]) - m.position(t[0]);
        corner[f][i] = {isoquad::dot(d, fr.x[f]), isoquad::dot(d, fr.y[f])};
      }
    }
  }

  // Barycentric coordinates of a chart point of face f.
  std::array<double, 3> bary(uint32_t f, P2 p) const {
    const auto& c = corner[f];
    const double area = cross(c[1] - c[0], c[2] - c[0]);
    if (!(std::abs(area) > 0)) return {1.0 / 3, 1.0 / 3, 1.0 / 3};
    const double b1 = cross(p - c[0], c[2] - c[0]) / area;
    const double b2 = cross(c[1] - c[0], p - c[0]) / area;
    return {1 - b1 - b2, b1, b2};
  }
};

P2 arm(const CrossField& cf, uint32_t f, int k) {
  const double a = cf.angle[f] + k * kPi / 2;
  return {std::cos(a), std::sin(a)};
}

// A ray that leaves vertex v into face f along arm k.
struct Ray {
  uint32_t vertex, face;
  int arm;
};

bool is_constraint(const CrossField& cf, const TriMesh& m, uint32_t h) {
  return m.twin(h) == kInvalid || cf.feature[m.edge(h)];
}

// The arms of the field inside the corner of each face around v: for face f whose corner at v is
// between edge vectors a (to the next corner) and b (to the previous one), the arms at an angle
// in [0, beta) from a. Arms along a constraint edge are not rays (they run along a track).
std::vector<Ray> rays_at(const CrossField& cf, const Charts& ch, const TriMesh& m, uint32_t v) {
  constexpr double kAlong = 1e-6;
  std::vector<Ray> rays;
  m.for_each_outgoing(v, [&](uint32_t h) {
    const uint32_t f = TriMesh::face_of(h), i = h % 3;
    const auto& c = ch.corner[f];
    const P2 a = c[(i + 1) % 3] - c[i], b = c[(i + 2) % 3] - c[i];
    const double beta = std::atan2(cross(a, b), dot(a, b));
    const bool a_constraint = is_constraint(cf, m, h);
    const bool b_constraint = is_constraint(cf, m, TriMesh::prev(h));
    for (int k = 0; k < 4; ++k) {
      const P2 d = arm(cf, f, k);
      const double alpha = std::atan2(cross(a, d), dot(a, d));
      if (alpha < 0 || alpha >= beta) continue;
      if ((a_constraint && alpha < kAlong) || (b_constraint && beta - alpha < kAlong)) continue;
      // An arm along an interior edge shows in both faces (each frame rounds it into its own
      // half-open sector): one ray.
      const Vec3 dir = cf.frames.direction(f, cf.angle[f] + k * kPi / 2);
      const bool seen = std::any_of(rays.begin(), rays.end(), [&](const Ray& r) {
        return angle_between(cf.frames.direction(r.face, cf.angle[r.face] + r.arm * kPi / 2), dir) <
               kAlong;
      });
      if (!seen) rays.push_back({v, f, k});
    }
  });
  return rays;
}

// Near a singularity the field turns fast, and an arm close to the edge between two faces can
// show in both sectors at clearly different angles: where v has more rays than its index allows,
// the two closest around v (by the angle from the fan's first edge) are merged, the first kept.
void merge_extra_rays(const CrossField& cf, const Charts& ch, const TriMesh& m, uint32_t v,
                      int expected, std::vector<Ray>& rays) {
  if (expected <= 0 || int(rays.size()) <= expected) return;
  // The angle of each ray around v, the corner angles of the faces before its own added.
  std::vector<double> around;
  double offset = 0;
  std::size_t next = 0;
  m.for_each_outgoing(v, [&](uint32_t h) {
    const uint32_t f = TriMesh::face_of(h), i = h % 3;
    const auto& c = ch.corner[f];
    const P2 a = c[(i + 1) % 3] - c[i], b = c[(i + 2) % 3] - c[i];
    for (; next < rays.size() && rays[next].face == f; ++next) {
      const P2 d = arm(cf, f, rays[next].arm);
      around.push_back(offset + std::atan2(cross(a, d), dot(a, d)));
    }
    offset += std::atan2(cross(a, b), dot(a, b));
  });
  while (int(rays.size()) > expected) {
    std::size_t best = 0;
    double gap = INFINITY;
    for (std::size_t j = 0; j < rays.size(); ++j) {
      const std::size_t k = (j + 1) % rays.size();
      const double g = k > j ? around[k] - around[j] : around[k] + offset - around[j];
      if (g < gap) gap = g, best = k;
    }
    rays.erase(rays.begin() + std::ptrdiff_t(best));
    around.erase(around.begin() + std::ptrdiff_t(best));
  }
}

// Whether v is a node of the constraint curves: where they end, branch or turn by more than 45
// degrees (straight stretches of a feature or the boundary emit nothing).
bool is_constraint_node(const CrossField& cf, const TriMesh& m, uint32_t v) {
  std::vector<Vec3> dirs;
  m.for_each_outgoing(v, [&](uint32_t h) {
    if (is_constraint(cf, m, h)) dirs.push_back(normalized(m.position(m.to(h)) - m.position(v)));
    // The boundary edge coming into v is the previous halfedge of the fan's last face.
    const uint32_t in = TriMesh::prev(h);
    if (m.twin(in) == kInvalid) dirs.push_back(normalized(m.position(m.from(in)) - m.position(v)));
  });
  if (dirs.empty()) return false;
  if (dirs.size() != 2) return true;
  return isoquad::dot(dirs[0], -dirs[1]) < std::cos(kPi / 4);
}

struct Segment {
  uint32_t trace;
  P2 from, to;
  double arc;  // the trace's length at `from`
};

struct Tracer {
  const CrossField& cf;
  const TriMesh& m;
  Charts charts;
  double cap;
  std::vector<std::vector<uint32_t>> face_segments;  // segment ids per face
  std::vector<Segment> segments;
  struct State {
    uint32_t face = kInvalid;
    P2 point;
    uint32_t entry = kInvalid;  // the halfedge of `face` it came in through; kInvalid at the source
    int arm = 0;
    double arc = 0;
    bool alive = true;
    uint32_t last_segment = kInvalid;
    // Set where the matched arm turns back at the entry edge (a sink edge, next to a
    // singularity): the trace crosses this face straight on, along its incoming direction.
    bool straight = false;
    P2 direction;
    uint32_t steps = 0;
  };
  std::vector<State> state;
  TraceResult result;

  Tracer(const CrossField& field, double cap_length)
      : cf(field),
        m(field.surface),
        charts(m, field.frames),
        cap(cap_length),
        face_segments(m.num_faces()) {}

  SurfacePoint surface_point(uint32_t f, P2 p) const { return {f, charts.bary(f, p)}; }

  void start(const Ray& r) {
    Trace t;
    t.source = r.vertex;
    t.first_face = r.face;
    t.first_arm = r.arm;
    const Tri& tri = m.face(r.face);
    const int i = int(std::find(tri.begin(), tri.end(), r.vertex) - tri.begin());
    t.points.push_back(surface_point(r.face, charts.corner[r.face][i]));
    t.on_edge.push_back({kInvalid, 0});
    result.traces.push_back(std::move(t));
    State st;
    st.face = r.face;
    st.point = charts.corner[r.face][i];
    st.arm = r.arm;
    state.push_back(st);
  }

  // Halfedge h at fraction s from its start, as a point of h's edge.
  EdgePoint edge_point(uint32_t h, double s) const {
    const uint32_t e = m.edge(h);
    return {e, m.edge_halfedge(e) == h ? s : 1 - s};
  }

  void finish(uint32_t id, uint32_t f, P2 p, EdgePoint at, TraceEnd end, uint32_t on = kInvalid) {
    Trace& t = result.traces[id];
    t.points.push_back(surface_point(f, p));
    t.on_edge.push_back(at);
    t.faces.push_back(f);
    t.end = end;
    t.end_trace = on;
    state[id].alive = false;
  }

  // The exit of the ray from p along d through an edge of f other than `entry` (and other than
  // the two at the source corner): the halfedge and the parameters along the ray and the edge.
  bool exit(uint32_t f, P2 p, P2 d, uint32_t entry, bool at_corner, uint32_t& h_out, double& t_out,
            double& s_out) const {
    const auto& c = charts.corner[f];
    double best = INFINITY;
    for (uint32_t i = 0; i < 3; ++i) {
      const uint32_t h = 3 * f + i;
      if (h == entry) continue;
      const P2 a = c[i], e = c[(i + 1) % 3] - c[i];
      if (at_corner && (length(a - p) == 0 || length(c[(i + 1) % 3] - p) == 0)) continue;
      const double den = cross(d, e);
      if (den == 0) continue;
      const double t = cross(a - p, e) / den, s = cross(a - p, d) / den;
      if (!(t > 0) || s < -1e-9 || s > 1 + 1e-9 || t >= best) continue;
      best = t, h_out = h, t_out = t, s_out = std::clamp(s, 1e-9, 1 - 1e-9);
    }
    return best < INFINITY;
  }

  // The first crossing of segment p -> q (trace id, arc length at p) with a stored segment of
  // face f that the trace reaches later than its owner; segments that the trace reaches first
  // and whose owner is still on them are cut back there.
  bool crossing(uint32_t id, uint32_t f, P2 p, P2 q, double arc, double& t_stop, uint32_t& on) {
    struct Hit {
      double t;
      uint32_t seg;
      double other_arc;
    };
    std::vector<Hit> hits;
    const P2 r = q - p;
    for (uint32_t sid : face_segments[f]) {
      const Segment& s = segments[sid];
      const P2 e = s.to - s.from;
      const double den = cross(r, e);
      if (den == 0) continue;
      const double t = cross(s.from - p, e) / den, u = cross(s.from - p, r) / den;
      if (t < 0 || t > 1 || u < 0 || u > 1) continue;
      // Two traces leaving the same vertex touch there, and nowhere else.
      if (t < 1e-9 && u < 1e-9) continue;
      hits.push_back({t, sid, s.arc + u * length(e)});
    }
    std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) {
      return a.t < b.t || (a.t == b.t && a.seg < b.seg);
    });
    for (const Hit& hit : hits) {
      Segment& s = segments[hit.seg];
      const double own_arc = arc + hit.t * length(r);
      const bool other_on_it = state[s.trace].alive && state[s.trace].last_segment == hit.seg;
      if (own_arc >= hit.other_arc || !other_on_it) {
        t_stop = hit.t;
        on = s.trace;
        return true;
      }
      // The other trace came here later: it stops at the crossing instead.
      const P2 x = p + hit.t * r;
      Trace& other = result.traces[s.trace];
      other.points.back() = surface_point(f, x);
      other.on_edge.back() = {kInvalid, 0};
      other.length = hit.other_arc;
      other.end = TraceEnd::track;
      other.end_trace = id;
      state[s.trace].alive = false;
      s.to = x;
      ++result.truncated;
    }
    return false;
  }

  // Two traces of one separatrix, run from its two ends (a singularity to a singularity), meet
  // head-on. Where trace id's segment in face f runs against the last segment of a live trace in
  // f (within 20 degrees of opposite), both end where the other entered f: one seam, joined at
  // an edge point (or at the other's source, when it has only just left it). Numerically the two
  // often pass one triangle apart: against a live trace's last segment in a neighbour of f, both
  // end at the nearer end of the edge between the two faces.
  bool head_on(uint32_t id, uint32_t f, P2 from, P2 dir) {
    const Vec3 dir3 = normalized(dir.x * cf.frames.x[f] + dir.y * cf.frames.y[f]);
    auto opposed = [&](uint32_t sid, uint32_t g) {
      const Segment& sg = segments[sid];
      const uint32_t y = sg.trace;
      if (y == id || !state[y].alive || state[y].last_segment != sid) return false;
      const P2 e = sg.to - sg.from;
      const Vec3 e3 = e.x * cf.frames.x[g] + e.y * cf.frames.y[g];
      return isoquad::dot(e3, dir3) < -std::cos(kPi / 9) * norm(e3);
    };
    auto end_other = [&](uint32_t y, uint32_t sid) {
      Trace& other = result.traces[y];
      other.points.pop_back();
      other.on_edge.pop_back();
      other.faces.pop_back();
      other.length = segments[sid].arc;
      other.end = TraceEnd::track;
      other.end_trace = id;
      state[y].alive = false;
      ++result.head_on;
    };
    for (uint32_t sid : face_segments[f]) {
      if (!opposed(sid, f)) continue;
      const Segment& sg = segments[sid];
      const uint32_t y = sg.trace;
      end_other(y, sid);
      result.traces[id].length = state[id].arc + length(sg.from - from);
      finish(id, f, sg.from, result.traces[y].on_edge.back(), TraceEnd::track, y);
      return true;
    }
    for (uint32_t i = 0; i < 3; ++i) {
      const uint32_t h = 3 * f + i, tw = m.twin(h);
      if (tw == kInvalid) continue;
      const uint32_t g = TriMesh::face_of(tw);
      for (uint32_t sid : face_segments[g]) {
        if (!opposed(sid, g)) continue;
        const Segment& sg = segments[sid];
        const uint32_t y = sg.trace;
        // The end of the shared edge nearer to the other's segment.
        const P2 mid = 0.5 * (sg.from + sg.to);
        const auto& cg = charts.corner[g];
        // tw runs from the corner h ends at (h's end is tw's start) to h's start.
        const bool h_end = length(cg[tw % 3] - mid) < length(cg[(tw % 3 + 1) % 3] - mid);
        const uint32_t corner_f = h_end ? (i + 1) % 3 : i;
        const uint32_t corner_g = h_end ? tw % 3 : (tw % 3 + 1) % 3;
        const EdgePoint w = edge_point(h, h_end ? 1.0 : 0.0);
        Trace& other = result.traces[y];
        other.points.back() = surface_point(g, cg[corner_g]);
        other.on_edge.back() = w;
        other.length = sg.arc + length(cg[corner_g] - sg.from);
        other.end = TraceEnd::track;
        other.end_trace = id;
        state[y].alive = false;
        segments[sid].to = cg[corner_g];
        ++result.head_on;
        result.traces[id].length = state[id].arc + length(charts.corner[f][corner_f] - from);
        finish(id, f, charts.corner[f][corner_f], w, TraceEnd::track, y);
        return true;
      }
    }
    return false;
  }

  // Advances trace id through its current face; false when it ends there.
  bool step(uint32_t id) {
    State& st = state[id];
    const uint32_t f = st.face;
    const P2 d = st.straight ? st.direction : arm(cf, f, st.arm);
    uint32_t h = kInvalid;
    double t = 0, s = 0;
    if (!exit(f, st.point, d, st.entry, st.entry == kInvalid, h, t, s)) {
      finish(id, f, st.point, {kInvalid, 0}, TraceEnd::sink);
      return false;
    }
    const P2 q = st.point + t * d;
    if (head_on(id, f, st.point, d)) return false;
    double t_stop = 0;
    uint32_t on = kInvalid;
    if (crossing(id, f, st.point, q, st.arc, t_stop, on)) {
      result.traces[id].length = st.arc + t_stop * t;
      finish(id, f, st.point + (t_stop * t) * d, {kInvalid, 0}, TraceEnd::track, on);
      return false;
    }
    segments.push_back({id, st.point, q, st.arc});
    face_segments[f].push_back(uint32_t(segments.size() - 1));
    st.last_segment = uint32_t(segments.size() - 1);
    st.arc += t;
    Trace& tr = result.traces[id];
    tr.length = st.arc;
    if (m.twin(h) == kInvalid || cf.feature[m.edge(h)]) {
      finish(id, f, q, edge_point(h, s),
             m.twin(h) == kInvalid ? TraceEnd::boundary : TraceEnd::feature);
      return false;
    }
    // The cap, or a trace that keeps crossing faces without getting anywhere (zero-length steps
    // back and forth at a degenerate spot).
    if (st.arc > cap || ++st.steps > 2 * m.num_faces()) {
      finish(id, f, q, edge_point(h, s), TraceEnd::cap);
      return false;
    }
    tr.points.push_back(surface_point(f, q));
    tr.on_edge.push_back(edge_point(h, s));
    tr.faces.push_back(f);
    // Into the neighbour: the same edge point, the arm matched by the period jump.
    const uint32_t tw = m.twin(h), g = TriMesh::face_of(tw);
    const auto& cg = charts.corner[g];
    const P2 a = cg[tw % 3], b = cg[(tw % 3 + 1) % 3];
    st.face = g;
    st.entry = tw;
    st.point = a + (1 - s) * (b - a);
    st.arm = ((st.arm + cf.period_jump[h]) % 4 + 4) % 4;
    st.straight = cross(b - a, arm(cf, g, st.arm)) <= 0;
    if (st.straight) {
      // The incoming direction in g's chart: the edge's own direction turned by the angle d
      // made with it in f.
      const auto& c = charts.corner[f];
      const P2 ef = c[(h % 3 + 1) % 3] - c[h % 3], eg = a - b;
      const double turn = std::atan2(cross(ef, d), dot(ef, d));
      const double base = std::atan2(eg.y, eg.x) + turn;
      st.direction = {std::cos(base), std::sin(base)};
      if (cross(b - a, st.direction) <= 0) {
        finish(id, g, st.point, edge_point(h, s), TraceEnd::sink);
        return false;
      }
      ++result.straight_crossings;
    }
    return true;
  }

  void run() {
    using Item = std::pair<double, uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
    for (uint32_t id = 0; id < state.size(); ++id) queue.push({0.0, id});
    while (!queue.empty()) {
      const uint32_t id = queue.top().second;
      queue.pop();
      if (!state[id].alive) continue;
      if (step(id)) queue.push({state[id].arc, id});
    }
  }
};

}  // namespace

Vec3 position_on(const TriMesh& mesh, const SurfacePoint& p) {
  const Tri& t = mesh.face(p.face);
  return p.bary[0] * mesh.position(t[0]) + p.bary[1] * mesh.position(t[1]) +
         p.bary[2] * mesh.position(t[2]);
}

TraceResult trace_separatrices(const CrossField& cf, const TraceOptions& options) {
  const TriMesh& m = cf.surface;
  double area = 0;
  for (uint32_t f = 0; f < m.num_faces(); ++f) area += m.face_area(f);
  const double cap = options.edge_length > 0
                         ? std::min(200 * options.edge_length, 4 * std::sqrt(area))
                         : 4 * std::sqrt(area);
  Tracer tracer(cf, cap);
  VertexData<char> singular(m.num_vertices(), 0);
  for (uint32_t v : cf.singular) singular[v] = 1;
  for (uint32_t v = 0; v < m.num_vertices(); ++v) {
    bool on_constraint = false;
    m.for_each_outgoing(v, [&](uint32_t h) {
      on_constraint =
          on_constraint || is_constraint(cf, m, h) || m.twin(TriMesh::prev(h)) == kInvalid;
    });
    const bool node = on_constraint ? singular[v] || is_constraint_node(cf, m, v) : singular[v];
    if (!node) continue;
    std::vector<Ray> rays = rays_at(cf, tracer.charts, m, v);
    if (!on_constraint) merge_extra_rays(cf, tracer.charts, m, v, 4 - cf.index4[v], rays);
    if (!on_constraint && rays.size() != std::size_t(4 - cf.index4[v]))
      ++tracer.result.ray_mismatches;
    if (rays.empty()) continue;
    tracer.result.nodes.push_back(v);
    for (const Ray& r : rays) tracer.start(r);
  }
  tracer.run();
  return std::move(tracer.result);
}

}  // namespace isoquad
