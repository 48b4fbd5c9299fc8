#include "param/seam_system.hpp"

#include <fmt/format.h>

#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>
#include <Eigen/UmfPackSupport>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <optional>

#include "isoquad/error.hpp"

namespace isoquad {

namespace {

using SpMat = Eigen::SparseMatrix<double>;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// R^k applied to p (counter-clockwise quarter turns).
UV rotate_uv(const UV& p, int k) {
  switch (k & 3) {
    case 1:
      return {-p[1], p[0]};
    case 2:
      return {-p[0], -p[1]};
    case 3:
      return {p[1], -p[0]};
    default:
      return p;
  }
}

// Entry (r, c) of R^k.
double rotation_entry(int k, int r, int c) {
  static constexpr double kR[4][2][2] = {
      {{1, 0}, {0, 1}}, {{0, -1}, {1, 0}}, {{-1, 0}, {0, -1}}, {{0, 1}, {-1, 0}}};
  return kR[k & 3][r][c];
}

// tan(alpha/2) of the angle at p between q and r, without acos (DESIGN.md §7.3), clamped so that
// alpha stays in [1e-8, pi - 1e-6] and the weight stays positive and finite.
double half_angle_tangent(const Vec3& p, const Vec3& q, const Vec3& r) {
  const Vec3 a = q - p, b = r - p;
  const double num = norm(cross(a, b));
  const double den = norm(a) * norm(b) + dot(a, b);
  static const double lo = std::tan(0.5e-8);
  static const double hi = std::tan(0.5 * (std::numbers::pi - 1e-6));
  if (!(den > 0)) return hi;
  return std::clamp(num / den, lo, hi);
}

}  // namespace

struct SeamSystem::Impl {
  const TriMesh& mesh;
  const FaceData<uint32_t>& labels;
  const MetaMesh& meta;
  const Layout& layout;
  WeightKind kind;

  VertexData<uint32_t> home;
  VertexData<UV> chord;      // seam vertices: chord-length position on the side, home chart
  VertexData<uint32_t> var;  // unknown index or kInvalid (fixed)
  std::vector<char> always_locked;
  EdgeData<uint32_t> edge_meta;

  // Per face corner: the transform from the vertex's home chart into the face's chart
  // (k quarter turns, then + t), or the fixed position of a meta-vertex in the face's chart.
  FaceData<std::array<int8_t, 3>> corner_k;  // -1 marks a meta-vertex (t is its position)
  FaceData<std::array<UV, 3>> corner_t;
  // Per face corner a and s in {0, 1}: the weight of corner (a + 1 + s) % 3 in a's equation.
  FaceData<std::array<std::array<double, 2>, 3>> weight;

  SpMat A;
  std::vector<std::array<int32_t, 4>> pair_slot;  // 6 per face: (a, s) -> block slots or -1
  std::vector<std::array<int32_t, 2>> diag_slot;  // per unknown: the (0,0) and (1,1) slots
  uint32_t n = 0;
  bool analyzed = false;
  // Simplicial: on these sparse 2D-like systems it beats the supernodal factorization.
  Eigen::CholmodSimplicialLLT<SpMat, Eigen::Lower> llt;
  Eigen::UmfPackLU<SpMat> lu;

  Impl(const TriMesh& m, const FaceData<uint32_t>& l, const MetaMesh& mm, const Layout& lay,
       WeightKind k)
      : mesh(m), labels(l), meta(mm), layout(lay), kind(k) {
    setup_charts();
    setup_weights();
    setup_pattern();
  }

  Lattice lattice_of(uint32_t mv, uint32_t patch) const {
    const MetaFace& face = meta.faces[patch];
    for (uint32_t i = 0; i < face.cycle.size(); ++i)
      if (face.start_vertex(i, meta.edges) == mv) return layout.charts[patch].item_position[i];
    throw Error(ErrorKind::internal, "E700",
                fmt::format("meta-vertex {} is not on the boundary of patch {}", mv, patch));
  }

