#include "pipeline/remesh.hpp"

#include <fmt/format.h>
#include <tbb/global_control.h>

#include <sys/resource.h>

#include <chrono>
#include <nlohmann/json.hpp>
#include <optional>

#include "io/mesh_arrays.hpp"
#include "io/report_json.hpp"
#include "isoquad/error.hpp"
#include "metrics/quality.hpp"
#include "pipeline/pipeline.hpp"
#include "pipeline/progress.hpp"
#include "prep/prepare.hpp"

namespace isoquad {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The process's peak resident memory so far (not this call's alone: in a long-lived process,
// e.g. Python, it includes what came before). Linux's ru_maxrss is in KiB, macOS's in bytes.
long long peak_rss_bytes() {
  rusage u{};
  if (getrusage(RUSAGE_SELF, &u) != 0) return 0;
#ifdef __APPLE__
  return static_cast<long long>(u.ru_maxrss);
#else
  return 1024LL * u.ru_maxrss;
#endif
}

nlohmann::json options_json(const RemeshOptions& o) {
  return {{"patches", o.patches},
          {"edge_length", o.edge_length},
          {"quads", o.quads},
          {"seed", o.seed},
          {"weights", o.paper_weights ? "mvc" : "smvc"},
          {"relax", o.relax},
          {"segmentation", o.segmentation},
          {"corners", o.local_corners ? "local" : "global"},
          {"improve_corners", o.improve_corners},
          {"feature_angle", o.feature_angle_deg},
          {"repair", o.repair},
          {"weld_epsilon", o.weld_epsilon},
          {"smooth", o.smooth},
          {"untangle", o.untangle},
          {"snap", o.snap},
          {"fold_rounds", o.fold_rounds},
          {"split_patches", o.split_patches},
          {"tolerance", o.tolerance},
          {"tolerance_rounds", o.tolerance_rounds},
          {"tip_split", o.tip_split},
          {"refine", o.refine},
          {"patch_rounds", o.patch_rounds},
          {"misfit_split", o.misfit_split},
          {"allow_topology_change", o.allow_topology_change},
          {"allow_invalid", o.allow_invalid}};
}

// Every option out of its range is refused (E003) before any work, rather than read as the
// default: quads = -5 or NaN ran at the default size.
void check_options(const RemeshOptions& o) {
  const auto refuse = [](const std::string& what) {
    throw Error(ErrorKind::invalid_input, "E003", what);
  };
  if (!(o.quads == 0 || (o.quads >= 1 && std::isfinite(o.quads))))
    refuse(fmt::format("quads {} is not a quad count (at least 1; 0 for the default)", o.quads));
  if (!(o.edge_length >= 0 && std::isfinite(o.edge_length)))
    refuse(
        fmt::format("edge length {} is not a length (positive; 0 for the default)", o.edge_length));
  if (o.quads > 0 && o.edge_length > 0) refuse("give a quad count or an edge length, not both");
  if (!(o.feature_angle_deg >= 0 && o.feature_angle_deg <= 180))
    refuse(fmt::format("feature angle {} is not in [0, 180] degrees", o.feature_angle_deg));
  if (!(o.weld_epsilon >= 0 && o.weld_epsilon <= 0.1))
    refuse(fmt::format("weld distance {} is not a fraction of the diagonal in [0, 0.1]",
                       o.weld_epsilon));
  if (o.relax != "adaptive" && o.relax != "bisection" && o.relax != "locked")
    refuse(fmt::format("unknown relaxation '{}' (adaptive, bisection or locked)", o.relax));
  if (o.segmentation != "vsa" && o.segmentation != "field")
    refuse(fmt::format("unknown segmentation '{}' (field or vsa)", o.segmentation));
  // The field layout's patches and corners come from its traces: VSA's patch count and corner
  // choice mean nothing there (a component that falls back to VSA takes VSA's defaults).
  if (o.segmentation == "field" && (o.patches > 0 || o.local_corners || o.split_patches))
    refuse(
        fmt::format("{} only for VSA's patches; the field layout's patches and corners come "
                    "from its traces (segmentation vsa to use {})",
                    o.patches > 0     ? "a patch count means something"
                    : o.local_corners ? "local corners mean something"
                                      : "splitting patches means something",
                    o.patches > 0 ? "it" : "them"));
  if (!(o.tolerance >= 0 && o.tolerance <= 1))
    refuse(fmt::format("tolerance {} is not a fraction of the diagonal in [0, 1]", o.tolerance));
  if (o.tolerance > 0 && (o.quads > 0 || o.edge_length > 0))
    refuse("tolerance chooses the size itself: give it without a quad count or edge length");
  if (o.tolerance > 0 && o.tolerance_rounds == 0)
    refuse("tolerance rounds must be at least 1 with a tolerance");
}

using Say = std::function<void(const std::string&)>;

// Every repair and warning of a run passes here, so that none is silent: said (the command line
// prints it on stderr unless -q) and kept for the report.
void warn(RemeshRun& run, InputIssue issue, const Say& say) {
  say(fmt::format("warning: {} [{}]", issue.message, issue.code));
  run.warnings.push_back(std::move(issue));
}

}  // namespace

