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
#include "param/blas_runtime.hpp"

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
  const std::vector<uint32_t>* rank;  // elimination rank per vertex, or null

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
  bool patterned = false, analyzed = false;
  // Supernodal from kSupernodalUnknowns on: its dense blocks go to BLAS. bunny00's (37,732
  // unknowns) four factorizations took 1.24-1.61 s simplicial, 0.46-0.72 s supernodal on
  // OpenBLAS (1.09 s on the reference BLAS); the armadillo's (26k) 0.51 -> 0.38 s. On fandisk
  // (5,855) the supernodal one is slower, 0.022 -> 0.052 s.
  static constexpr uint32_t kSupernodalUnknowns = 10000;
  Eigen::CholmodSimplicialLLT<SpMat, Eigen::Lower> llt;
  Eigen::CholmodSupernodalLLT<SpMat, Eigen::Lower> supernodal;
  Eigen::UmfPackLU<SpMat> lu;

  Impl(const TriMesh& m, const FaceData<uint32_t>& l, const MetaMesh& mm, const Layout& lay,
       WeightKind k, const std::vector<uint32_t>* r)
      : mesh(m), labels(l), meta(mm), layout(lay), kind(k), rank(r) {
    if (rank && rank->size() != m.num_vertices())
      throw Error(ErrorKind::internal, "E700",
                  fmt::format("an elimination order of {} vertices for a mesh of {}", rank->size(),
                              m.num_vertices()));
    setup_charts();
    setup_weights();
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
    // Unknowns are numbered in elimination order when one is given (ordering.hpp).
    std::vector<uint32_t> visit(nv);
    for (uint32_t v = 0; v < nv; ++v) visit[rank ? (*rank)[v] : v] = v;
    for (const uint32_t v : visit) {
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

  // The sparsity pattern, built column by column (the system's pattern is symmetric). A block
  // R^m has entries on its diagonal (m even) or off it (m odd), never both: the u and v of two
  // vertices in the same chart are not coupled, which halves the fill. Near a singular
  // meta-vertex two unknowns may be coupled through faces of different parities: both kinds.
  void setup_pattern() {
    // Per unknown j: (i << 1 | parity) for every unknown i coupled to it, itself included.
    std::vector<std::vector<uint32_t>> near(n);
    for (uint32_t j = 0; j < n; ++j) near[j].push_back(j << 1);
    for (uint32_t f = 0; f < mesh.num_faces(); ++f)
      for (int a = 0; a < 3; ++a)
        for (int s = 0; s < 2; ++s) {
          const int b = (a + 1 + s) % 3;
          const uint32_t i = var[mesh.face(f)[a]], j = var[mesh.face(f)[b]];
          if (i != kInvalid && j != kInvalid)
            near[j].push_back(i << 1 | uint32_t((corner_k[f][b] - corner_k[f][a]) & 1));
        }
    std::size_t nnz = 0;
    for (auto& list : near) {
      std::sort(list.begin(), list.end());
      list.erase(std::unique(list.begin(), list.end()), list.end());
      nnz += 2 * list.size();
    }
    A.resize(2 * n, 2 * n);
    A.resizeNonZeros(Eigen::Index(nnz));
    int32_t* outer = A.outerIndexPtr();
    int32_t* inner = A.innerIndexPtr();
    std::fill(A.valuePtr(), A.valuePtr() + nnz, 0.0);  // explicit zeros are kept
    int32_t k = 0;
    std::vector<int32_t> rows;
    for (uint32_t j = 0; j < n; ++j)
      for (uint32_t c = 0; c < 2; ++c) {
        outer[2 * j + c] = k;
        rows.clear();
        for (const uint32_t x : near[j]) rows.push_back(int32_t(2 * (x >> 1) + ((x & 1) ^ c)));
        std::sort(rows.begin(), rows.end());
        for (const int32_t r : rows) inner[k++] = r;
      }
    outer[2 * n] = k;
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
    // On the first solve, not in the constructor: it then overlaps the locked map's solve.
    if (!patterned) setup_pattern(), patterned = true;
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

  Eigen::VectorXd factor_and_solve_relaxed(auto& solver, const Eigen::VectorXd& rhs,
                                           ParamReport& report) {
    // Nested dissection halves the factorization's work on large 2D-like graphs but costs more
    // than AMD to compute; it pays from a few tens of thousands of vertices on. There the
    // pipeline passes one of the vertex graph (ordering.hpp) that numbers the unknowns, computed
    // beside the segmentation; without it, METIS orders the system itself (the better order,
    // as it sees how seams couple u and v, but 0.43 s on bunny00 on the critical path).
    const int ordering = rank ? CHOLMOD_NATURAL : (A.rows() > 60000 ? CHOLMOD_METIS : CHOLMOD_AMD);
    return factor_and_solve(solver, A, rhs, ordering, analyzed, report);
  }

  // Factors M (the symbolic part once, on `analyzed`) and solves for every column of rhs, with up
  // to two steps of iterative refinement.
  // `ordering`: CHOLMOD's (NATURAL where M is numbered in a fill-reducing order already).
  template <class Solver, class Rhs>
  Rhs factor_and_solve(Solver& solver, const SpMat& M, const Rhs& rhs, int ordering,
                       bool& is_analyzed, ParamReport& report) const {
    const auto blas = blas_section();
    auto t0 = Clock::now();
    if (!is_analyzed) {
      if constexpr (requires { solver.cholmod(); }) {
        // CHOLMOD prints its warnings (not positive definite: coincident vertices) on stdout,
        // into a --json document; the failure is reported as an Error (E551) instead.
        solver.cholmod().print = 0;
        solver.cholmod().nmethods = 1;
        solver.cholmod().method[0].ordering = ordering;
      }
      solver.analyzePattern(M);
      is_analyzed = true;
      ++report.symbolic;
      report.analyze_seconds += seconds_since(t0);
      t0 = Clock::now();
    }
    solver.factorize(M);
    ++report.factorizations;
    report.factorize_seconds += seconds_since(t0);
    if (solver.info() != Eigen::Success)
      throw Error(ErrorKind::solver, "E551",
                  fmt::format("the parametrization matrix ({} unknowns) could not be factorized; "
                              "the input likely has degenerate triangles - try --repair",
                              M.rows()));
    t0 = Clock::now();
    Rhs x = solver.solve(rhs);
    report.solves += uint32_t(rhs.cols());
    const double scale = std::max(rhs.norm(), 1e-300);
    double residual = (rhs - M * x).norm() / scale;
    for (int step = 0; step < 2 && residual > 1e-14; ++step) {  // iterative refinement
      const Rhs r = rhs - M * x;
      x += solver.solve(r);
      report.solves += uint32_t(rhs.cols());
      residual = (rhs - M * x).norm() / scale;
    }
    report.solve_seconds += seconds_since(t0);
    report.max_residual = std::max(report.max_residual, residual);
    // The normwise backward error |b - M x| / (|M| |x| + |b|) is what tells a failed solve: a
    // Cholesky solve keeps it near the rounding unit whatever M's condition, whereas the residual
    // relative to |b| alone grows with the condition, which the stiff seam weights make large
    // (relative residuals up to 4e-10 with backward errors near 3e-19, on certified maps).
    const double backward = residual * scale / (M.norm() * x.norm() + scale);
    if (!(backward < 1e-12))
      throw Error(ErrorKind::solver, "E552",
                  fmt::format("the parametrization solve stays inaccurate (backward error "
                              "{:.1e}, relative residual {:.1e}); the input likely has extreme "
                              "triangles",
                              backward, residual));
    return x;
  }

  // The map with every meta-edge locked. Then every seam vertex is fixed, the patches do not
  // interact, and u and v solve the same scalar system on the vertices inside the patches (one
  // matrix, two right-hand sides): a quarter of the work of the coupled system's factorization,
  // and independent of it.
  ParamMap solve_locked(ParamReport& report) const {
    auto t0 = Clock::now();
    const uint32_t nv = mesh.num_vertices();
    VertexData<uint32_t> inner(nv, kInvalid);
    uint32_t m = 0;
    for (uint32_t v = 0; v < nv; ++v)
      if (var[v] != kInvalid && meta.vertex_meta_edge[v] == kInvalid) inner[v] = m++;
    std::vector<Eigen::Triplet<double>> trip;
    trip.reserve(std::size_t(mesh.num_faces()) * 9);
    Eigen::MatrixX2d rhs = Eigen::MatrixX2d::Zero(m, 2);
    for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
      const Tri& t = mesh.face(f);
      for (int a = 0; a < 3; ++a) {
        const uint32_t i = inner[t[a]];
        if (i == kInvalid) continue;
        for (int s = 0; s < 2; ++s) {
          const int b = (a + 1 + s) % 3;
          const double w = weight[f][a][s];
          trip.emplace_back(i, i, w);
          const uint32_t j = inner[t[b]];
          if (j != kInvalid) {
            trip.emplace_back(i, j, -w);
          } else {  // fixed: in the face's chart, which is the home chart of corner a
            const UV c = fixed_uv(f, b);
            rhs(i, 0) += w * c[0];
            rhs(i, 1) += w * c[1];
          }
        }
      }
    }
    SpMat L(m, m);
    L.setFromTriplets(trip.begin(), trip.end());
    report.assemble_seconds += seconds_since(t0);
    Eigen::MatrixX2d x;
    if (m > 0) {
      bool is_analyzed = false;
      if (kind == WeightKind::smvc) {
        Eigen::CholmodSimplicialLLT<SpMat, Eigen::Lower> solver;
        x = factor_and_solve(solver, L, rhs, CHOLMOD_AMD, is_analyzed, report);
      } else {
        Eigen::UmfPackLU<SpMat> solver;
        x = factor_and_solve(solver, L, rhs, CHOLMOD_AMD, is_analyzed, report);
      }
    }
    return make_map([&](uint32_t v) {
      const uint32_t i = inner[v];
      return i == kInvalid ? chord[v] : UV{x(i, 0), x(i, 1)};
    });
  }

  // The map from each non-meta-vertex's position in its home chart.
  ParamMap make_map(auto&& position_of) const {
    ParamMap map;
    map.home = home;
    map.position = VertexData<UV>(mesh.num_vertices(), UV{0, 0});
    for (uint32_t v = 0; v < mesh.num_vertices(); ++v)
      if (meta.vertex_meta_vertex[v] == kInvalid) map.position[v] = position_of(v);
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

  ParamMap solve(const EdgeData<double>& stiffness, const std::vector<char>& locked,
                 ParamReport& report) {
    auto t0 = Clock::now();
    Eigen::VectorXd rhs;
    assemble(stiffness, locked, rhs);
    report.assemble_seconds += seconds_since(t0);
    const Eigen::VectorXd x = n == 0                    ? Eigen::VectorXd()
                              : kind == WeightKind::mvc ? factor_and_solve_relaxed(lu, rhs, report)
                              : n >= kSupernodalUnknowns
                                  ? factor_and_solve_relaxed(supernodal, rhs, report)
                                  : factor_and_solve_relaxed(llt, rhs, report);
    return make_map([&](uint32_t v) {
      const uint32_t i = var[v];
      return (i == kInvalid || is_locked(v, locked)) ? chord[v] : UV{x[2 * i], x[2 * i + 1]};
    });
  }
};

SeamSystem::SeamSystem(const TriMesh& mesh, const FaceData<uint32_t>& labels, const MetaMesh& meta,
                       const Layout& layout, WeightKind weights, const std::vector<uint32_t>* rank)
    : impl_(std::make_unique<Impl>(mesh, labels, meta, layout, weights, rank)) {}

SeamSystem::~SeamSystem() = default;

const std::vector<char>& SeamSystem::always_locked() const { return impl_->always_locked; }
const EdgeData<uint32_t>& SeamSystem::edge_meta_edge() const { return impl_->edge_meta; }
uint32_t SeamSystem::unknowns() const { return impl_->n; }

ParamMap SeamSystem::solve(const EdgeData<double>& stiffness, const std::vector<char>& locked,
                           ParamReport& report) {
  return impl_->solve(stiffness, locked, report);
}

ParamMap SeamSystem::solve_locked(ParamReport& report) const { return impl_->solve_locked(report); }

}  // namespace isoquad