  void setup_charts() {
    const uint32_t nv = mesh.num_vertices();
    home = VertexData<uint32_t>(nv, kInvalid);
    chord = VertexData<UV>(nv, UV{0, 0});
    var = VertexData<uint32_t>(nv, kInvalid);
    always_locked.assign(meta.edges.size(), 0);
    edge_meta = EdgeData<uint32_t>(mesh.num_edges(), kInvalid);
    for (uint32_t e = 0; e < meta.edges.size(); ++e) {
      const MetaEdge& me = meta.edges[e];
      always_locked[e] = me.feature || me.right == kInvalid;
      for (const uint32_t h : me.halfedges) edge_meta[mesh.edge(h)] = e;
      // Chord-length positions on the straight side in the left chart.
      const Lattice a = lattice_of(me.mv0, me.left), b = lattice_of(me.mv1, me.left);
      std::vector<double> arc(me.vertices.size(), 0.0);
      for (std::size_t i = 1; i < me.vertices.size(); ++i)
        arc[i] =
            arc[i - 1] + norm(mesh.position(me.vertices[i]) - mesh.position(me.vertices[i - 1]));
      const double total = arc.back() > 0 ? arc.back() : 1.0;
      for (std::size_t i = 1; i + 1 < me.vertices.size(); ++i) {
        const double s = arc[i] / total;
        const uint32_t v = me.vertices[i];
        chord[v] = {double(a[0]) + s * double(b[0] - a[0]), double(a[1]) + s * double(b[1] - a[1])};
        home[v] = me.left;
      }
    }
    for (uint32_t v = 0; v < nv; ++v) {
      if (meta.vertex_meta_vertex[v] != kInvalid) continue;
      const uint32_t e = meta.vertex_meta_edge[v];
      if (e == kInvalid) {
        if (mesh.is_boundary_vertex(v))
          throw Error(ErrorKind::internal, "E700",
                      fmt::format("mesh-boundary vertex {} is on no meta-edge", v));
        home[v] = labels[TriMesh::face_of(mesh.outgoing(v))];
      }
      if (e == kInvalid || !always_locked[e]) var[v] = n++;
    }
    corner_k = FaceData<std::array<int8_t, 3>>(mesh.num_faces());
    corner_t = FaceData<std::array<UV, 3>>(mesh.num_faces());
    for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
      const uint32_t p = labels[f];
      for (int c = 0; c < 3; ++c) {
        const uint32_t v = mesh.face(f)[c];
        const uint32_t mv = meta.vertex_meta_vertex[v];
        if (mv != kInvalid) {
          const Lattice q = lattice_of(mv, p);
          corner_k[f][c] = -1;
          corner_t[f][c] = {double(q[0]), double(q[1])};
        } else if (home[v] == p) {
          corner_k[f][c] = 0;
          corner_t[f][c] = {0, 0};
        } else {
          const uint32_t e = meta.vertex_meta_edge[v];
          if (e == kInvalid || meta.edges[e].right != p)
            throw Error(
                ErrorKind::internal, "E700",
                fmt::format("vertex {} of face {} has no transition into patch {}", v, f, p));
          const Transition& t = layout.transition[e];
          corner_k[f][c] = int8_t(t.k);
          corner_t[f][c] = {double(t.t[0]), double(t.t[1])};
        }
      }
    }
  }