std::optional<InputIssue> check_component_topology(uint32_t component, const Topology& input,
                                                   const Topology& quads, bool allow) {
  const std::string change = topology_change(input, quads);
  if (change.empty()) return std::nullopt;
  const std::string what =
      fmt::format("component {}: the quads' topology is not the input's ({})", component, change);
  if (!allow)
    throw Error(ErrorKind::extraction, "E603",
                what + "; --allow-topology-change (allow_topology_change) keeps them");
  return InputIssue{InputIssue::Severity::warning, "W113", what + ", kept as allowed", 1};
}

namespace {

// Where a component's quads are not valid: how many, the worst one's centre (input units) and
// the input face nearest to it, and what was tried. An error (E604) unless `allow` or a repair
// was switched off (the caller looks at what the passes leave), then W117.
std::optional<InputIssue> check_component_validity(const PreparedMesh& prep, uint32_t c,
                                                   const ComponentRun& r, bool allow,
                                                   bool repairs_off) {
  const QuadMesh& q = r.quads;
  uint32_t invalid = 0, worst = 0;
  double worst_value = INFINITY;
  for (uint32_t i = 0; i < q.quads.size(); ++i) {
    const auto& v = q.quads[i];
    const double sj = quad_scaled_jacobian(
        {q.positions[v[0]], q.positions[v[1]], q.positions[v[2]], q.positions[v[3]]});
    if (sj > kMinValidScaledJacobian) continue;
    ++invalid;
    if (sj < worst_value) worst_value = sj, worst = i;
  }
  if (invalid == 0) return std::nullopt;
  const auto& v = q.quads[worst];
  const Vec3 centre =
      (q.positions[v[0]] + q.positions[v[1]] + q.positions[v[2]] + q.positions[v[3]]) / 4.0;
  const PreparedComponent& comp = prep.components[c];
  uint32_t nearest = 0;
  double nearest_distance = INFINITY;
  for (uint32_t f = 0; f < comp.mesh.num_faces(); ++f) {
    const auto t = comp.mesh.face(f);
    const double d = norm(
        (comp.mesh.position(t[0]) + comp.mesh.position(t[1]) + comp.mesh.position(t[2])) / 3.0 -
        centre);
    if (d < nearest_distance) nearest_distance = d, nearest = f;
  }
  std::string tried;
  for (const std::string& a : r.alternatives_failed) tried += (tried.empty() ? "" : "; ") + a;
  if (repairs_off)
    tried = "the patches with a repair switched off or four-sided patches asked for";
  else if (tried.empty())
    tried = r.triangle_split ? "the triangle split, the only one for so few faces"
                             : "the patches, the only alternative run";
  const Vec3 at = prep.normalization.invert(centre);
  const std::string what = fmt::format(
      "component {}: no alternative gave valid quads: {} of {} have scaled Jacobian <= {} "
      "against their own normal, the worst ({:.3g}) at ({:.6g}, {:.6g}, {:.6g}) near input face "
      "{}; tried: {}",
      comp.report_index, invalid, q.quads.size(), kMinValidScaledJacobian, worst_value, at.x, at.y,
      at.z, comp.input_face[nearest], tried);
  if (!allow && !repairs_off)
    throw Error(ErrorKind::extraction, "E604",
                what + "; --allow-invalid (allow_invalid) keeps them");
  return InputIssue{InputIssue::Severity::warning, "W117",
                    what + (repairs_off ? ", kept" : ", kept as allowed"), invalid};
}

}  // namespace

