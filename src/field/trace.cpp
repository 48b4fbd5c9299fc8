#include "field/trace.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <queue>
#include <unordered_map>

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

// A ray that leaves vertex v into face f along arm k; where the arm lies in the gap between two
// faces' copies of the field (see interior_rays), it leaves along `direction` (f's chart)
// through f and follows arm k from the next face on.
struct Ray {
  uint32_t vertex, face;
  int arm;
  bool along = false;
  P2 direction{};
};

P2 ray_direction(const CrossField& cf, const Ray& r) {
  return r.along ? r.direction : arm(cf, r.face, r.arm);
}

Vec3 ray_direction3(const CrossField& cf, const Ray& r) {
  if (!r.along) return cf.frames.direction(r.face, cf.angle[r.face] + r.arm * kPi / 2);
  return normalized(r.direction.x * cf.frames.x[r.face] + r.direction.y * cf.frames.y[r.face]);
}

bool is_constraint(const CrossField& cf, const TriMesh& m, uint32_t h) {
  return m.twin(h) == kInvalid || cf.feature[m.edge(h)];
}

// The arms of the field inside the corner of each face around v: for face f whose corner at v is
// between edge vectors a (to the next corner) and b (to the previous one), the arms at an angle
// in [0, beta) from a. Arms along a constraint edge are not rays (they run along a track).
// Used on the feature and boundary nodes; interior nodes count their rays as crossings
// (interior_rays).
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

