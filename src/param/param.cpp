// Relaxation drivers (DESIGN.md §7.4-7.6): the locked map (always injective; its own scalar
// system, solved alongside) and either adaptive per-seam-edge stiffening or the paper's global
// bisection, each solve reusing the one symbolic factorization of SeamSystem.
#include "param/param.hpp"

#include <fmt/format.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>

#include "isoquad/error.hpp"
#include "param/seam_system.hpp"

namespace isoquad {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

struct Context {
  const TriMesh& mesh;
  const FaceData<uint32_t>& labels;
  const MetaMesh& meta;
  const Layout& layout;
  const ParamOptions& options;
  ParamReport& report;
  SeamSystem& system;

  Certificate check(const ParamMap& map) const {
    const auto t0 = Clock::now();
    Certificate c = certify(mesh, labels, meta, layout, map);
    report.certify_seconds += seconds_since(t0);
    report.bad_per_solve.push_back(c.flipped + c.degenerate + c.bad_angle_sums);
    return c;
  }
};

// Seam mesh edges within `rings` face rings of face `seed` whose meta-edge is not locked.
void seam_edges_near(const Context& ctx, uint32_t seed, const std::vector<char>& locked,
                     std::vector<uint32_t>& stamp, uint32_t stamp_value,
                     std::vector<uint32_t>& out) {
  const TriMesh& mesh = ctx.mesh;
  const EdgeData<uint32_t>& edge_meta = ctx.system.edge_meta_edge();
  std::vector<uint32_t> frontier{seed};
  stamp[seed] = stamp_value;
  for (uint32_t ring = 0; ring <= ctx.options.rings && !frontier.empty(); ++ring) {
    std::vector<uint32_t> next;
    for (const uint32_t f : frontier)
      for (int c = 0; c < 3; ++c) {
        const uint32_t h = 3 * f + c;
        const uint32_t e = edge_meta[mesh.edge(h)];
        if (e != kInvalid && !locked[e]) out.push_back(mesh.edge(h));
        const uint32_t t = mesh.twin(h);
        if (t == kInvalid || stamp[TriMesh::face_of(t)] == stamp_value) continue;
        stamp[TriMesh::face_of(t)] = stamp_value;
        next.push_back(TriMesh::face_of(t));
      }
    frontier = std::move(next);
  }
}

// Faces to act on: the bad faces and the faces around vertices with a wrong angle sum.
std::vector<uint32_t> bad_region(const TriMesh& mesh, const Certificate& cert) {
  std::vector<uint32_t> faces = cert.bad_faces;
  for (const uint32_t v : cert.bad_vertices)
    mesh.for_each_outgoing(v, [&](uint32_t h) { faces.push_back(TriMesh::face_of(h)); });
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return faces;
}

struct Outcome {
  ParamMap map;
  Certificate cert;
  EdgeData<double> stiffness;
  std::vector<char> locked;
  bool ok = false;
};

Outcome relax_adaptive(const Context& ctx) {
  const TriMesh& mesh = ctx.mesh;
  const ParamOptions& opt = ctx.options;
  const EdgeData<uint32_t>& edge_meta = ctx.system.edge_meta_edge();
  Outcome out;
  out.stiffness = EdgeData<double>(mesh.num_edges(), 1.0);
  // Seams start stiff (the paper's large boundary weights), not free: a free seam bends with
  // the harmonic map of both sides, which distorts the quads along it more than the flips it
  // avoids are worth (corpus at 1,500 quads: 931 folded quads from weight 1, 817 from 100).
  for (uint32_t e = 0; e < mesh.num_edges(); ++e)
    if (edge_meta[e] != kInvalid) out.stiffness[e] = opt.initial_stiffness;
  out.locked = ctx.system.always_locked();
  std::vector<uint32_t> suspect(ctx.meta.faces.size(), 0);
  std::vector<uint32_t> raises(ctx.meta.edges.size(), 0);
  std::vector<uint32_t> stamp(mesh.num_faces(), 0);
  uint32_t stamp_value = 0;
  for (uint32_t it = 0; it < opt.max_iterations; ++it) {
    out.map = ctx.system.solve(out.stiffness, out.locked, ctx.report);
    out.cert = ctx.check(out.map);
    ctx.report.iterations = it + 1;
    if (it == 0) ctx.report.flipped_first = out.cert.flipped + out.cert.degenerate;
    if (out.cert.ok()) {
      out.ok = true;
      return out;
    }
    std::vector<uint32_t> raise;
    for (const uint32_t f : bad_region(mesh, out.cert)) {
      std::vector<uint32_t> near;
      seam_edges_near(ctx, f, out.locked, stamp, ++stamp_value, near);
      if (near.empty()) ++suspect[ctx.labels[f]];
      raise.insert(raise.end(), near.begin(), near.end());
    }
    std::sort(raise.begin(), raise.end());
    raise.erase(std::unique(raise.begin(), raise.end()), raise.end());
    // A meta-edge next to flips is stiffened there `max_raises` times; the next time it is
    // locked (straight), which settles it for good.
    std::vector<char> raised_meta(ctx.meta.edges.size(), 0);
    for (const uint32_t s : raise) raised_meta[edge_meta[s]] = 1;
    for (uint32_t e = 0; e < ctx.meta.edges.size(); ++e)
      if (raised_meta[e] && ++raises[e] > opt.max_raises) out.locked[e] = 1;
    for (const uint32_t s : raise)
      if (!out.locked[edge_meta[s]])
        out.stiffness[s] = std::min(out.stiffness[s] * opt.growth, opt.max_stiffness);
    // No stiffness kinks along a seam: a weight is at least half of its neighbours'.
    for (uint32_t e = 0; e < ctx.meta.edges.size(); ++e) {
      const auto& hs = ctx.meta.edges[e].halfedges;
      for (std::size_t i = 1; i < hs.size(); ++i) {
        double& w = out.stiffness[mesh.edge(hs[i])];
        w = std::max(w, 0.5 * out.stiffness[mesh.edge(hs[i - 1])]);
      }
      for (std::size_t i = hs.size(); i-- > 1;) {
        double& w = out.stiffness[mesh.edge(hs[i - 1])];
        w = std::max(w, 0.5 * out.stiffness[mesh.edge(hs[i])]);
      }
      if (out.locked[e]) continue;
      bool at_max = false;
      for (const uint32_t h : hs) at_max |= out.stiffness[mesh.edge(h)] >= opt.max_stiffness;
      if (at_max) out.locked[e] = 1;
    }
    // Flips deep inside a patch, seen twice: straighten the whole patch boundary.
    for (uint32_t p = 0; p < suspect.size(); ++p)
      if (suspect[p] >= 2)
        for (const BoundaryItem& item : ctx.meta.faces[p].cycle) out.locked[item.edge] = 1;
  }
  return out;
}

Outcome solve_uniform(const Context& ctx, double lambda) {
  Outcome out;
  out.stiffness = EdgeData<double>(ctx.mesh.num_edges(), 1.0);
  const EdgeData<uint32_t>& edge_meta = ctx.system.edge_meta_edge();
  out.locked = ctx.system.always_locked();
  for (uint32_t e = 0; e < ctx.mesh.num_edges(); ++e)
    if (edge_meta[e] != kInvalid && !out.locked[edge_meta[e]]) out.stiffness[e] = lambda;
  out.map = ctx.system.solve(out.stiffness, out.locked, ctx.report);
  out.cert = ctx.check(out.map);
  out.ok = out.cert.ok();
  ++ctx.report.iterations;
  return out;
}

// The paper's weight adjustment: one weight for every seam edge, raised from max_stiffness until
// no triangle flips, then bisected (in log scale) down to the smallest that leaves none.
Outcome relax_bisection(const Context& ctx) {
  Outcome low = solve_uniform(ctx, 1.0);
  ctx.report.flipped_unstiffened = ctx.report.flipped_first =
      low.cert.flipped + low.cert.degenerate;
  if (low.ok) return low;
  // The upper bracket: weights large enough to leave no flip. The map tends to the (injective)
  // locked map as the weight grows, so raising it by 100 at a time ends; 1e12 is the limit.
  double lo = 0, hi = std::log(ctx.options.max_stiffness);
  Outcome best = solve_uniform(ctx, std::exp(hi));
  while (!best.ok && hi < std::log(1e12)) {
    lo = hi;
    hi += std::log(100.0);
    best = solve_uniform(ctx, std::exp(hi));
  }
  if (!best.ok) return best;
  for (uint32_t step = 0; step < ctx.options.bisection_steps; ++step) {
    const double mid = 0.5 * (lo + hi);
    Outcome o = solve_uniform(ctx, std::exp(mid));
    if (o.ok) {
      hi = mid;
      best = std::move(o);
    } else {
      lo = mid;
    }
  }
  return best;
}

}  // namespace

