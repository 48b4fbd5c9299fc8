#include "field/cross_field.hpp"

#include <fmt/format.h>

#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include "field/curvature.hpp"
#include "field/feature_curves.hpp"
#include "isoquad/error.hpp"
#include "param/blas_runtime.hpp"
#include "seg/patch_topology.hpp"

namespace isoquad {

namespace {

using Complex = std::complex<double>;
using SpMat = Eigen::SparseMatrix<double>;
using CxMat = Eigen::SparseMatrix<Complex>;
constexpr double kPi = std::numbers::pi;

Vec3 centroid(const TriMesh& mesh, uint32_t f) {
  const Tri& t = mesh.face(f);
  return (mesh.position(t[0]) + mesh.position(t[1]) + mesh.position(t[2])) / 3.0;
}

Vec3 halfedge_vector(const TriMesh& mesh, uint32_t h) {
  return mesh.position(mesh.to(h)) - mesh.position(mesh.from(h));
}

// The smoothness weight of the edge of halfedge h: its length over the distance between the two
// centroids (the dual edge), 0 for a degenerate pair.
double edge_weight(const TriMesh& mesh, uint32_t h) {
  const double dual =
      norm(centroid(mesh, TriMesh::face_of(h)) - centroid(mesh, TriMesh::face_of(mesh.twin(h))));
  const double len = norm(halfedge_vector(mesh, h));
  return dual > 1e-12 * len && mesh.face_area(TriMesh::face_of(h)) > 0 &&
                 mesh.face_area(TriMesh::face_of(mesh.twin(h))) > 0
             ? len / dual
             : 0.0;
}

// Hard constraints (Bommes et al. 2009): a face with feature or boundary edges is aligned with
// them, u_f = e^{4i alpha}; two such edges that agree within 10 degrees (mod 90) are averaged by
// length, otherwise the longest one wins (the other then meets a field turned against it, which
// the tracing treats as a corner).
void constrain_faces(const TriMesh& mesh, const FaceFrames& frames, const EdgeData<char>& feature,
                     FaceData<Complex>& u) {
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
    std::array<std::pair<Complex, double>, 3> edges;
    int count = 0, longest = 0;
    for (uint32_t i = 0; i < 3; ++i) {
      const uint32_t h = 3 * f + i;
      if (mesh.twin(h) != kInvalid && !feature[mesh.edge(h)]) continue;
      const Vec3 d = halfedge_vector(mesh, h);
      edges[count] = {std::polar(1.0, 4 * frames.arg(f, d)), norm(d)};
      if (edges[count].second > edges[longest].second) longest = count;
      ++count;
    }
    if (count == 0) continue;
    Complex sum(0, 0);
    for (int i = 0; i < count; ++i)
      if (std::abs(std::arg(edges[i].first / edges[longest].first)) <= 4 * kPi / 18)
        sum += edges[i].second * edges[i].first;
    u[f] = std::abs(sum) > 0 ? sum / std::abs(sum) : edges[longest].first;
  }
}

// The third edge of every face whose two constrained edges disagree by more than 10 degrees.
std::vector<uint32_t> conflicting_faces_third_edges(const TriMesh& mesh,
                                                    const EdgeData<char>& feature) {
  std::vector<uint32_t> edges;
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
    uint32_t free_side = kInvalid, constrained = 0;
    std::array<Vec3, 3> dir;
    for (uint32_t i = 0; i < 3; ++i) {
      const uint32_t h = 3 * f + i;
      if (mesh.twin(h) != kInvalid && !feature[mesh.edge(h)]) {
        free_side = h;
        continue;
      }
      dir[constrained++] = normalized(halfedge_vector(mesh, h));
    }
    if (constrained != 2) continue;
    // Directions agree mod 90 degrees when the angle between them is near 0, 90 or 180.
    const double a = angle_between(dir[0], dir[1]);
    if (std::abs(std::remainder(a, kPi / 2)) > kPi / 18) edges.push_back(mesh.edge(free_side));
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

// The Hermitian smoothness matrix plus a diagonal mass, restricted to the free faces (lower
// triangle, one complex unknown per face), and the right-hand side that the constrained
// neighbours give.
struct FieldSystem {
  FaceData<char> constrained;     // a feature or boundary edge (constrain_faces)
  std::vector<uint32_t> unknown;  // face -> free index, or kInvalid
  std::vector<uint32_t> face_of;  // free index -> face
  std::vector<double> weight;     // per halfedge (0 on the boundary)
};

// The free faces and their numbering, which depend on the connectivity alone.
FieldSystem field_system(const TriMesh& mesh, const EdgeData<char>& feature) {
  const uint32_t nf = mesh.num_faces();
  FieldSystem sys;
  sys.constrained = FaceData<char>(nf, 0);
  sys.unknown.assign(nf, kInvalid);
  for (uint32_t f = 0; f < nf; ++f) {
    for (uint32_t i = 0; i < 3; ++i) {
      const uint32_t h = 3 * f + i;
      if (mesh.twin(h) == kInvalid || feature[mesh.edge(h)]) sys.constrained[f] = 1;
    }
    if (sys.constrained[f]) continue;
    sys.unknown[f] = uint32_t(sys.face_of.size());
    sys.face_of.push_back(f);
  }
  return sys;
}

// The pattern of assemble()'s matrix: a pair of free faces sharing an edge has an entry even
// where the edge's weight is 0, so that the pattern, and with it the symbolic factorization,
// is known before the geometry.
CxMat system_pattern(const TriMesh& mesh, const FieldSystem& sys) {
  const std::size_t n = sys.face_of.size();
  std::vector<Eigen::Triplet<Complex>> t;
  t.reserve(n * 3);
  for (std::size_t k = 0; k < n; ++k) {
    for (uint32_t i = 0; i < 3; ++i) {
      const uint32_t tw = mesh.twin(3 * sys.face_of[k] + i);
      if (tw == kInvalid) continue;
      const uint32_t j = sys.unknown[TriMesh::face_of(tw)];
      if (j != kInvalid && j < k) t.emplace_back(int(k), int(j), Complex(1, 0));
    }
    t.emplace_back(int(k), int(k), Complex(1, 0));
  }
  CxMat A{Eigen::Index(n), Eigen::Index(n)};
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

CxMat assemble(const TriMesh& mesh, const FaceFrames& frames, const FieldSystem& sys,
               const FaceData<double>& mass, const FaceData<Complex>& u_fixed,
               Eigen::VectorXcd& rhs) {
  const std::size_t n = sys.face_of.size();
  std::vector<Eigen::Triplet<Complex>> t;
  t.reserve(n * 3);
  rhs = Eigen::VectorXcd::Zero(Eigen::Index(n));
  for (std::size_t k = 0; k < n; ++k) {
    const uint32_t f = sys.face_of[k];
    double diag = mass[f];
    for (uint32_t i = 0; i < 3; ++i) {
      const uint32_t h = 3 * f + i, tw = mesh.twin(h);
      if (tw == kInvalid) continue;
      const double w = sys.weight[h];
      diag += w;
      const uint32_t g = TriMesh::face_of(tw);
      // Row f of the energy w |u_f - e^{4i rho_gf} u_g|^2, rho_gf = -rho[h].
      const Complex c = w * std::polar(1.0, -4 * frames.rho[h]);
      const uint32_t j = sys.unknown[g];
      if (j == kInvalid)
        rhs[Eigen::Index(k)] += c * u_fixed[g];
      else if (j < k)
        t.emplace_back(int(k), int(j), -c);
    }
    t.emplace_back(int(k), int(k), Complex(diag, 0));
  }
  CxMat A{Eigen::Index(n), Eigen::Index(n)};
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

// CHOLMOD's complex supernodal LLT of the Hermitian system. Its real 2n x 2n form
// [[A, -B], [B, A]], the same solution, took twice as long on bunny00 (75k faces): AMD ordered a
// graph four times the size (90 -> 52 ms) and left nnz(L) at 5.1M reals instead of 1.3M complex
// values (factorization 232 -> 118 ms, each solve 45 -> 25 ms).
class Factor {
 public:
  // The symbolic factorization (AMD ordering), from system_pattern().
  explicit Factor(const CxMat& pattern) {
    llt_.cholmod().nmethods = 1;
    llt_.cholmod().method[0].ordering = CHOLMOD_AMD;
    llt_.analyzePattern(pattern);
  }
  // A: assemble()'s matrix, kept for the solves' refinement step.
  void factorize(const CxMat& A) {
    const auto blas = blas_section();
    llt_.factorize(A);
    if (llt_.info() != Eigen::Success)
      throw Error(
          ErrorKind::solver, "E561",
          fmt::format("the cross field's system ({} unknowns) could not be factorized", A.rows()));
    A_ = &A;
  }
  Eigen::VectorXcd solve(const Eigen::VectorXcd& b) {
    const auto blas = blas_section();
    Eigen::VectorXcd x = llt_.solve(b);
    x += llt_.solve(Eigen::VectorXcd(b - A_->selfadjointView<Eigen::Lower>() * x));
    if (!x.allFinite())
      throw Error(ErrorKind::solver, "E561", "the cross field's solve gave non-finite values");
    return x;
  }

 private:
  const CxMat* A_ = nullptr;
  Eigen::CholmodSupernodalLLT<CxMat, Eigen::Lower> llt_;
};

void scatter(const FieldSystem& sys, const Eigen::VectorXcd& x, FaceData<Complex>& u) {
  for (std::size_t k = 0; k < sys.face_of.size(); ++k) u[sys.face_of[k]] = x[Eigen::Index(k)];
}

// The free faces' unit field times their mass, the right-hand side of a pull towards it.
Eigen::VectorXcd pull(const FieldSystem& sys, const FaceData<double>& mass,
                      const FaceData<Complex>& target) {
  Eigen::VectorXcd b(Eigen::Index(sys.face_of.size()));
  for (std::size_t k = 0; k < sys.face_of.size(); ++k) {
    const uint32_t f = sys.face_of[k];
    b[Eigen::Index(k)] = mass[f] * target[f];
  }
  return b;
}

FaceData<Complex> unit(const FaceData<Complex>& u) {
  FaceData<Complex> r(u.size());
  for (uint32_t f = 0; f < u.size(); ++f)
    r[f] = std::abs(u[f]) > 0 ? u[f] / std::abs(u[f]) : Complex(1, 0);
  return r;
}

// The globally smoothest unit field (Knoeppel et al. 2013, eq. 9): the smallest eigenvector of
// L u = sigma M u by inverse iteration on one factorization of L + eps M, until no direction
// moves 0.1 degree.
void smoothest_field(const TriMesh& mesh, const FaceFrames& frames, const FieldSystem& sys,
                     const FaceData<double>& area, Factor& factor, FaceData<Complex>& u,
                     uint32_t& solves) {
  const uint32_t nf = mesh.num_faces();
  double trace_l = 0, trace_m = 0;
  for (uint32_t h = 0; h < mesh.num_halfedges(); ++h) trace_l += sys.weight[h];
  for (uint32_t f = 0; f < nf; ++f) trace_m += area[f];
  FaceData<double> shift(nf);
  for (uint32_t f = 0; f < nf; ++f) shift[f] = 1e-8 * trace_l / trace_m * area[f];
  Eigen::VectorXcd unused;
  const CxMat A = assemble(mesh, frames, sys, shift, u, unused);
  factor.factorize(A);
  // The start: the cube's cross field (the coordinate axes projected onto each face, weighted
  // towards the two most tangential), which fixes the global rotation the eigenproblem leaves free
  // and, where the smallest eigenvalue is degenerate (a round sphere), picks its eight-singularity
  // member rather than an arbitrary mixture with extra +- pairs.
  for (uint32_t f = 0; f < nf; ++f) {
    Complex start(0, 0);
    for (const Vec3 axis : {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}) {
      const Vec3 t = axis - dot(axis, frames.normal[f]) * frames.normal[f];
      const double w = squared_norm(t);
      if (w > 0) start += w * w * std::polar(1.0, 4 * frames.arg(f, t));
    }
    u[f] = std::abs(start) > 0 ? start : Complex(1, 0);
  }
  for (int it = 0; it < 20; ++it) {
    Eigen::VectorXcd x = factor.solve(pull(sys, area, u));
    ++solves;
    double mnorm = 0;
    for (std::size_t k = 0; k < sys.face_of.size(); ++k)
      mnorm += area[sys.face_of[k]] * std::norm(x[Eigen::Index(k)]);
    x /= std::sqrt(std::max(mnorm, 1e-300));
    double moved = 0;
    for (std::size_t k = 0; k < sys.face_of.size(); ++k) {
      const Complex next = x[Eigen::Index(k)], prev = u[sys.face_of[k]];
      if (std::abs(next) > 0 && std::abs(prev) > 0)
        moved = std::max(moved, std::abs(std::arg(next / prev)) / 4);
    }
    scatter(sys, x, u);
    if (moved < 0.1 * kPi / 180) break;
  }
}

}  // namespace

RefinedMesh split_constraint_conflicts(const RefinedMesh& in, EdgeData<char>& feature,
                                       uint32_t rounds) {
  RefinedMesh out = in;
  for (uint32_t round = 0; round < rounds; ++round) {
    const std::vector<uint32_t> edges = conflicting_faces_third_edges(out.mesh, feature);
    if (edges.empty()) break;
    out = split_edges(out, edges, nullptr, &feature);
  }
  return out;
}

Vec3 CrossField::direction(uint32_t f, int k) const {
  return frames.direction(f, angle[f] + k * kPi / 2);
}

Vec3 CrossField::direction_on(const TriMesh& mesh, uint32_t f, int k) const {
  const Tri& t = surface.face(f);
  const Vec3 a1 = surface.position(t[1]) - surface.position(t[0]);
  const Vec3 a2 = surface.position(t[2]) - surface.position(t[0]);
  const Vec3 d = direction(f, k);
  const double g11 = dot(a1, a1), g12 = dot(a1, a2), g22 = dot(a2, a2);
  const double det = g11 * g22 - g12 * g12;
  if (!(det > 1e-24 * g11 * g22)) return d;
  const double r1 = dot(d, a1), r2 = dot(d, a2);
  const double x = (g22 * r1 - g12 * r2) / det, y = (g11 * r2 - g12 * r1) / det;
  return normalized(x * (mesh.position(t[1]) - mesh.position(t[0])) +
                    y * (mesh.position(t[2]) - mesh.position(t[0])));
}

namespace {

void period_jumps_and_indices(const TriMesh& mesh, CrossField& cf);

// The pattern of laplacian_system()'s matrix: every edge between two free vertices (`index`:
// vertex -> free index, or kInvalid), lower triangle, and the diagonal.
SpMat vertex_pattern(const TriMesh& mesh, const std::vector<uint32_t>& index, uint32_t n) {
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(std::size_t(mesh.num_edges()) + n);
  for (uint32_t e = 0; e < mesh.num_edges(); ++e) {
    const uint32_t h = mesh.edge_halfedge(e);
    const uint32_t p = index[mesh.from(h)], q = index[mesh.to(h)];
    if (p != kInvalid && q != kInvalid)
      trip.emplace_back(int(std::max(p, q)), int(std::min(p, q)), 1.0);
  }
  for (uint32_t k = 0; k < n; ++k) trip.emplace_back(int(k), int(k), 1.0);
  SpMat A(n, n);
  A.setFromTriplets(trip.begin(), trip.end());
  return A;
}

// M + t L on the n free vertices (lower triangle; an edge of weight 0 keeps its entry, as in
// vertex_pattern), and in `rhs` M x0 plus what the fixed neighbours give, a column per
// coordinate.
SpMat laplacian_system(const TriMesh& mesh, const std::vector<uint32_t>& index, uint32_t n,
                       double t, Eigen::MatrixXd& rhs) {
  const uint32_t nv = mesh.num_vertices();
  std::vector<double> mass(nv, 0.0);
  for (uint32_t f = 0; f < mesh.num_faces(); ++f)
    for (uint32_t v : mesh.face(f)) mass[v] += mesh.face_area(f) / 3;
  std::vector<Eigen::Triplet<double>> trip;
  rhs = Eigen::MatrixXd::Zero(n, 3);
  std::vector<double> diag(n, 0.0);
  for (uint32_t v = 0; v < nv; ++v)
    if (index[v] != kInvalid) {
      diag[index[v]] = mass[v];
      for (int c = 0; c < 3; ++c) rhs(index[v], c) = mass[v] * mesh.position(v)[c];
    }
  for (uint32_t h = 0; h < mesh.num_halfedges(); ++h) {
    // Half the cotangent of the angle opposite h, for the edge from(h) - to(h).
    const uint32_t a = mesh.from(h), b = mesh.to(h), o = mesh.to(TriMesh::next(h));
    const Vec3 u = mesh.position(a) - mesh.position(o), w = mesh.position(b) - mesh.position(o);
    const double sine = norm(cross(u, w));
    const double weight = sine > 0 ? std::max(0.0, 0.5 * dot(u, w) / sine) * t : 0;
    for (const auto& [p, q] : {std::pair{a, b}, std::pair{b, a}}) {
      if (index[p] == kInvalid) continue;
      diag[index[p]] += weight;
      if (index[q] == kInvalid) {
        for (int c = 0; c < 3; ++c) rhs(index[p], c) += weight * mesh.position(q)[c];
      } else if (index[q] < index[p]) {
        trip.emplace_back(int(index[p]), int(index[q]), -weight);
      }
    }
  }
  for (uint32_t k = 0; k < n; ++k) trip.emplace_back(int(k), int(k), diag[k]);
  SpMat A(n, n);
  A.setFromTriplets(trip.begin(), trip.end());
  return A;
}

// The surface after one implicit step of mean curvature flow over time t (Desbrun et al. 1999):
// (M + t L) x = M x0 with the cotangent Laplacian (negative weights clamped to 0, so the system
// is an M-matrix) and the lumped mass, vertices on feature or boundary edges fixed. Detail finer
// than about sqrt(t) is smoothed away; unconditionally stable, so no vertex is left as a spike.
TriMesh smoothed(const TriMesh& mesh, const EdgeData<char>& feature, double t) {
  const uint32_t nv = mesh.num_vertices();
  VertexData<char> fixed(nv, 0);
  for (uint32_t e = 0; e < mesh.num_edges(); ++e) {
    if (!feature[e] && !mesh.is_boundary_edge(e)) continue;
    const uint32_t h = mesh.edge_halfedge(e);
    fixed[mesh.from(h)] = fixed[mesh.to(h)] = 1;
  }
  std::vector<uint32_t> index(nv, kInvalid);
  uint32_t n = 0;
  for (uint32_t v = 0; v < nv; ++v)
    if (!fixed[v]) index[v] = n++;
  if (n == 0) return mesh;
  // The pattern, every edge between free vertices (zero weights kept as entries), depends on the
  // connectivity alone: its symbolic factorization (33 ms on bunny00) runs beside the assembly.
  Eigen::CholmodSupernodalLLT<SpMat, Eigen::Lower> llt;
  SpMat A;
  Eigen::MatrixXd rhs;
  tbb::parallel_invoke([&] { llt.analyzePattern(vertex_pattern(mesh, index, n)); },
                       [&] { A = laplacian_system(mesh, index, n, t, rhs); });
  Eigen::MatrixXd x;
  {
    const auto blas = blas_section();
    llt.factorize(A);
    // A vertex with no area and no positive weight (degenerate input) leaves the system singular:
    // the field is then solved on the surface as it is.
    if (llt.info() != Eigen::Success) return mesh;
    x = llt.solve(rhs);
  }
  std::vector<Vec3> p = mesh.positions();
  for (uint32_t v = 0; v < nv; ++v)
    if (index[v] != kInvalid) p[v] = {x(index[v], 0), x(index[v], 1), x(index[v], 2)};
  return mesh.with_positions(std::move(p));
}

CrossField solve_field(const TriMesh& mesh, const EdgeData<char>& feature,
                       const CrossFieldOptions& options, FieldSystem sys,
                       std::optional<Factor>& factor);

}  // namespace

CrossField compute_cross_field(const TriMesh& mesh, const EdgeData<char>& feature,
                               const CrossFieldOptions& options) {
  uint32_t dropped = 0;
  EdgeData<char> kept = options.edge_length > 0
                            ? long_features(mesh, feature,
                                            {options.min_feature_length * options.edge_length,
                                             options.weak_feature_length * options.edge_length,
                                             options.weak_feature_angle},
                                            &dropped)
                            : feature;
  const double t = options.smoothing * options.edge_length * options.edge_length;
  // The field system's pattern depends on the connectivity alone: its symbolic factorization
  // runs beside the smoothing (bunny00: 53 ms of AMD ordering beside 115 ms).
  FieldSystem sys = field_system(mesh, kept);
  std::optional<Factor> factor;
  TriMesh surface;
  tbb::parallel_invoke([&] { surface = t > 0 ? smoothed(mesh, kept, t) : mesh; },
                       [&] {
                         if (!sys.face_of.empty()) factor.emplace(system_pattern(mesh, sys));
                       });
  CrossField cf = solve_field(surface, kept, options, std::move(sys), factor);
  cf.feature = std::move(kept);
  cf.short_feature_networks = dropped;
  period_jumps_and_indices(surface, cf);
  cf.surface = std::move(surface);
  return cf;
}

namespace {

// E(u) = u^H L u + lambda sum_f A_f |u_f - a_f q_f|^2: the pull towards the curvature
// directions is as strong as they are clear, and where they say nothing it pulls |u| down, not
// its direction. The normalization rounds reuse the same matrix, pulling towards the unit field
// instead. `factor`: of A, the matrix; `rhs`: what the constrained faces give.
void guided_field(const FieldSystem& sys, const FaceData<double>& mass,
                  const CurvatureGuidance& guide, Factor& factor, const Eigen::VectorXcd& rhs,
                  uint32_t normalize_rounds, CrossField& cf, FaceData<Complex>& u) {
  FaceData<Complex> target(mass.size());
  for (uint32_t f = 0; f < mass.size(); ++f) target[f] = guide.weight[f] * guide.target[f];
  scatter(sys, factor.solve(rhs + pull(sys, mass, target)), u);
  ++cf.solves;
  for (uint32_t f : sys.face_of) cf.confidence[f] = std::abs(u[f]);
  for (uint32_t round = 0; round < normalize_rounds; ++round) {
    scatter(sys, factor.solve(rhs + pull(sys, mass, unit(u))), u);
    ++cf.solves;
  }
}

CrossField solve_field(const TriMesh& mesh, const EdgeData<char>& feature,
                       const CrossFieldOptions& options, FieldSystem sys,
                       std::optional<Factor>& factor) {
  const uint32_t nf = mesh.num_faces();
  CrossField cf;
  cf.frames = face_frames(mesh);
  const FaceFrames& fr = cf.frames;
  FaceData<Complex> u(nf, Complex(0, 0));
  constrain_faces(mesh, fr, feature, u);
  cf.constrained_faces = uint32_t(nf - sys.face_of.size());
  sys.weight.assign(mesh.num_halfedges(), 0.0);
  tbb::parallel_for(uint32_t(0), mesh.num_halfedges(), [&](uint32_t h) {
    if (mesh.twin(h) != kInvalid) sys.weight[h] = edge_weight(mesh, h);
  });

  FaceData<double> area(nf);
  double total_area = 0;
  for (uint32_t f = 0; f < nf; ++f) total_area += area[f] = mesh.face_area(f);
  const double scale = options.guidance_scale * options.edge_length;
  const double lambda = scale > 0 ? 1 / (scale * scale) : 0;
  FaceData<double> mass(nf);
  for (uint32_t f = 0; f < nf; ++f) mass[f] = lambda * area[f];

  // The guided field's matrix does not depend on the guidance, only its right-hand side does:
  // it is factored beside the guidance, unless only the eigen variant can follow (bunny00: 72 ms
  // of guidance beside 140 ms).
  const bool guided = options.curvature && options.edge_length > 0;
  const bool maybe_linear = cf.constrained_faces > 0 || (guided && lambda > 0);
  CurvatureGuidance guide;
  CxMat A;
  Eigen::VectorXcd rhs;
  tbb::parallel_invoke(
      [&] {
        if (guided) guide = curvature_guidance(mesh, fr, feature, options.edge_length);
      },
      [&] {
        if (!factor || !maybe_linear) return;
        A = assemble(mesh, fr, sys, mass, u, rhs);
        factor->factorize(A);
      });
  if (!guided) {
    guide.target = FaceData<Complex>(nf, Complex(0, 0));
    guide.weight = FaceData<double>(nf, 0.0);
  }
  double guided_area = 0;
  for (uint32_t f = 0; f < nf; ++f)
    if (guide.weight[f] > 0.5) guided_area += area[f];
  cf.guided_area_share = total_area > 0 ? guided_area / total_area : 0;

  cf.confidence = FaceData<double>(nf, 1.0);
  if (factor) {
    if (cf.constrained_faces == 0 && (cf.guided_area_share < 0.05 || lambda == 0)) {
      cf.variant = FieldVariant::eigen;
      smoothest_field(mesh, fr, sys, area, *factor, u, cf.solves);
      for (uint32_t f : sys.face_of) cf.confidence[f] = std::abs(u[f]);
    } else {
      guided_field(sys, mass, guide, *factor, rhs, options.normalize_rounds, cf, u);
    }
  }
  cf.constrained = std::move(sys.constrained);

  u = unit(u);
  cf.angle = FaceData<double>(nf);
  for (uint32_t f = 0; f < nf; ++f) {
    double a = std::arg(u[f]) / 4;  // (-pi/4, pi/4]
    cf.angle[f] = a < 0 ? a + kPi / 2 : a;
  }
  for (uint32_t h = 0; h < mesh.num_halfedges(); ++h) {
    const uint32_t tw = mesh.twin(h);
    if (tw == kInvalid || tw < h) continue;
    const uint32_t f = TriMesh::face_of(h), g = TriMesh::face_of(tw);
    cf.energy += sys.weight[h] * std::norm(u[g] - std::polar(1.0, 4 * fr.rho[h]) * u[f]);
  }
  return cf;
}

}  // namespace

namespace {

// Ray et al. 2008: delta = theta_g - theta_f - rho + p pi/2 in (-pi/4, pi/4].
int period_jump(const CrossField& cf, uint32_t f, uint32_t g, double rho) {
  const double raw = cf.angle[g] - cf.angle[f] - rho;
  return int(std::lround((wrap_angle(raw, kPi / 2) - raw) / (kPi / 2)));
}

double turn(const CrossField& cf, uint32_t f, uint32_t g, uint32_t h) {
  return cf.angle[g] - cf.angle[f] - cf.frames.rho[h] + cf.period_jump[h] * kPi / 2;
}

// The index of vertex v in quarter turns (4 I_v, before rounding) and the sum of its corner
// angles.
double quarter_turns(const TriMesh& mesh, const CrossField& cf, uint32_t v, double& angles) {
  // Around v, CCW: the field's turning against parallel transport plus the angle defect (the
  // transport's own turning) is 2 pi I_v.
  double turning = 0;
  angles = 0;
  uint32_t last = kInvalid;
  mesh.for_each_outgoing(v, [&](uint32_t h) {
    const uint32_t f = TriMesh::face_of(h);
    angles += corner_angle(mesh, h);
    const uint32_t in = TriMesh::prev(h), tw = mesh.twin(in);
    if (tw != kInvalid) turning += turn(cf, f, TriMesh::face_of(tw), in);
    last = h;
  });
  if (!mesh.is_boundary_vertex(v)) return (2 * kPi - angles + turning) / (kPi / 2);
  // The field measured from the boundary: its offset from the outgoing boundary edge at the
  // start of the fan, and from the incoming one at its end, each mod 90 degrees.
  const uint32_t h0 = mesh.outgoing(v), f0 = TriMesh::face_of(h0);
  const uint32_t in = TriMesh::prev(last), f1 = TriMesh::face_of(last);
  const double a0 =
      wrap_angle(cf.angle[f0] - cf.frames.arg(f0, halfedge_vector(mesh, h0)), kPi / 2);
  const double a1 =
      wrap_angle(cf.angle[f1] - cf.frames.arg(f1, -halfedge_vector(mesh, in)), kPi / 2);
  return (kPi - angles + a0 + turning - a1) / (kPi / 2);
}

// Per vertex in parallel (each writes its own entries), then checked and collected in vertex
// order, so that the error names the same vertex on any thread count.
void period_jumps_and_indices(const TriMesh& mesh, CrossField& cf) {
  cf.period_jump = HalfedgeData<int8_t>(mesh.num_halfedges(), 0);
  tbb::parallel_for(uint32_t(0), mesh.num_halfedges(), [&](uint32_t h) {
    const uint32_t tw = mesh.twin(h);
    if (tw == kInvalid || tw < h) return;
    const int p = period_jump(cf, TriMesh::face_of(h), TriMesh::face_of(tw), cf.frames.rho[h]);
    cf.period_jump[h] = int8_t(p);
    cf.period_jump[tw] = int8_t(-p);
  });
  const uint32_t nv = mesh.num_vertices();
  std::vector<double> i4(nv), angles(nv);
  tbb::parallel_for(uint32_t(0), nv,
                    [&](uint32_t v) { i4[v] = quarter_turns(mesh, cf, v, angles[v]); });
  cf.index4 = VertexData<int32_t>(nv, 0);
  int64_t sum4 = 0;
  for (uint32_t v = 0; v < nv; ++v) {
    const long r = std::lround(i4[v]);
    if (std::abs(i4[v] - double(r)) > 1e-4)
      throw Error(ErrorKind::internal, "E700",
                  fmt::format("the cross field's index at vertex {} is {} quarter turns, not an "
                              "integer",
                              v, i4[v]));
    cf.index4[v] = int32_t(r);
    sum4 += r;
    const bool singular = mesh.is_boundary_vertex(v)
                              ? 2 - r != std::max(1L, std::lround(angles[v] / (kPi / 2)))
                              : r != 0;
    if (singular) cf.singular.push_back(v);
  }
  const int64_t chi4 = 4 * mesh.euler_characteristic();
  if (sum4 != chi4)
    throw Error(ErrorKind::internal, "E700",
                fmt::format("the cross field's indices sum to {}/4, not the Euler characteristic "
                            "{} (Poincare-Hopf)",
                            sum4, mesh.euler_characteristic()));
}

}  // namespace

}  // namespace isoquad