// The rays of an interior node v, counted as crossings. Around v's fan (cone angle Theta, angle
// phi from the first face's first edge) follow one arm of the field continuously: psi_i, its
// angle in face i, unwrapped, the arm matched across each edge by the period jump. G = psi - phi
// decreases inside a face and jumps by the field's turn across an edge (|jump| <= 45 degrees);
// a ray is where G crosses a level -j pi/2 going down. Over the loop G falls by (4 - 4I) pi/2,
// so the net count of crossings is 4 - 4I, but a jump up across a level makes a second copy of
// the previous ray, and a jump down across a level hides a ray between two faces. So: every
// crossing is an event (down inside a face, up or down at an edge), events of one level (levels j
// and j + N at phi + Theta being one, N = 4 - 4I) cancel in down-up pairs, and each level keeps
// the down crossing farthest from its level's up crossings. A hidden ray leaves along the mean
// of its two faces' copies, in the face that mean lies in.
std::vector<Ray> interior_rays(const CrossField& cf, const Charts& ch, const TriMesh& m, uint32_t v,
                               int expected) {
  struct FanFace {
    uint32_t f = 0, in = 0;  // the face and its halfedge into v (shared with the next face)
    P2 a;                    // the edge vector of the fan's earlier edge
    double beta = 0, phi = 0, psi = 0;
    int arm = 0;  // the followed arm's index in f
  };
  std::vector<FanFace> fan;
  double theta = 0;
  m.for_each_outgoing(v, [&](uint32_t h) {
    const uint32_t f = TriMesh::face_of(h), i = h % 3;
    const auto& c = ch.corner[f];
    FanFace ff;
    ff.f = f;
    ff.in = TriMesh::prev(h);
    ff.a = c[(i + 1) % 3] - c[i];
    const P2 b = c[(i + 2) % 3] - c[i];
    ff.beta = std::atan2(cross(ff.a, b), dot(ff.a, b));
    ff.phi = theta;
    theta += ff.beta;
    fan.push_back(ff);
  });
  const std::size_t n = fan.size();
  if (n < 3 || expected <= 0) return {};
  auto arm_angle = [&](const FanFace& ff, int k) {
    const P2 d = arm(cf, ff.f, k);
    return ff.phi + std::atan2(cross(ff.a, d), dot(ff.a, d));
  };
  fan[0].arm = 0;
  fan[0].psi = arm_angle(fan[0], 0);
  // fan[n] is face 0 again, one turn on.
  FanFace wrap = fan[0];
  wrap.phi = theta;
  for (std::size_t i = 1; i <= n; ++i) {
    FanFace& cur = i < n ? fan[i] : wrap;
    const FanFace& prev = fan[i - 1];
    cur.arm = ((prev.arm + cf.period_jump[prev.in]) % 4 + 4) % 4;
    double psi = arm_angle(cur, cur.arm);
    psi += 2 * kPi * std::round((prev.psi - psi) / (2 * kPi));
    cur.psi = psi;
  }
  struct Event {
    int64_t level;  // j, normalized to its class
    double at;      // phi, shifted with the level
    int sign;       // +1 down (a ray), -1 up
    Ray ray;
  };
  std::vector<Event> events;
  const int64_t big = int64_t(expected);
  auto add = [&](int64_t j, double phi, int sign, const Ray& r) {
    // Level j at phi is level j - k N at phi - k Theta: normalize to j mod N.
    const int64_t k = (j >= 0 ? j : j - big + 1) / big;
    events.push_back({j - k * big, phi - double(k) * theta, sign, r});
  };
  auto lo_level = [](double g) { return int64_t(std::ceil(-g / (kPi / 2) - 1e-12)); };
  // The unit vector at angle t from e.
  auto turned = [](P2 e, double t) {
    const double l = length(e), c = std::cos(t), s = std::sin(t);
    return P2{(c * e.x - s * e.y) / l, (s * e.x + c * e.y) / l};
  };
  for (std::size_t i = 0; i < n; ++i) {
    const FanFace& ff = fan[i];
    // Inside face i: psi + j pi/2 in [phi_i, phi_i + beta_i).
    const double g_hi = ff.psi - ff.phi, g_lo = ff.psi - ff.phi - ff.beta;  // G falls g_hi -> g_lo
    for (int64_t j = lo_level(g_hi); - double(j) * kPi / 2 > g_lo; ++j) {
      const int k = int(((ff.arm + j) % 4 + 4) % 4);
      add(j, ff.psi + double(j) * kPi / 2, +1, Ray{v, ff.f, k});
    }
    // The edge into face i + 1: G jumps from g_lo to next.psi - phi_{i+1}.
    const FanFace& next = i + 1 < n ? fan[i + 1] : wrap;
    const double g_next = next.psi - next.phi;
    const double lo = std::min(g_lo, g_next), hi = std::max(g_lo, g_next);
    for (int64_t j = lo_level(hi); - double(j) * kPi / 2 > lo; ++j) {
      if (g_next > g_lo) {  // up: cancels a copy
        add(j, next.phi, -1, Ray{v, ff.f, 0});
        continue;
      }
      // Down across the edge: the ray between the two faces, along the mean of its copies.
      const double in_f = ff.psi + double(j) * kPi / 2, in_g = next.psi + double(j) * kPi / 2;
      const double mid = 0.5 * (in_f + in_g);
      const FanFace& g = i + 1 < n ? fan[i + 1] : fan[0];
      Ray r;
      if (mid < next.phi) {
        const double t = std::max(mid - ff.phi, 0.5 * ff.beta);
        r = Ray{v, ff.f, int(((ff.arm + j) % 4 + 4) % 4), true, turned(ff.a, t)};
      } else {
        const double t = std::min(std::max(mid - next.phi, 1e-3), 0.5 * g.beta);
        r = Ray{v, g.f, int(((next.arm + j) % 4 + 4) % 4), true, turned(g.a, t)};
      }
      add(j, next.phi, +1, r);
    }
  }
  // Per level: keep the down crossing farthest from the level's up crossings (all of them, also
  // one period on either side).
  std::vector<Ray> rays;
  std::vector<double> where;
  for (int64_t c = 0; c < big; ++c) {
    std::vector<double> ups;
    for (const Event& e : events)
      if (e.level == c && e.sign < 0)
        for (int s = -1; s <= 1; ++s) ups.push_back(e.at + s * theta);
    int down = 0, up = 0;
    const Event* best = nullptr;
    double best_gap = -1;
    for (const Event& e : events) {
      if (e.level != c) continue;
      (e.sign > 0 ? down : up) += 1;
      if (e.sign < 0) continue;
      double gap = INFINITY;
      for (double u : ups) gap = std::min(gap, std::abs(u - e.at));
      if (gap > best_gap + 1e-12) best_gap = gap, best = &e;
    }
    if (best && down - up == 1) {
      rays.push_back(best->ray);
      where.push_back(std::fmod(std::fmod(best->at, theta) + theta, theta));
    }
  }
  // Around v in order.
  std::vector<std::size_t> order(rays.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t x, std::size_t y) { return where[x] < where[y]; });
  std::vector<Ray> out;
  for (std::size_t i : order) out.push_back(rays[i]);
  return out;
}