  void setup_weights() {
    weight = FaceData<std::array<std::array<double, 2>, 3>>(mesh.num_faces());
    for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
      const Tri& t = mesh.face(f);
      std::array<Vec3, 3> p;
      for (int c = 0; c < 3; ++c) p[c] = mesh.position(t[c]);
      std::array<double, 3> tan_half, len;  // len[c]: edge from corner c to c + 1
      for (int c = 0; c < 3; ++c) {
        tan_half[c] = half_angle_tangent(p[c], p[(c + 1) % 3], p[(c + 2) % 3]);
        len[c] = std::max(norm(p[(c + 1) % 3] - p[c]), 1e-12);
      }
      // omega(a -> b) = tan(angle at a / 2) / |ab| (Floater's weight, split per face).
      auto omega = [&](int a, int b) {
        const int e = (b == (a + 1) % 3) ? a : b;  // the edge between a and b
        return tan_half[a] / len[e];
      };
      for (int a = 0; a < 3; ++a)
        for (int s = 0; s < 2; ++s) {
          const int b = (a + 1 + s) % 3;
          weight[f][a][s] =
              kind == WeightKind::mvc ? omega(a, b) : 0.5 * (omega(a, b) + omega(b, a));
        }
    }
  }

  int32_t find_slot(uint32_t row, uint32_t col) const {
    const int32_t* begin = A.innerIndexPtr() + A.outerIndexPtr()[col];
    const int32_t* end = A.innerIndexPtr() + A.outerIndexPtr()[col + 1];
    const int32_t* it = std::lower_bound(begin, end, int32_t(row));
    return int32_t(it - A.innerIndexPtr());
  }

  void setup_pattern() {
    std::vector<Eigen::Triplet<double>> trip;
    trip.reserve(std::size_t(mesh.num_faces()) * 24 + 4 * n);
    // A block R^m has entries on its diagonal (m even) or off it (m odd), never both: the u and
    // v of two vertices in the same chart are not coupled, which halves the fill.
    auto block = [&](uint32_t ri, uint32_t rj, int m) {
      for (int r = 0; r < 2; ++r)
        for (int c = 0; c < 2; ++c)
          if (rotation_entry(m, r, c) != 0) trip.emplace_back(2 * ri + r, 2 * rj + c, 0.0);
    };
    for (uint32_t r = 0; r < n; ++r) block(r, r, 0);
    for (uint32_t f = 0; f < mesh.num_faces(); ++f)
      for (int a = 0; a < 3; ++a)
        for (int s = 0; s < 2; ++s) {
          const int b = (a + 1 + s) % 3;
          const uint32_t i = var[mesh.face(f)[a]], j = var[mesh.face(f)[b]];
          if (i != kInvalid && j != kInvalid) block(i, j, corner_k[f][b] - corner_k[f][a]);
        }
    A.resize(2 * n, 2 * n);
    A.setFromTriplets(trip.begin(), trip.end());  // explicit zeros are kept
    A.makeCompressed();
    diag_slot.resize(n);
    for (uint32_t r = 0; r < n; ++r)
      diag_slot[r] = {find_slot(2 * r, 2 * r), find_slot(2 * r + 1, 2 * r + 1)};
    pair_slot.assign(std::size_t(mesh.num_faces()) * 6, {-1, -1, -1, -1});
    for (uint32_t f = 0; f < mesh.num_faces(); ++f)
      for (int a = 0; a < 3; ++a)
        for (int s = 0; s < 2; ++s) {
          const uint32_t i = var[mesh.face(f)[a]], j = var[mesh.face(f)[(a + 1 + s) % 3]];
          if (i == kInvalid || j == kInvalid) continue;
          const int m = corner_k[f][(a + 1 + s) % 3] - corner_k[f][a];
          auto& slot = pair_slot[6 * f + 2 * a + s];
          for (int r = 0; r < 2; ++r)
            for (int c = 0; c < 2; ++c)
              if (rotation_entry(m, r, c) != 0) slot[2 * r + c] = find_slot(2 * i + r, 2 * j + c);
        }
  }

  bool is_locked(uint32_t v, const std::vector<char>& locked) const {
    const uint32_t e = meta.vertex_meta_edge[v];
    return e != kInvalid && locked[e];
  }

  // The position of a fixed corner (meta-vertex or locked seam vertex) in the face's chart.
  UV fixed_uv(uint32_t f, int c) const {
    if (corner_k[f][c] < 0) return corner_t[f][c];
    const UV r = rotate_uv(chord[mesh.face(f)[c]], corner_k[f][c]);
    return {r[0] + corner_t[f][c][0], r[1] + corner_t[f][c][1]};
  }

  void assemble(const EdgeData<double>& stiffness, const std::vector<char>& locked,
                Eigen::VectorXd& rhs) {
    double* val = A.valuePtr();
    std::fill(val, val + A.nonZeros(), 0.0);
    rhs.setZero(2 * n);
    for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
      const Tri& t = mesh.face(f);
      for (int a = 0; a < 3; ++a) {
        const uint32_t i = var[t[a]];
        if (i == kInvalid || is_locked(t[a], locked)) continue;
        const int ka = corner_k[f][a];
        const UV ta = corner_t[f][a];
        for (int s = 0; s < 2; ++s) {
          const int b = (a + 1 + s) % 3;
          const uint32_t h = 3 * f + (s == 0 ? a : b);  // the halfedge between a and b
          const double w = stiffness[mesh.edge(h)] * weight[f][a][s];
          val[diag_slot[i][0]] += w;
          val[diag_slot[i][1]] += w;
          const uint32_t j = var[t[b]];
          UV d;  // w R^{-ka} (c_b - t_a), the known part of uv_f(b) - t_a
          if (j != kInvalid && !is_locked(t[b], locked)) {
            const int m = corner_k[f][b] - ka;
            const auto& slot = pair_slot[6 * f + 2 * a + s];
            for (int r = 0; r < 2; ++r)
              for (int c = 0; c < 2; ++c)
                if (slot[2 * r + c] >= 0) val[slot[2 * r + c]] -= w * rotation_entry(m, r, c);
            d = {corner_t[f][b][0] - ta[0], corner_t[f][b][1] - ta[1]};
          } else {
            const UV cb = fixed_uv(f, b);
            d = {cb[0] - ta[0], cb[1] - ta[1]};
          }
          const UV rd = rotate_uv(d, -ka);
          rhs[2 * i] += w * rd[0];
          rhs[2 * i + 1] += w * rd[1];
        }
      }
    }
    for (uint32_t v = 0; v < mesh.num_vertices(); ++v) {
      const uint32_t i = var[v];
      if (i == kInvalid || !is_locked(v, locked)) continue;
      val[diag_slot[i][0]] = 1;
      val[diag_slot[i][1]] = 1;
      rhs[2 * i] = chord[v][0];
      rhs[2 * i + 1] = chord[v][1];
    }
  }

  template <class Solver>
  Eigen::VectorXd factor_and_solve(Solver& solver, const Eigen::VectorXd& rhs,
                                   ParamReport& report) {
    auto t0 = Clock::now();
    if (!analyzed) {
      // Nested dissection (METIS) halves the factorization's work on large 2D-like graphs but
      // costs more than AMD to compute; it pays from a few tens of thousands of vertices on.
      if constexpr (requires { solver.cholmod(); }) {
        solver.cholmod().nmethods = 1;
        solver.cholmod().method[0].ordering = A.rows() > 60000 ? CHOLMOD_METIS : CHOLMOD_AMD;
      }
      solver.analyzePattern(A);
      analyzed = true;
      ++report.symbolic;
      report.analyze_seconds += seconds_since(t0);
      t0 = Clock::now();
    }
    solver.factorize(A);
    ++report.factorizations;
    report.factorize_seconds += seconds_since(t0);
    if (solver.info() != Eigen::Success)
      throw Error(ErrorKind::solver, "E551",
                  fmt::format("the parametrization matrix ({} unknowns) could not be factorized; "
                              "the input likely has degenerate triangles - try --repair",
                              n));
    t0 = Clock::now();
    Eigen::VectorXd x = solver.solve(rhs);
    ++report.solves;
    const double scale = std::max(rhs.norm(), 1e-300);
    double residual = (rhs - A * x).norm() / scale;
    for (int step = 0; step < 2 && residual > 1e-14; ++step) {  // iterative refinement
      const Eigen::VectorXd r = rhs - A * x;
      x += solver.solve(r);
      ++report.solves;
      residual = (rhs - A * x).norm() / scale;
    }
    report.solve_seconds += seconds_since(t0);
    report.max_residual = std::max(report.max_residual, residual);
    if (!(residual < 1e-10))
      throw Error(ErrorKind::solver, "E552",
                  fmt::format("the parametrization solve stays inaccurate (relative residual "
                              "{:.1e}); the input likely has extreme triangles - try --repair",
                              residual));
    return x;
  }

  ParamMap solve(const EdgeData<double>& stiffness, const std::vector<char>& locked,
                 ParamReport& report) {
    auto t0 = Clock::now();
    Eigen::VectorXd rhs;
    assemble(stiffness, locked, rhs);
    report.assemble_seconds += seconds_since(t0);
    const Eigen::VectorXd x = n == 0
                                  ? Eigen::VectorXd()
                                  : (kind == WeightKind::smvc ? factor_and_solve(llt, rhs, report)
                                                              : factor_and_solve(lu, rhs, report));
    ParamMap map;
    map.home = home;
    map.position = VertexData<UV>(mesh.num_vertices(), UV{0, 0});
    for (uint32_t v = 0; v < mesh.num_vertices(); ++v) {
      if (meta.vertex_meta_vertex[v] != kInvalid) continue;
      const uint32_t i = var[v];
      map.position[v] =
          (i == kInvalid || is_locked(v, locked)) ? chord[v] : UV{x[2 * i], x[2 * i + 1]};
    }
    map.uv = FaceData<std::array<UV, 3>>(mesh.num_faces());
    for (uint32_t f = 0; f < mesh.num_faces(); ++f)
      for (int c = 0; c < 3; ++c) {
        if (corner_k[f][c] < 0) {
          map.uv[f][c] = corner_t[f][c];
          continue;
        }
        const UV r = rotate_uv(map.position[mesh.face(f)[c]], corner_k[f][c]);
        map.uv[f][c] = {r[0] + corner_t[f][c][0], r[1] + corner_t[f][c][1]};
      }
    return map;
  }
};

SeamSystem::SeamSystem(const TriMesh& mesh, const FaceData<uint32_t>& labels, const MetaMesh& meta,
                       const Layout& layout, WeightKind weights)
    : impl_(std::make_unique<Impl>(mesh, labels, meta, layout, weights)) {}

SeamSystem::~SeamSystem() = default;

const std::vector<char>& SeamSystem::always_locked() const { return impl_->always_locked; }
const EdgeData<uint32_t>& SeamSystem::edge_meta_edge() const { return impl_->edge_meta; }
uint32_t SeamSystem::unknowns() const { return impl_->n; }

ParamMap SeamSystem::solve(const EdgeData<double>& stiffness, const std::vector<char>& locked,
                           ParamReport& report) {
  return impl_->solve(stiffness, locked, report);
}

}  // namespace isoquad