Param parametrize(const TriMesh& mesh, const FaceData<uint32_t>& labels, const MetaMesh& meta,
                  const Layout& layout, const ParamOptions& options, ParamReport& report,
                  const std::vector<uint32_t>* rank) {
  const auto t_total = Clock::now();
  report.weights = options.weights == WeightKind::smvc ? "smvc" : "mvc";
  static constexpr const char* kRelax[] = {"adaptive", "bisection", "locked", "none"};
  report.relax = kRelax[int(options.relax)];
  report.meta_edges = uint32_t(meta.edges.size());
  auto t0 = Clock::now();
  SeamSystem system(mesh, labels, meta, layout, options.weights, rank);
  report.unknowns = system.unknowns();
  report.setup_seconds = seconds_since(t0);
  const Context ctx{mesh, labels, meta, layout, options, report, system};

  // The locked map (every seam straight, each patch an independent fixed-boundary map) and the
  // relaxation are independent: they run side by side, each with its own report, and errors are
  // raised in a fixed order (the locked map's first), whichever thread met them first.
  Param result;
  const EdgeData<double> ones(mesh.num_edges(), 1.0);
  const std::vector<char> all(meta.edges.size(), 1);
  Certificate locked_cert;
  ParamReport locked_report;
  std::exception_ptr locked_error, relax_error;
  auto lock = [&] {
    try {
      result.locked = system.solve_locked(locked_report);
      locked_cert = certify(mesh, labels, meta, layout, result.locked);
    } catch (...) {
      locked_error = std::current_exception();
    }
  };
  Outcome out;
  auto relax = [&] {
    try {
      switch (options.relax) {
        case RelaxMode::adaptive:
          out = relax_adaptive(ctx);
          break;
        case RelaxMode::bisection:
          out = relax_bisection(ctx);
          break;
        case RelaxMode::none:
          out = solve_uniform(ctx, 1.0);
          report.flipped_unstiffened = report.flipped_first =
              out.cert.flipped + out.cert.degenerate;
          out.ok = true;  // returned as is, flips included
          break;
        case RelaxMode::locked:
          break;
      }
    } catch (...) {
      relax_error = std::current_exception();
    }
  };
  if (options.relax == RelaxMode::locked)
    lock();
  else
    tbb::parallel_invoke(lock, relax);
  report.symbolic += locked_report.symbolic;
  report.factorizations += locked_report.factorizations;
  report.solves += locked_report.solves;
  report.max_residual = std::max(report.max_residual, locked_report.max_residual);
  report.analyze_seconds += locked_report.analyze_seconds;
  report.assemble_seconds += locked_report.assemble_seconds;
  report.factorize_seconds += locked_report.factorize_seconds;
  report.solve_seconds += locked_report.solve_seconds;
  if (locked_error) std::rethrow_exception(locked_error);
  if (!locked_cert.ok()) {
    // Either the input has (near) zero-area triangles, or a patch is so unlike its rectangle
    // (a long strip laid out as a square) that the map crowds triangles to zero area.
    const uint32_t f = locked_cert.bad_faces.empty() ? kInvalid : locked_cert.bad_faces.front();
    double mean_area = 0;
    for (uint32_t g = 0; g < mesh.num_faces(); ++g) mean_area += mesh.face_area(g);
    mean_area /= std::max(1u, mesh.num_faces());
    const bool input_degenerate = f != kInvalid && mesh.face_area(f) < 1e-8 * mean_area;
    const std::string why =
        f == kInvalid ? "vertices with a wrong angle sum"
        : input_degenerate
            ? "the input has degenerate triangles - try --repair"
            : fmt::format(
                  "patch {} does not fit its {} x {} rectangle (the map crowds its "
                  "triangles to zero area) - try more --patches",
                  labels[f], layout.charts[labels[f]].width, layout.charts[labels[f]].height);
    throw Error(ErrorKind::solver, "E553",
                fmt::format("the locked map has {} flipped and {} degenerate faces and {} "
                            "vertices with a wrong angle sum (first face {}): {}",
                            locked_cert.flipped, locked_cert.degenerate, locked_cert.bad_angle_sums,
                            f, why));
  }

  if (relax_error) std::rethrow_exception(relax_error);
  if (options.relax == RelaxMode::locked) {
    out.map = result.locked;
    out.cert = locked_cert;
    out.stiffness = ones;
    out.locked = all;
    out.ok = true;
  }
  if (!out.ok) {  // relaxation gave up: the locked map is certified
    report.fell_back_to_locked = true;
    out.map = result.locked;
    out.cert = locked_cert;
    out.stiffness = ones;
    out.locked = all;
  }
  result.map = std::move(out.map);
  result.certificate = std::move(out.cert);
  result.stiffness = std::move(out.stiffness);
  result.locked_edges = std::move(out.locked);
  report.flipped_final = result.certificate.flipped + result.certificate.degenerate;
  report.locked_meta_edges =
      uint32_t(std::count(result.locked_edges.begin(), result.locked_edges.end(), char(1)));
  report.stiffened_edges = uint32_t(std::count_if(result.stiffness.begin(), result.stiffness.end(),
                                                  [](double w) { return w > 1; }));
  report.seam_angle_distortion =
      mean_angle_distortion(mesh, result.map, faces_near_seams(mesh, labels, 3));
  report.total_seconds = seconds_since(t_total);
  return result;
}

}  // namespace isoquad