// Sorts v's rays around it, by their angle from the fan's first edge.
void sort_rays_around(const CrossField& cf, const Charts& ch, const TriMesh& m, uint32_t v,
                      std::vector<Ray>& rays) {
  // The angle of each ray around v: the corner angles of the faces before its own, plus its
  // angle in its own corner. The rays sorted by it.
  std::vector<std::pair<uint32_t, double>> face_offset;  // face, corner angles before it
  double offset = 0;
  m.for_each_outgoing(v, [&](uint32_t h) {
    const uint32_t f = TriMesh::face_of(h), i = h % 3;
    const auto& c = ch.corner[f];
    const P2 a = c[(i + 1) % 3] - c[i], b = c[(i + 2) % 3] - c[i];
    face_offset.push_back({f, offset});
    offset += std::atan2(cross(a, b), dot(a, b));
  });
  std::vector<std::pair<double, Ray>> sorted;
  for (const Ray& r : rays) {
    const uint32_t f = r.face;
    const auto it = std::find_if(face_offset.begin(), face_offset.end(),
                                 [&](const auto& fo) { return fo.first == f; });
    const Tri& tri = m.face(f);
    const uint32_t i = uint32_t(std::find(tri.begin(), tri.end(), v) - tri.begin());
    const auto& c = ch.corner[f];
    const P2 a = c[(i + 1) % 3] - c[i], d = ray_direction(cf, r);
    sorted.push_back({it->second + std::atan2(cross(a, d), dot(a, d)), r});
  }
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const auto& x, const auto& y) { return x.first < y.first; });
  rays.clear();
  for (const auto& [angle, r] : sorted) rays.push_back(r);
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

// A stretch of a trace inside one face, in that face's chart.
struct FacePiece {
  uint32_t face;
  P2 from, to;
};