PrepOptions prep_options(const RemeshOptions& o, bool unshared_vertices) {
  PrepOptions po;
  po.repair = o.repair;
  po.weld_all = unshared_vertices || o.weld_all;
  po.weld_epsilon = o.weld_epsilon;
  po.feature_angle_deg = o.feature_angle_deg;
  return po;
}

PreparedMesh check_input(const PolyMesh& input, const RemeshOptions& options,
                         bool unshared_vertices, bool diagnose) {
  check_options(options);
  PrepOptions po = prep_options(options, unshared_vertices);
  po.diagnose = diagnose;
  return prepare(input, po);
}

PolyRemesh remesh_polymesh(const PolyMesh& input, const RemeshOptions& opt, bool unshared_vertices,
                           const std::function<void(const std::string&)>& progress,
                           const ProgressCallback& advance) {
  return remesh_run(input, opt, unshared_vertices, progress, advance).result;
}

RemeshRun remesh_run(const PolyMesh& input, const RemeshOptions& opt, bool unshared_vertices,
                     const std::function<void(const std::string&)>& progress,
                     const ProgressCallback& advance) {
  // How far the run is: preparation and the quality measurements a small share each, the
  // components the rest, by their faces, each by its stages (pipeline/progress.hpp).
  ProgressMeter meter(advance);
  auto say = [&](const std::string& s) {
    if (progress) progress(s);
    meter.say(s);
  };
  meter.reach(0, "prepare");
  // Parallel stages are deterministic: the thread count changes the time, not the output.
  std::optional<tbb::global_control> limit;
  if (opt.threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, opt.threads);
  auto t0 = std::chrono::steady_clock::now();
  const auto start = t0;
  RemeshRun run;
  run.prep = check_input(input, opt, unshared_vertices);  // the options first, then the input
  const PreparedMesh& prep = run.prep;
  const double prep_s = seconds_since(t0);
  constexpr double kPrepareShare = 0.05;
  const double component_share = opt.quality ? 0.9 : 1 - kPrepareShare;
  uint64_t faces = 0, faces_done = 0;
  for (const PreparedComponent& c : prep.components) faces += c.mesh.num_faces();
  meter.set_fraction(kPrepareShare);
  say(fmt::format("prepared {} component{} ({:.0f} ms)", prep.components.size(),
                  prep.components.size() == 1 ? "" : "s", 1e3 * prep_s));
  for (const InputIssue& issue : prep.report.issues) warn(run, issue, say);
  PipelineOptions o;
  o.patches = opt.patches;
  o.edge_length = opt.edge_length;
  o.quads = opt.quads;
  o.seed = opt.seed;
  o.smooth = opt.smooth;
  o.untangle = opt.untangle;
  o.snap = opt.snap;
  o.fold_rounds = opt.fold_rounds;
  o.quad_split = opt.split_patches;
  o.tolerance = opt.tolerance;
  o.tolerance_rounds = opt.tolerance_rounds;
  o.tip_split = opt.tip_split;
  o.refine = opt.refine;
  o.patch_rounds = opt.patch_rounds;
  o.misfit_split = opt.misfit_split;
  o.allow_topology_change = opt.allow_topology_change;
  // The field gives the corners; the repairs that re-segment (tips, patch counts, misfit
  // regions) or re-choose corners are VSA's, and run (pipeline.cpp) on the components that
  // fall back to VSA's patches.
  o.field_layout = opt.segmentation == "field";
  o.layout.corners = opt.local_corners ? CornerMode::local : CornerMode::global;
  o.layout.improve_corners = opt.improve_corners;
  o.param.weights = opt.paper_weights ? WeightKind::mvc : WeightKind::smvc;
  o.param.relax = opt.relax == "bisection" ? RelaxMode::bisection
                  : opt.relax == "locked"  ? RelaxMode::locked
                                           : RelaxMode::adaptive;
  std::vector<ComponentRun>& runs = run.runs;
  nlohmann::json comps = nlohmann::json::array();
  o.stage_begins = [&](const char* stage) { meter.stage(stage); };
  for (uint32_t c = 0; c < prep.components.size(); ++c) {
    const auto component_done = [&] {
      return kPrepareShare +
             component_share * double(faces_done) / double(std::max<uint64_t>(faces, 1));
    };
    const double begin = component_done();
    faces_done += prep.components[c].mesh.num_faces();
    meter.enter_span(begin, component_done());
    runs.push_back(run_component(prep, c, o));
    const ComponentRun& r = runs.back();
    meter.set_fraction(component_done());
    const TriMesh& mesh = prep.components[c].mesh;
    const Topology input_topology{mesh.euler_characteristic(), mesh.num_components(),
                                  uint32_t(mesh.boundary_loops().size())};
    if (const auto changed = check_component_topology(
            prep.components[c].report_index, input_topology,
            topology_of(as_poly(r.quads), nullptr, nullptr, nullptr, nullptr, nullptr),
            opt.allow_topology_change))
      warn(run, *changed, say);
    if (const auto invalid =
            check_component_validity(prep, c, r, opt.allow_invalid, !o.repairs_on()))
      warn(run, *invalid, say);
    if (r.triangle_split && !r.triangle_split_reason.empty())
      warn(run,
           {InputIssue::Severity::warning, "W114",
            fmt::format("component {} could not be laid out ({}): each of its {} triangles split "
                        "into three quads, {} quads",
                        prep.components[c].report_index, r.triangle_split_reason,
                        r.surface.mesh.num_faces(), r.quads.quads.size()),
            1},
           say);
    else if (!r.four_sided_reason.empty())
      warn(run,
           {InputIssue::Severity::warning, "W115",
            fmt::format("component {} could not be laid out ({}): VSA's patches were each split "
                        "into four-sided ones",
                        prep.components[c].report_index, r.four_sided_reason),
            1},
           say);
    else if (r.triangle_split)
      warn(run,
           {InputIssue::Severity::warning, "W109",
            fmt::format("component {} has {} faces, too few for patches: each triangle split "
                        "into three quads",
                        prep.components[c].report_index, r.surface.mesh.num_faces()),
            1},
           say);
    else
      say(fmt::format(
          "component {}: segment {} patches ({:.0f} ms), layout {} quads ({:.0f} ms), "
          "param {} factorizations{} ({:.0f} ms), extract ({:.0f} ms)",
          c, r.seg.num_patches, 1e3 * r.segment_seconds, r.layout.quads(), 1e3 * r.layout_seconds,
          r.param_report.factorizations, r.param_report.fell_back_to_locked ? ", locked map" : "",
          1e3 * r.param_seconds, 1e3 * r.extract_seconds));
    if (r.size_rounds.size() > 1) {
      std::string tried;
      for (std::size_t k = 0; k < r.size_rounds.size(); ++k)
        tried +=
            fmt::format("{}{} quads {:.2f}%{}", k ? ", " : "", r.size_rounds[k].quads,
                        100 * r.size_rounds[k].distance, k == r.size_round_kept ? " (kept)" : "");
      say(fmt::format("component {}: sizes tried for the {:.2f}% tolerance: {}", c,
                      100 * o.tolerance, tried));
    }
    if (!r.tip_rounds.empty()) {
      std::string tried;
      for (std::size_t k = 0; k < r.tip_rounds.size(); ++k) {
        const auto& [tips, s] = r.tip_rounds[k];
        tried += fmt::format("{}{} tip{} {:.2f}% {} folded{}", k ? " -> " : "", tips,
                             tips == 1 ? "" : "s", 100 * s.distance, s.folded,
                             k == r.tip_round_kept ? " (kept)" : "");
      }
      say(fmt::format("component {}: tips split: {}", c, tried));
    }
    if (!r.refine_rounds.empty()) {
      std::string tried;
      for (std::size_t k = 0; k < r.refine_rounds.size(); ++k) {
        const auto& [marked, s] = r.refine_rounds[k];
        tried += fmt::format("{}{} quads {:.2f}% {} folded{}", k ? " -> " : "", s.quads,
                             100 * s.distance, s.folded, k == r.refine_round_kept ? " (kept)" : "");
      }
      say(fmt::format("component {}: refined where far: {}", c, tried));
    }
    if (!r.patch_rounds.empty()) {
      std::string tried;
      for (std::size_t k = 0; k < r.patch_rounds.size(); ++k) {
        const auto& [patches, s] = r.patch_rounds[k];
        tried += fmt::format("{}{} patches {:.2f}% {} folded{}", k ? " -> " : "", patches,
                             100 * s.distance, s.folded, k == r.patch_round_kept ? " (kept)" : "");
      }
      say(fmt::format("component {}: more patches: {}", c, tried));
    }
    if (r.misfit_split.regions > 0)
      say(
          fmt::format("component {}: misfit patches cut in two for folds: {} regions, {} -> {} "
                      "folded{}",
                      c, r.misfit_split.regions, r.misfit_split.folded_before,
                      r.misfit_split.folded_after, r.misfit_split.kept ? " (kept)" : ""));
    // The output is not all it should be: said, with where to look.
    if (const uint32_t n = r.untangle_report.nonpositive; n > 0) {
      std::string where;
      if (!r.untangle_report.folded.empty() && r.surface_tree) {
        // The untangler's list also holds degenerate quads (at or below kFoldedAtOrBelow)
        // where collapses ran: the one named is the most folded, measured as the untangler
        // does, against the surface normal just inside each corner and the quad's own normal.
        const AabbTree& tree = *r.surface_tree;
        const auto& p = r.quads.positions;
        uint32_t worst = r.untangle_report.folded.front();
        double lowest = INFINITY;
        for (const uint32_t f : r.untangle_report.folded) {
          const auto& q = r.quads.quads[f];
          const double sj = std::min(
              quad_corner_sj(r.quads, f,
                             [&](uint32_t, const Vec3& x) { return tree.normal_at_closest(x); }),
              quad_scaled_jacobian({p[q[0]], p[q[1]], p[q[2]], p[q[3]]}));
          if (sj < lowest) lowest = sj, worst = f;
        }
        const auto& q = r.quads.quads[worst];
        const Vec3 x = prep.normalization.invert(0.25 * (p[q[0]] + p[q[1]] + p[q[2]] + p[q[3]]));
        where = fmt::format(", {}near ({:.4g}, {:.4g}, {:.4g})", n == 1 ? "" : "the most folded ",
                            x.x, x.y, x.z);
      }
      say(
          fmt::format("component {}: warning: {} quad{} still fold{} against the surface or "
                      "{} own normal (a corner's scaled Jacobian at or below 0){}; another "
                      "--quads or --seed may avoid {}",
                      c, n, n == 1 ? "" : "s", n == 1 ? "s" : "", n == 1 ? "its" : "their", where,
                      n == 1 ? "it" : "them"));
    }
    std::map<std::string, int> valence;
    // How far the integer lengths are from the geodesic ones: x_e / c_e per meta-edge.
    const std::vector<double> ratio = r.layout.length_ratios();
    const auto at = [&](double q) {
      return ratio.empty() ? 0.0 : ratio[std::size_t(std::lround(q * double(ratio.size() - 1)))];
    };
    for (uint32_t v = 0; v < r.seg.meta.vertices.size(); ++v)
      if (!r.seg.meta.vertices[v].on_boundary) ++valence[std::to_string(r.layout.quarter_turns[v])];
    nlohmann::json sizes = nlohmann::json::array();
    for (const SizeRound& s : r.size_rounds)
      sizes.push_back({{"quads", s.quads}, {"hausdorff", s.distance}, {"folded", s.folded}});
    // Distances over the mesh's bounding-box diagonal.
    nlohmann::json tip_runs = nlohmann::json::array();
    for (const auto& [tips, s] : r.tip_rounds)
      tip_runs.push_back(
          {{"tips", tips}, {"quads", s.quads}, {"hausdorff", s.distance}, {"folded", s.folded}});
    const nlohmann::json tips = {{"tried", tip_runs}, {"kept", r.tip_round_kept}};
    nlohmann::json refine_runs = nlohmann::json::array();
    for (const auto& [marked, s] : r.refine_rounds)
      refine_runs.push_back({{"marked", marked},
                             {"quads", s.quads},
                             {"hausdorff", s.distance},
                             {"folded", s.folded}});
    nlohmann::json patch_runs = nlohmann::json::array();
    for (const auto& [patches, s] : r.patch_rounds)
      patch_runs.push_back({{"patches", patches},
                            {"quads", s.quads},
                            {"hausdorff", s.distance},
                            {"folded", s.folded}});
    comps.push_back({{"component", prep.components[c].report_index},
                     {"tip_split", tips},
                     {"refine", {{"tried", refine_runs}, {"kept", r.refine_round_kept}}},
                     {"patch_rounds", {{"tried", patch_runs}, {"kept", r.patch_round_kept}}},
                     {"size_rounds", {{"tried", sizes}, {"kept", r.size_round_kept}}},
                     {"subdivisions", r.subdivisions},
                     {"subdivision_retreats", r.subdivision_retreats},
                     {"corner_refinement_dropped", r.corners_unrefined},
                     {"fold_rounds", {{"tried", r.fold_rounds}, {"kept", r.fold_rounds_kept}}},
                     {"corners_retried", {{"tried", r.corner_tries}, {"kept", r.corner_try_kept}}},
                     {"misfit_split",
                      {{"regions", r.misfit_split.regions},
                       {"folded_before", r.misfit_split.folded_before},
                       {"folded_after", r.misfit_split.folded_after},
                       {"kept", r.misfit_split.kept}}},
                     {"triangle_split", r.triangle_split},
                     {"triangle_split_reason", r.triangle_split_reason},
                     {"four_sided_reason", r.four_sided_reason},
                     {"patches", r.seg.num_patches},
                     {"meta_vertices", r.seg.meta.vertices.size()},
                     {"meta_vertex_valence", valence},
                     {"quads", r.triangle_split ? int64_t(r.quads.quads.size()) : r.layout.quads()},
                     {"edge_length", r.layout.edge_length / prep.normalization.scale},
                     {"layout_repairs", r.layout_report.repairs},
                     {"length_ratio",
                      {{"min", at(0)},
                       {"p05", at(0.05)},
                       {"median", at(0.5)},
                       {"p95", at(0.95)},
                       {"max", at(1)}}},
                     {"factorizations", r.param_report.factorizations},
                     {"flipped_unstiffened", r.param_report.flipped_unstiffened},
                     {"flipped_first_solve", r.param_report.flipped_first},
                     {"locked_meta_edges", r.param_report.locked_meta_edges},
                     {"smoothing",
                      {{"iterations", r.smooth_report.iterations},
                       {"moves", r.smooth_report.moves},
                       {"rejected", r.smooth_report.rejected}}},
                     {"untangle",
                      {{"folded_before", r.untangle_report.folded_before},
                       {"folded_after", r.untangle_report.folded_after},
                       {"min_sj_before", r.untangle_report.min_before},
                       {"min_sj_after", r.untangle_report.min_after},
                       {"rounds", r.untangle_report.rounds},
                       {"moves", r.untangle_report.moves},
                       {"collapsed", r.untangle_report.collapsed},
                       {"doublets", r.untangle_report.doublets},
                       {"refused", r.untangle_report.refused},
                       {"split", r.untangle_report.split},
                       {"nonpositive", r.untangle_report.nonpositive},
                       {"degenerate", r.untangle_report.degenerate},
                       {"seconds", r.untangle_report.seconds}}},
                     {"snap",
                      {{"tips", r.snap_report.tips},
                       {"gaps", r.snap_report.gaps},
                       {"snapped", r.snap_report.snapped},
                       {"left", r.snap_report.left},
                       {"farthest_before", r.snap_report.farthest_before},
                       {"farthest_after", r.snap_report.farthest_after},
                       {"seconds", r.snap_report.seconds}}},
                     {"layout_source", r.field_used ? "field" : "vsa"},
                     {"field",
                      {{"fallback_reason", r.field_log.failure},
                       {"singularities", r.field_log.singularities},
                       {"nodes", r.field_log.nodes},
                       {"traces", r.field_log.traces},
                       {"t_junctions", r.field_log.t_junctions},
                       {"seeds", r.field_log.seeds},
                       {"connections", r.field_log.connections},
                       {"deleted", r.field_log.deleted},
                       {"rounds", r.field_log.rounds},
                       {"patches", r.field_log.patches},
                       {"repaired_patches", r.field_log.repaired_patches},
                       {"free_corner_patches", r.field_log.free_corner_patches},
                       {"angle_corner_patches", r.field_log.angle_corner_patches},
                       {"coarse",
                        {{"deleted", r.field_log.coarse_deleted},
                         {"evaluations", r.field_log.coarse_evaluations},
                         {"patches_traced", r.field_log.patches_traced},
                         {"misfit_traced", r.field_log.misfit_traced},
                         {"misfit", r.field_log.misfit}}},
                       {"seconds",
                        {{"field", r.field_log.field_seconds},
                         {"trace", r.field_log.trace_seconds},
                         {"embed", r.field_log.embed_seconds},
                         {"coarse", r.field_log.coarse_seconds}}}}},
                     {"fell_back_to_locked", r.param_report.fell_back_to_locked},
                     {"lattice_points",
                      {{"direct", r.extract_report.direct},
                       {"across_seam", r.extract_report.across},
                       {"locked_fallback", r.extract_report.locked},
                       {"meta_vertices", r.extract_report.meta},
                       {"quads", r.extract_report.quads},
                       {"multiply_covered", r.extract_report.multiply_covered},
                       {"patches_locked", r.extract_report.patches_locked}}},
                     {"seconds",
                      {{"segment", r.segment_seconds},
                       {"layout", r.layout_seconds},
                       {"param", r.param_seconds},
                       {"extract", r.extract_seconds}}},
                     {"param_seconds",
                      {{"setup", r.param_report.setup_seconds},
                       {"analyze", r.param_report.analyze_seconds},
                       {"assemble", r.param_report.assemble_seconds},
                       {"factorize", r.param_report.factorize_seconds},
                       {"solve", r.param_report.solve_seconds},
                       {"certify", r.param_report.certify_seconds}}}});
  }
  PolyRemesh& out = run.result;
  out.quads = merge_quads(prep, runs);
  nlohmann::json j = {{"quads", out.quads.num_faces()},
                      {"options", options_json(opt)},
                      {"components", comps},
                      {"warnings", run.warnings},
                      {"seconds", {{"prepare", prep_s}, {"remesh", seconds_since(start)}}}};
  if (opt.quality) {
    meter.reach(kPrepareShare + component_share, "quality");
    t0 = std::chrono::steady_clock::now();
    j["quality"] = measure_quality(out.quads, &input);
    j["seconds"]["quality"] = seconds_since(t0);
  }
  j["peak_rss_bytes"] = peak_rss_bytes();
  out.report = j.dump(2);
  meter.reach(1, "done");
  return run;
}

RemeshResult remesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                    const RemeshOptions& options, const ProgressCallback& progress) {
  const PolyMesh m = poly_mesh_from_arrays(V, F);
  const PolyRemesh r = remesh_polymesh(m, options, false, {}, progress);
  RemeshResult out;
  out.V.resize(Eigen::Index(r.quads.num_vertices()), 3);
  for (std::size_t i = 0; i < r.quads.num_vertices(); ++i)
    out.V.row(Eigen::Index(i)) << r.quads.positions[i].x, r.quads.positions[i].y,
        r.quads.positions[i].z;
  out.Q.resize(Eigen::Index(r.quads.num_faces()), 4);
  out.patch.resize(Eigen::Index(r.quads.num_faces()));
  for (std::size_t f = 0; f < r.quads.num_faces(); ++f) {
    for (int k = 0; k < 4; ++k) out.Q(Eigen::Index(f), k) = int(r.quads.face(f)[k]);
    out.patch(Eigen::Index(f)) = r.quads.face_group[f];
  }
  out.report = r.report;
  return out;
}

}  // namespace isoquad