// A step shorter than this fraction of the cap gets nowhere; this many in a row (more faces than a
// vertex's one-ring has, but for a degenerate fan) end the trace.
constexpr double kStalledStep = 1e-9;
constexpr uint32_t kStalledSteps = 16;
// A trace that crosses one face this many times runs in a limit cycle: it ends as capped.
constexpr uint32_t kMostVisits = 8;

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
    uint32_t stalled = 0;  // consecutive steps shorter than kStalledStep * cap
  };
  std::vector<State> state;
  TraceResult result;
  // False: every trace runs as if alone (no crossing, no head-on join), to see where its
  // separatrix goes.
  bool interact = true;

  Tracer(const CrossField& field, double cap_length)
      : cf(field),
        m(field.surface),
        charts(m, field.frames),
        cap(cap_length),
        face_segments(m.num_faces()) {}

  SurfacePoint surface_point(uint32_t f, P2 p) const { return {f, charts.bary(f, p)}; }

  Vec3 position(uint32_t f, P2 p) const {
    return m.position(m.face(f)[0]) + p.x * cf.frames.x[f] + p.y * cf.frames.y[f];
  }

  uint32_t start(const Ray& r) {
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
    st.straight = r.along;
    st.direction = r.direction;
    state.push_back(st);
    return uint32_t(state.size() - 1);
  }

  // Halfedge h at fraction s from its start, as a point of h's edge.
  EdgePoint edge_point(uint32_t h, double s) const {
    const uint32_t e = m.edge(h);
    return {e, m.edge_halfedge(e) == h ? s : 1 - s};
  }

  // Appends to trace t, and to `pieces`, a path from p in face f (entered through halfedge
  // `entry`; kInvalid at a corner) straight towards vertex v, face by face, until a face has v as
  // a corner. False where a boundary or feature edge comes first, or after 256 faces.
  bool steer(uint32_t f, P2 p, uint32_t entry, uint32_t v, Trace& t,
             std::vector<FacePiece>& pieces) const {
    const Vec3 x = m.position(v);
    for (int guard = 0; guard < 256; ++guard) {
      const Tri& tri = m.face(f);
      if (const auto* at = std::find(tri.begin(), tri.end(), v); at != tri.end()) {
        const P2 q = charts.corner[f][at - tri.begin()];
        pieces.push_back({f, p, q});
        t.length += length(q - p);
        t.faces.push_back(f);
        t.points.push_back(surface_point(f, q));
        t.on_edge.push_back({kInvalid, 0});
        return true;
      }
      const Vec3 w = x - position(f, p);
      const P2 d{dot(w, cf.frames.x[f]), dot(w, cf.frames.y[f])};
      uint32_t h = kInvalid;
      double step = 0, s = 0;
      if (!exit(f, p, d, entry, entry == kInvalid, h, step, s)) return false;
      if (m.twin(h) == kInvalid || cf.feature[m.edge(h)]) return false;
      const P2 q = p + step * d;
      pieces.push_back({f, p, q});
      t.length += length(q - p);
      t.faces.push_back(f);
      t.points.push_back(surface_point(f, q));
      t.on_edge.push_back(edge_point(h, s));
      const uint32_t tw = m.twin(h), g = TriMesh::face_of(tw);
      const auto& cg = charts.corner[g];
      const P2 ga = cg[tw % 3], gb = cg[(tw % 3 + 1) % 3];
      p = ga + (1 - s) * (gb - ga);
      f = g;
      entry = tw;
    }
    return false;
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

  // How often trace id has crossed face f: its segments there.
  uint32_t crossings(uint32_t id, uint32_t f) const {
    const auto& in = face_segments[f];
    return uint32_t(std::count_if(in.begin(), in.end(),
                                  [&](uint32_t sid) { return segments[sid].trace == id; }));
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
    if (interact && head_on(id, f, st.point, d)) return false;
    double t_stop = 0;
    uint32_t on = kInvalid;
    if (interact && crossing(id, f, st.point, q, st.arc, t_stop, on)) {
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
    // A trace that has run onto a vertex circles its one-ring in steps of zero length (the exits
    // are clamped off the corners): it ends there, a sink, after more steps than a one-ring has.
    st.stalled = t > kStalledStep * cap ? 0 : st.stalled + 1;
    if (st.stalled > kStalledSteps) {
      finish(id, f, q, edge_point(h, s), TraceEnd::sink);
      return false;
    }
    // The cap, or a trace caught in a limit cycle (a face crossed kMostVisits times: round a
    // vortex the field makes at a sharp tip, a closed streamline, a spiral), or one that keeps
    // crossing faces without getting anywhere. Either is deleted before the next round.
    if (st.arc > cap || ++st.steps > 2 * m.num_faces() || crossings(id, f) >= kMostVisits) {
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

  // Lays a finished trace down before the others run (a connection between two nodes): every
  // trace that reaches it stops there.
  template <class Piece>
  void lay(uint32_t id, Trace trace, const std::vector<Piece>& pieces) {
    for (const Piece& pc : pieces) {
      segments.push_back({id, pc.from, pc.to, -INFINITY});
      face_segments[pc.face].push_back(uint32_t(segments.size() - 1));
    }
    result.traces[id] = std::move(trace);
    state[id].alive = false;
    ++result.connections;
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

// A separatrix from one node into another (FIELD_LAYOUT.md §3 rule 3): the two ends of one
// streamline of the field, which traced from both ends would pass each other a triangle or two
// apart and leave a sliver between them. Laid before the motorcycle graph runs, so every other
// trace stops on it.
struct Connection {
  uint32_t ray_a = 0, ray_b = 0;  // the ray traced, and the ray of the node it reaches
  Trace trace;
  std::vector<FacePiece> pieces;  // per face crossed
};

// Nodes near a point, on a grid of cells the capture radius wide.
class NodeGrid {
 public:
  NodeGrid(const TriMesh& m, const std::vector<uint32_t>& nodes, double cell) : m_(m), cell_(cell) {
    for (uint32_t n = 0; n < nodes.size(); ++n)
      cells_[key(cell_of(m.position(nodes[n])))].push_back(n);
  }

  // Nodes within `radius` (≤ the cell) of segment a-b may lie in any cell its box touches.
  template <class F>
  void near(const Vec3& a, const Vec3& b, F&& visit) const {
    const auto lo = cell_of(Vec3{std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)});
    const auto hi = cell_of(Vec3{std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)});
    for (int64_t i = lo[0] - 1; i <= hi[0] + 1; ++i)
      for (int64_t j = lo[1] - 1; j <= hi[1] + 1; ++j)
        for (int64_t k = lo[2] - 1; k <= hi[2] + 1; ++k)
          if (const auto it = cells_.find(key({i, j, k})); it != cells_.end())
            for (uint32_t n : it->second) visit(n);
  }

 private:
  std::array<int64_t, 3> cell_of(const Vec3& p) const {
    return {int64_t(std::floor(p.x / cell_)), int64_t(std::floor(p.y / cell_)),
            int64_t(std::floor(p.z / cell_))};
  }
  static uint64_t key(const std::array<int64_t, 3>& c) {
    return (uint64_t(c[0]) * 73856093u) ^ (uint64_t(c[1]) * 19349663u) ^
           (uint64_t(c[2]) * 83492791u);
  }
  const TriMesh& m_;
  double cell_;
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
};

// Whether two pieces in one face's chart cross (touching at an end does not count).
bool pieces_cross(P2 a, P2 b, P2 c, P2 d) {
  const P2 r = b - a, e = d - c;
  const double den = cross(r, e);
  if (den == 0) return false;
  const double t = cross(c - a, e) / den, u = cross(c - a, r) / den;
  constexpr double kEnd = 1e-9;
  return t > kEnd && t < 1 - kEnd && u > kEnd && u < 1 - kEnd;
}

// Traces every ray alone and, where it first passes within `radius` of a node coming in along one
// of the node's rays, steers it into that node over the last stretch. The connections found,
// shortest first, are kept where neither ray is taken yet and they cross no kept connection.
std::vector<Connection> find_connections(const CrossField& cf, const std::vector<Ray>& rays,
                                         const std::vector<uint32_t>& ray_node,
                                         const std::vector<uint32_t>& nodes, double radius,
                                         double cap) {
  const TriMesh& m = cf.surface;
  Tracer free(cf, cap);
  free.interact = false;
  const NodeGrid grid(m, nodes, radius);
  std::vector<std::vector<uint32_t>> node_rays(nodes.size());
  std::vector<Vec3> ray_dir(rays.size());
  for (uint32_t r = 0; r < rays.size(); ++r) {
    node_rays[ray_node[r]].push_back(r);
    ray_dir[r] = ray_direction3(cf, rays[r]);
  }
  const double from_behind = std::cos(kPi / 6), head_on = std::cos(5 * kPi / 36);
  std::vector<Connection> found;
  for (uint32_t a = 0; a < rays.size(); ++a) {
    const uint32_t id = free.start(rays[a]);
    const std::size_t first_segment = free.segments.size();
    uint32_t target = kInvalid, ray_b = kInvalid;
    Vec3 along;
    while (target == kInvalid && free.state[id].alive) {
      const std::size_t before = free.segments.size();
      free.step(id);
      for (std::size_t sid = before; sid < free.segments.size() && target == kInvalid; ++sid) {
        const Segment& sg = free.segments[sid];
        const uint32_t f = free.result.traces[id].faces[sid - first_segment];
        const Vec3 p = free.position(f, sg.from), q = free.position(f, sg.to);
        const Vec3 pq = q - p;
        const double len2 = dot(pq, pq);
        if (!(len2 > 0)) continue;
        const Vec3 dir = pq / std::sqrt(len2);
        double nearest = radius;
        grid.near(p, q, [&](uint32_t n) {
          const Vec3 x = m.position(nodes[n]);
          const double t = std::clamp(dot(x - p, pq) / len2, 0.0, 1.0);
          const double dist = norm(p + t * pq - x);
          if (dist >= nearest) return;
          // Back at its own node only after going round something (a loop), by another ray.
          if (n == ray_node[a] && sg.arc + t * std::sqrt(len2) < 4 * radius) return;
          // It comes in along ray b if, seen from the node, where it was twice the radius
          // before lies within 30 degrees of b: near a node the field turns fast, so its own
          // direction there says less than where it came from. (A trace parallel to b passing
          // at the capture radius is seen at atan(1/2) = 26.6 degrees: with 20, a pass farther
          // than 0.73 radius was captured only head-on, else it stopped beside the node.)
          const double arc = sg.arc + t * std::sqrt(len2);
          std::size_t k = sid;
          while (k > first_segment && free.segments[k].arc > arc - 2 * radius) --k;
          const Vec3 back =
              free.position(free.result.traces[id].faces[k - first_segment], free.segments[k].from);
          const Vec3 w = back - x;
          const double wn = norm(w);
          if (!(wn > 0)) return;
          // Or if its own direction there is within 25 degrees of b's, reversed.
          double best = 0;
          for (uint32_t b : node_rays[n]) {
            if (b == a || dot(dir, ray_dir[b]) >= 0) continue;
            const double c =
                std::max(dot(w, ray_dir[b]) / wn - from_behind, -dot(dir, ray_dir[b]) - head_on);
            if (c <= best) continue;
            best = c, nearest = dist, target = n, ray_b = b, along = dir;
          }
        });
      }
    }
    if (target == kInvalid) continue;
    // Join where the node is still well ahead (twice as far along as aside), so the steered
    // stretch bends the trace by at most 27 degrees.
    const Trace& t = free.result.traces[id];
    const Vec3 x = m.position(nodes[target]);
    std::size_t j = 0;
    for (std::size_t k = t.faces.size(); k-- > 1;) {
      const Vec3 w = x - position_on(m, t.points[k]);
      const double ahead = dot(w, along);
      if (ahead >= 0 && ahead >= 2 * norm(w - ahead * along)) {
        j = k;
        break;
      }
    }
    Connection c;
    c.ray_a = a;
    c.ray_b = ray_b;
    c.trace.source = t.source;
    c.trace.first_face = t.first_face;
    c.trace.first_arm = t.first_arm;
    c.trace.points.assign(t.points.begin(), t.points.begin() + std::ptrdiff_t(j + 1));
    c.trace.on_edge.assign(t.on_edge.begin(), t.on_edge.begin() + std::ptrdiff_t(j + 1));
    c.trace.faces.assign(t.faces.begin(), t.faces.begin() + std::ptrdiff_t(j));
    for (std::size_t k = 0; k < j; ++k) {
      const Segment& sg = free.segments[first_segment + k];
      c.pieces.push_back({t.faces[k], sg.from, sg.to});
      c.trace.length += length(sg.to - sg.from);
    }
    // Steered: in each face straight towards the node, until a face has it as a corner.
    uint32_t f = t.faces[j], entry = kInvalid;
    const P2 p = free.segments[first_segment + j].from;
    if (j > 0)
      for (uint32_t i = 0; i < 3; ++i)
        if (m.edge(3 * f + i) == t.on_edge[j].edge) entry = 3 * f + i;
    const uint32_t v = nodes[target];
    if (!free.steer(f, p, entry, v, c.trace, c.pieces)) continue;
    c.trace.end = TraceEnd::node;
    c.trace.end_vertex = v;
    found.push_back(std::move(c));
  }
  // Shortest first; each ray in one connection at most; connections cross no other.
  std::vector<uint32_t> order(found.size());
  for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](uint32_t x, uint32_t y) {
    return found[x].trace.length < found[y].trace.length ||
           (found[x].trace.length == found[y].trace.length && found[x].ray_a < found[y].ray_a);
  });
  std::vector<char> taken(rays.size(), 0);
  std::vector<std::vector<std::pair<P2, P2>>> laid(m.num_faces());
  std::vector<Connection> kept;
  for (uint32_t i : order) {
    Connection& c = found[i];
    if (taken[c.ray_a] || taken[c.ray_b]) continue;
    const bool crosses = std::any_of(c.pieces.begin(), c.pieces.end(), [&](const auto& pc) {
      return std::any_of(laid[pc.face].begin(), laid[pc.face].end(), [&](const auto& other) {
        return pieces_cross(pc.from, pc.to, other.first, other.second);
      });
    });
    if (crosses) continue;
    taken[c.ray_a] = taken[c.ray_b] = 1;
    for (const auto& pc : c.pieces) laid[pc.face].push_back({pc.from, pc.to});
    kept.push_back(std::move(c));
  }
  return kept;
}

struct Strips {
  std::vector<uint32_t> drop;                 // traces to delete, first the most urgent
  std::vector<std::vector<uint32_t>> beside;  // per trace, the traces it runs beside
};

// The traces that found no end, and those that run closer than `width` beside a parallel track
// (within 20 degrees) along at least half of their length: another trace, a feature, the
// boundary, or the trace itself further on (a spiral).
Strips strip_traces(const Tracer& tracer, const TraceResult& result, double width, double gap) {
  const TriMesh& m = tracer.m;
  struct Piece {
    Vec3 p, q;
    uint32_t trace;  // kInvalid: a feature or boundary edge
    double arc;
  };
  std::vector<Piece> pieces;
  std::vector<std::vector<uint32_t>> of_trace(result.traces.size());
  for (uint32_t f = 0; f < m.num_faces(); ++f)
    for (uint32_t sid : tracer.face_segments[f]) {
      const Segment& sg = tracer.segments[sid];
      of_trace[sg.trace].push_back(uint32_t(pieces.size()));
      pieces.push_back({tracer.position(f, sg.from), tracer.position(f, sg.to), sg.trace,
                        std::isfinite(sg.arc) ? sg.arc : 0.0});
    }
  for (uint32_t e = 0; e < m.num_edges(); ++e) {
    const uint32_t h = m.edge_halfedge(e);
    if (m.twin(h) == kInvalid || tracer.cf.feature[e])
      pieces.push_back({m.position(m.from(h)), m.position(m.to(h)), kInvalid, 0});
  }
  std::unordered_map<uint64_t, std::vector<uint32_t>> grid;
  auto cell = [&](const Vec3& x) {
    return std::array<int64_t, 3>{int64_t(std::floor(x.x / width)),
                                  int64_t(std::floor(x.y / width)),
                                  int64_t(std::floor(x.z / width))};
  };
  auto key = [](int64_t i, int64_t j, int64_t k) {
    return (uint64_t(i) * 73856093u) ^ (uint64_t(j) * 19349663u) ^ (uint64_t(k) * 83492791u);
  };
  for (uint32_t i = 0; i < pieces.size(); ++i) {
    // A piece longer than a few cells (a coarse mesh) is filed in the cells of its samples.
    const double len = norm(pieces[i].q - pieces[i].p);
    const int samples = std::min(64, 1 + int(len / width));
    std::vector<uint64_t> keys;
    for (int sidx = 0; sidx <= samples; ++sidx) {
      const auto c = cell(pieces[i].p + (double(sidx) / samples) * (pieces[i].q - pieces[i].p));
      keys.push_back(key(c[0], c[1], c[2]));
    }
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    for (uint64_t k : keys) grid[k].push_back(i);
  }
  const double parallel = std::cos(kPi / 9);
  Strips out;
  out.beside.resize(result.traces.size());
  std::vector<std::pair<double, uint32_t>> ranked;  // (urgency, trace)
  for (uint32_t id = 0; id < result.traces.size(); ++id) {
    const Trace& t = result.traces[id];
    if (t.end == TraceEnd::cap || t.end == TraceEnd::sink) {
      ranked.push_back({2.0, id});
      continue;
    }
    if (t.end == TraceEnd::node || !(t.length > 0)) continue;  // connections stay
    double beside = 0;
    for (uint32_t i : of_trace[id]) {
      const Piece& pc = pieces[i];
      const Vec3 d = pc.q - pc.p;
      const double len = norm(d);
      if (!(len > 0)) continue;
      const Vec3 dir = d / len, mid = 0.5 * (pc.p + pc.q);
      const auto c = cell(mid);
      bool found = false;
      for (int64_t a = c[0] - 1; a <= c[0] + 1; ++a)
        for (int64_t b = c[1] - 1; b <= c[1] + 1; ++b)
          for (int64_t k = c[2] - 1; k <= c[2] + 1; ++k) {
            const auto it = grid.find(key(a, b, k));
            if (it == grid.end()) continue;
            for (uint32_t j : it->second) {
              const Piece& o = pieces[j];
              if (o.trace == id && std::abs(o.arc - pc.arc) < 4 * width) continue;
              const Vec3 e = o.q - o.p;
              const double elen2 = dot(e, e);
              if (!(elen2 > 0) || std::abs(dot(e, dir)) < parallel * std::sqrt(elen2)) continue;
              const double s = std::clamp(dot(mid - o.p, e) / elen2, 0.0, 1.0);
              if (norm(o.p + s * e - mid) >= width) continue;
              found = true;
              if (o.trace != kInvalid && o.trace != id &&
                  std::find(out.beside[id].begin(), out.beside[id].end(), o.trace) ==
                      out.beside[id].end())
                out.beside[id].push_back(o.trace);
            }
          }
      if (found) beside += len;
    }
    if (beside >= 0.5 * t.length) ranked.push_back({beside / t.length, id});
  }
  // Two points of one track closer than `gap`: a trace that stops there, beside another trace's
  // end or a node. The meta-edge between them is shorter than a quad, so the integer lengths
  // stretch it to one, or cannot: a strip that closes around a tube a fraction of a quad away
  // from where it started forces that fraction to zero. Each such end is a candidate, the
  // closest first; deleting one frees the traces that stopped on it.
  if (gap > 0) {
    const std::size_t n = result.traces.size();
    std::vector<Vec3> end(n);
    for (uint32_t id = 0; id < n; ++id)
      if (!result.traces[id].points.empty())
        end[id] = position_on(m, result.traces[id].points.back());
    // The ends by what they stopped on: a trace, or (kInvalid) a feature or the boundary.
    std::unordered_map<uint32_t, std::vector<uint32_t>> on_track;
    for (uint32_t id = 0; id < n; ++id) {
      const TraceEnd e = result.traces[id].end;
      if (e == TraceEnd::track) on_track[result.traces[id].end_trace].push_back(id);
      if (e == TraceEnd::boundary || e == TraceEnd::feature) on_track[kInvalid].push_back(id);
    }
    const NodeGrid nodes(m, result.nodes, gap);
    std::vector<double> nearest(n, INFINITY);
    for (const auto& [track, ends] : on_track)
      for (const uint32_t a : ends) {
        for (const uint32_t b : ends) {
          const double d = norm(end[a] - end[b]);
          if (b == a || d >= nearest[a]) continue;
          nearest[a] = d;
          if (std::find(out.beside[a].begin(), out.beside[a].end(), b) == out.beside[a].end())
            out.beside[a].push_back(b);
        }
        // A node near the end, the track's own source among them (not the trace's own).
        nodes.near(end[a], end[a], [&](uint32_t k) {
          if (result.nodes[k] != result.traces[a].source)
            nearest[a] = std::min(nearest[a], norm(end[a] - m.position(result.nodes[k])));
        });
      }
    for (uint32_t id = 0; id < n; ++id) {
      if (!(nearest[id] < gap)) continue;
      const bool listed =
          std::any_of(ranked.begin(), ranked.end(), [&](const auto& r) { return r.second == id; });
      if (!listed) ranked.push_back({1 + (1 - nearest[id] / gap) / 2, id});
    }
  }
  std::sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) {
    return a.first > b.first || (a.first == b.first && a.second < b.second);
  });
  for (const auto& [urgency, id] : ranked) out.drop.push_back(id);
  return out;
}

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
  const Charts charts(m, cf.frames);
  std::vector<uint32_t> nodes;
  std::vector<char> interior;
  uint32_t mismatches = 0;
  VertexData<char> singular(m.num_vertices(), 0);
  for (uint32_t v : cf.singular) singular[v] = 1;
  VertexData<char> seed(m.num_vertices(), 0);
  for (uint32_t v : options.seeds) seed[v] = 1;
  std::vector<Ray> rays;
  std::vector<uint32_t> ray_node;
  for (uint32_t v = 0; v < m.num_vertices(); ++v) {
    bool on_constraint = false;
    m.for_each_outgoing(v, [&](uint32_t h) {
      on_constraint =
          on_constraint || is_constraint(cf, m, h) || m.twin(TriMesh::prev(h)) == kInvalid;
    });
    const bool node =
        on_constraint ? singular[v] || is_constraint_node(cf, m, v) : singular[v] || seed[v];
    if (!node) continue;
    std::vector<Ray> at;
    if (!on_constraint && 4 - cf.index4[v] > 0) {
      at = interior_rays(cf, charts, m, v, 4 - cf.index4[v]);
    } else {
      at = rays_at(cf, charts, m, v);
      sort_rays_around(cf, charts, m, v, at);
    }
    if (!on_constraint && at.size() != std::size_t(4 - cf.index4[v])) ++mismatches;
    if (at.empty()) continue;
    for (const Ray& r : at) {
      rays.push_back(r);
      ray_node.push_back(uint32_t(nodes.size()));
    }
    nodes.push_back(v);
    interior.push_back(!on_constraint);
  }
  std::vector<Connection> connections;
  if (options.capture > 0 && options.edge_length > 0)
    connections =
        find_connections(cf, rays, ray_node, nodes, options.capture * options.edge_length, cap);
  // A ray a connection reaches is that connection: not traced on its own.
  std::vector<char> reached(rays.size(), 0), fixed(rays.size(), 0), deleted(rays.size(), 0);
  for (const Connection& c : connections) reached[c.ray_b] = fixed[c.ray_a] = 1;
  // Deletes ray r unless it is a connection's or a neighbouring ray of its node is deleted (a
  // sector of three quarter turns has no place in a quad layout).
  auto delete_ray = [&](uint32_t r) {
    if (fixed[r] || reached[r] || deleted[r]) return false;
    const uint32_t n = ray_node[r];
    uint32_t first = r, last = r;
    while (first > 0 && ray_node[first - 1] == n) --first;
    while (last + 1 < rays.size() && ray_node[last + 1] == n) ++last;
    const uint32_t count = last - first + 1;
    auto neighbour = [&](int step) -> uint32_t {
      if (!interior[n]) {
        const int64_t k = int64_t(r) + step;
        return k < int64_t(first) || k > int64_t(last) ? kInvalid : uint32_t(k);
      }
      return first + uint32_t((int64_t(r - first) + step + count) % count);
    };
    const uint32_t before = neighbour(-1), after = neighbour(1);
    if ((before != kInvalid && deleted[before]) || (after != kInvalid && deleted[after]))
      return false;
    deleted[r] = 1;
    return true;
  };
  for (const RayId& id : options.removed)
    for (uint32_t r = 0; r < rays.size(); ++r)
      if (RayId{rays[r].vertex, rays[r].face, rays[r].arm} == id) delete_ray(r);
  TraceResult result;
  for (uint32_t round = 0;; ++round) {
    Tracer tracer(cf, cap);
    std::vector<uint32_t> id_of(rays.size(), kInvalid), ray_of;
    for (uint32_t r = 0; r < rays.size(); ++r)
      if (!reached[r] && !deleted[r]) {
        id_of[r] = tracer.start(rays[r]);
        ray_of.push_back(r);
      }
    for (const Connection& c : connections) tracer.lay(id_of[c.ray_a], Trace(c.trace), c.pieces);
    tracer.run();
    tracer.result.nodes = nodes;
    tracer.result.ray_mismatches = mismatches;
    tracer.result.rounds = round + 1;
    result = std::move(tracer.result);
    if (round + 1 >= options.rounds || options.strip <= 0 || options.edge_length <= 0) break;
    const Strips strips = strip_traces(tracer, result, options.strip * options.edge_length,
                                       options.gap * options.edge_length);
    // Traces that bound a strip together lose one.
    bool any = false;
    std::vector<char> partner_gone(result.traces.size(), 0);
    for (uint32_t id : strips.drop) {
      if (partner_gone[id] || !delete_ray(ray_of[id])) continue;
      any = true;
      for (uint32_t other : strips.beside[id]) partner_gone[other] = 1;
    }
    if (!any) break;
  }
  for (uint32_t r = 0; r < rays.size(); ++r) {
    if (!deleted[r]) continue;
    ++result.deleted;
    const uint32_t v = nodes[ray_node[r]];
    if (result.partial_nodes.empty() || result.partial_nodes.back() != v)
      result.partial_nodes.push_back(v);
  }
  return result;
}

}  // namespace isoquad
