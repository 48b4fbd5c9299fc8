#include "pipeline/pipeline.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <optional>

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include "extract/split_triangles.hpp"
#include "isoquad/error.hpp"
#include "metrics/aabb_tree.hpp"
#include "metrics/quality.hpp"
#include "param/ordering.hpp"
#include "pipeline/sizing.hpp"

namespace isoquad {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// A stage begins (PipelineOptions::stage_begins): for the progress only.
void begin_stage(const PipelineOptions& o, const char* stage) {
  if (o.stage_begins) o.stage_begins(stage);
}

// A point on the subdivided surface, expressed in the component it was subdivided from.
SurfacePoint to_component(const RefinedMesh& surface, const SurfacePoint& s) {
  SurfacePoint out;
  out.face = surface.base_face[s.face];
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) out.bary[k] += s.bary[i] * surface.corner_bary[s.face][i][k];
  return out;
}

}  // namespace

RefinedMesh subdivide_coarse(const TriMesh& mesh, const EdgeData<char>& feature, double h,
                             double triangles_per_quad, EdgeData<char>& out_feature,
                             uint32_t& levels, uint32_t max_levels) {
  RefinedMesh r = identity_refinement(mesh);
  out_feature = feature;
  levels = 0;
  const double wanted = h > 0 ? triangles_per_quad * surface_area(mesh) / (h * h) : 0;
  // Each level has 4 times the faces: one is taken only if the surface stays under 250,000
  // (the rotor at 10,000 quads went from 77k to 307k triangles, and its map took minutes).
  while (levels < max_levels && r.mesh.num_faces() < wanted &&
         4 * std::size_t(r.mesh.num_faces()) <= 250000) {
    std::vector<uint32_t> all(r.mesh.num_edges());
    for (uint32_t e = 0; e < all.size(); ++e) all[e] = e;
    r = split_edges(r, all, nullptr, &out_feature);
    ++levels;
  }
  return r;
}

namespace {

// The tree of run.surface's faces, built on first use.
const AabbTree& surface_tree(ComponentRun& run) {
  if (!run.surface_tree)
    run.surface_tree = std::make_shared<const AabbTree>(face_triangles(run.surface.mesh));
  return *run.surface_tree;
}

// A place where the quads are far from the surface: how far, the surface vertex there, and the
// point that is far (that vertex, or a point of a quad).
struct FarPoint {
  double distance = 0;
  uint32_t vertex = kInvalid;
  Vec3 at;
};

// Where the quads are farther than `far` from the surface, the farthest first: surface
// vertices farther than that from the quads (a tip they cut off), and a quad's centre or edge
// midpoint farther than that from the surface (a valley they bridge), with the surface vertex
// nearest to it. A vertex may be listed more than once.
std::vector<FarPoint> far_points(const TriMesh& surface, const AabbTree& surface_tree,
                                 const QuadMesh& quads, double far) {
  const AabbTree tree(fan_triangles(quads));
  // Independent queries, in parallel into their own slots; gathered in index order.
  const uint32_t nv = surface.num_vertices(), nq = uint32_t(quads.quads.size());
  std::vector<double> vertex_distance(nv);
  std::vector<FarPoint> sample(5 * std::size_t(nq));
  tbb::parallel_invoke(
      [&] {
        tbb::parallel_for(uint32_t(0), nv, [&](uint32_t v) {
          vertex_distance[v] = tree.closest(surface.position(v)).distance;
        });
      },
      [&] {
        const auto& p = quads.positions;
        tbb::parallel_for(uint32_t(0), nq, [&](uint32_t i) {
          const auto& q = quads.quads[i];
          const Vec3 x[5] = {0.25 * (p[q[0]] + p[q[1]] + p[q[2]] + p[q[3]]),
                             0.5 * (p[q[0]] + p[q[1]]), 0.5 * (p[q[1]] + p[q[2]]),
                             0.5 * (p[q[2]] + p[q[3]]), 0.5 * (p[q[3]] + p[q[0]])};
          for (int k = 0; k < 5; ++k) {
            const AabbTree::Hit hit = surface_tree.closest(x[k]);
            if (hit.distance <= far) continue;
            uint32_t nearest = kInvalid;
            double best = INFINITY;
            for (const uint32_t v : surface.face(hit.triangle))
              if (norm(surface.position(v) - hit.point) < best)
                best = norm(surface.position(v) - hit.point), nearest = v;
            sample[5 * std::size_t(i) + k] = {hit.distance, nearest, x[k]};
          }
        });
      });
  std::vector<FarPoint> candidates;
  for (uint32_t v = 0; v < nv; ++v)
    if (vertex_distance[v] > far)
      candidates.push_back({vertex_distance[v], v, surface.position(v)});
  for (const FarPoint& f : sample)
    if (f.vertex != kInvalid) candidates.push_back(f);
  std::stable_sort(candidates.begin(), candidates.end(), [](const auto& x, const auto& y) {
    return x.distance != y.distance ? x.distance > y.distance : x.vertex < y.vertex;
  });
  return candidates;
}

// far_points' vertices, the farthest first, none within `spacing` of one taken before, and none
// nearer than half the farthest distance (`farthest`: that distance, 0 if none).
std::vector<uint32_t> cut_off_tips(const TriMesh& surface, const AabbTree& surface_tree,
                                   const QuadMesh& quads, double far, double spacing,
                                   double& farthest) {
  const auto candidates = far_points(surface, surface_tree, quads, far);
  farthest = candidates.empty() ? 0 : candidates.front().distance;
  std::vector<uint32_t> tips;
  for (const auto& [d, v, at] : candidates)
    if (d > 0.5 * farthest && std::none_of(tips.begin(), tips.end(), [&](uint32_t t) {
          return norm(surface.position(t) - surface.position(v)) < spacing;
        }))
      tips.push_back(v);
  return tips;
}

// The bounding-box diagonal of all components (1 if they are a point).
double mesh_diagonal(const PreparedMesh& prep) {
  Box3 box;
  for (const PreparedComponent& comp : prep.components)
    for (const Vec3& p : comp.mesh.positions()) box.add(p);
  return box.diagonal() > 0 ? box.diagonal() : 1.0;
}

// The quads with scaled Jacobian at most kMinValidScaledJacobian against their own normal: the
// output's validity as `isoquad quality` counts it.
uint32_t invalid_quads(const QuadMesh& quads) {
  uint32_t n = 0;
  for (const auto& q : quads.quads) {
    const std::array<Vec3, 4> at{quads.positions[q[0]], quads.positions[q[1]],
                                 quads.positions[q[2]], quads.positions[q[3]]};
    n += quad_scaled_jacobian(at) <= kMinValidScaledJacobian;
  }
  return n;
}

// How two tries compare where either is kept whole: fewer quads at or below the validity bound
// (UntangleReport::degenerate, which holds those at or below 0) first, then fewer at or below 0.
std::pair<uint32_t, uint32_t> invalid_score(const UntangleReport& r) {
  return {r.degenerate, r.nonpositive};
}

// A run's quads, their two-sided distance to `surface` (sampled as `isoquad quality` does) over
// `diagonal`, and its folded quads.
SizeRound measure_run(const ComponentRun& run, const AabbTree& surface, double diagonal) {
  const QualityOptions measure;
  const double d =
      surface_distance(fan_triangles(run.quads), surface, measure.samples, measure.seed).max;
  return SizeRound{run.quads.quads.size(), d / diagonal, run.untangle_report.nonpositive};
}

// The last touch of every extraction, on quads the fold repairs kept (of run's layout and map,
// on run.surface): the tips the quads cut off are snapped onto (only moves that make no fold).
void finish_quads(const PipelineOptions& o, ComponentRun& run, QuadMesh& quads, SnapReport& snap) {
  if (!o.snap) return;
  const auto t0 = Clock::now();
  SnapOptions so;
  so.edge_length = run.layout.edge_length;
  snap_tips(quads, run.surface.mesh, run.seg.refined.mesh, run.seg.meta, so, snap,
            &surface_tree(run));
  run.extract_seconds += seconds_since(t0);
}

// The stages from segmentation on, on the (possibly subdivided) surface already in `run`.
// `tips` and `vsa` (an earlier run's VSA partition, or null): SegmentOptions. `diagonal`: the
// mesh's bounding-box diagonal, the unit of the distance target.
void run_stages(double h, const PipelineOptions& o, const std::vector<uint32_t>& tips,
                const FaceData<uint32_t>* vsa, double diagonal, ComponentRun& run) {
  auto t0 = Clock::now();
  const TriMesh& surface = run.surface.mesh;
  // A large surface's elimination order (param/ordering.hpp) depends on the surface alone: it
  // is computed on a second thread while the segmentation runs, and serves every map below.
  std::vector<uint32_t> ranks;
  const bool dissect = o.last != Stage::segment && o.last != Stage::layout &&
                       surface.num_vertices() >= kNestedDissectionVertices;
  begin_stage(o, "segment");
  tbb::parallel_invoke(
      [&] {
        run.field_used = false;
        if (o.field_layout && tips.empty() && !vsa) {
          run.field_log = {};
          FieldSegmentation fs = field_segment(surface, run.surface_feature, h, run.field_log);
          if (run.field_log.failure.empty()) {
            run.seg = std::move(fs.seg);
            run.field_corners = std::move(fs.corners);
            run.field_preferred = std::move(fs.preferred);
            run.field_quarter_turns = std::move(fs.quarter_turns);
            run.field_used = true;
            return;
          }
        }
        SegmentOptions so = SegmentOptions::sized(h, o.patches, o.seed);
        so.piecewise_disks = o.piecewise_disks;
        so.tips = tips;
        so.vsa_labels = vsa;
        run.seg = segment(surface, run.surface_feature, so);
      },
      [&] {
        if (dissect && run.surface_ranks.size() != surface.num_vertices())
          run.surface_ranks = nested_dissection_ranks(surface);
        // Untangling, snapping and the tip search query the surface: its tree is built here, on
        // the core the segmentation leaves idle.
        if (o.last == Stage::extract) surface_tree(run);
      });
  run.segment_seconds += seconds_since(t0);
  if (o.last == Stage::segment) return;

  LayoutOptions sized_layout = o.layout;
  sized_layout.edge_length = o.edge_length > 0 ? h : 0;
  sized_layout.quads = o.edge_length > 0 ? 0 : (o.quads > 0 ? o.quads * run.area_share : 0);
  sized_layout.default_share = run.area_share;
  LayoutOptions lo = sized_layout;
  begin_stage(o, "layout");
  t0 = Clock::now();
  auto split = [&] {
    run.quad_split.emplace();
    split_patches_into_quads(run.seg, *run.quad_split);
  };
  auto layout = [&] {
    run.layout_report = {};
    lo.given_corners = run.field_used && !run.quad_split ? &run.field_corners : nullptr;
    lo.preferred_corners = lo.given_corners ? &run.field_preferred : nullptr;
    lo.field_quarter_turns = lo.given_corners ? &run.field_quarter_turns : nullptr;
    run.layout = solve_layout(run.seg.refined.mesh, run.seg.labels, run.seg.feature, run.seg.meta,
                              lo, run.layout_report);
  };
  // The layout may insert meta-vertices; a second choice of corners starts from the meta-mesh as
  // the segmentation built it.
  std::optional<MetaMesh> segmented;
  if (o.untangle && o.corner_retry_penalty > 0 && o.last != Stage::layout && !run.field_used)
    segmented = run.seg.meta;
  if (o.quad_split) split();
  if (run.field_used) {
    try {
      layout();
    } catch (const Error& e) {
      // The traced corners admit no lengths: this component takes VSA's patches instead.
      if (e.kind() != ErrorKind::layout) throw;
      run.field_log.failure = fmt::format("the layout of the traced patches failed: {}", e.what());
      run.field_used = false;
      SegmentOptions so = SegmentOptions::sized(h, o.patches, o.seed);
      so.piecewise_disks = o.piecewise_disks;
      run.seg = segment(surface, run.surface_feature, so);
      if (o.untangle && o.corner_retry_penalty > 0 && o.last != Stage::layout)
        segmented = run.seg.meta;
    }
  }
  if (!run.field_used) {
    try {
      layout();
    } catch (const Error& e) {
      // The paper's repair (§5), which always succeeds, once nothing cheaper did.
      if (e.code() != "E402" || run.quad_split) throw;
      split();
      layout();
    }
  }
  if (run.quad_split)
    run.layout_report.repairs.push_back(
        fmt::format("every patch split into four-sided ones (paper section 5): {} -> {} patches{}",
                    run.quad_split->patches_before, run.quad_split->patches_after,
                    run.quad_split->refinements
                        ? fmt::format(", surface refined {} times", run.quad_split->refinements)
                        : ""));
  run.layout_seconds += seconds_since(t0);
  if (o.last == Stage::layout) return;

  auto param_and_extract = [&] {
    begin_stage(o, "map");
    auto t = Clock::now();
    run.param_report = {};
    const TriMesh& mesh = run.seg.refined.mesh;
    if (dissect && ranks.size() != mesh.num_vertices())  // first map, or refined since
      ranks = extend_ranks(mesh, run.surface_ranks);
    run.param = parametrize(mesh, run.seg.labels, run.seg.meta, run.layout, o.param,
                            run.param_report, dissect ? &ranks : nullptr);
    run.param_seconds += seconds_since(t);
    if (o.last == Stage::param) return;

    begin_stage(o, "extract");
    t = Clock::now();
    run.extract_report = {};
    run.untangle_report = {};
    run.quads = extract_quads(run.seg.refined, surface, run.seg.labels, run.seg.meta, run.layout,
                              run.param, run.extract_report);
    if (o.untangle) {
      UntangleOptions uo;
      uo.edge_length = run.layout.edge_length;
      uo.collapse_rounds = 0;  // once, at the end: a fold round may still remove the fold
      untangle_quads(run.quads, surface, run.seg.refined.mesh, run.seg.meta, uo,
                     run.untangle_report, &surface_tree(run));
    }
    run.extract_seconds += seconds_since(t);
  };
  // Surface points on the subdivided surface, expressed in the component.
  auto to_component_points = [&] {
    if (run.subdivisions > 0 && o.last != Stage::param)
      for (SurfacePoint& p : run.quads.surface) p = to_component(run.surface, p);
  };
  param_and_extract();
  if (o.last == Stage::param || !o.untangle) return to_component_points();

  // Diagonal collapses (extract/collapse.hpp) of the quads `r` lists as folded, merged into `r`.
  auto collapse_folds = [&](QuadMesh& quads, UntangleReport& r) {
    const auto t = Clock::now();
    UntangleOptions uo;
    uo.edge_length = run.layout.edge_length;
    UntangleReport last;
    untangle_quads(quads, surface, run.seg.refined.mesh, run.seg.meta, uo, last,
                   &surface_tree(run));
    r.folded_after = last.folded_after;
    r.folded = std::move(last.folded);
    r.min_after = last.min_after;
    r.rounds += last.rounds;
    r.moves += last.moves;
    r.collapsed = last.collapsed;
    r.doublets = last.doublets;
    r.refused = last.refused;
    r.split = last.split;
    r.nonpositive = last.nonpositive;
    r.degenerate = last.degenerate;
    r.seconds += last.seconds;
    run.extract_seconds += seconds_since(t);
  };
  // Back to `before` after a fold repair not kept, keeping the time it took and the tries counted.
  auto undo_try = [&](ComponentRun& before) {
    before.segment_seconds = run.segment_seconds;
    before.layout_seconds = run.layout_seconds;
    before.param_seconds = run.param_seconds;
    before.extract_seconds = run.extract_seconds;
    before.fold_rounds = run.fold_rounds;
    before.corner_tries = run.corner_tries;
    before.misfit_split = run.misfit_split;
    run = std::move(before);
  };
  // Folds left after untangling: thicker patches, then diagonal collapses.
  auto repair_folds = [&] {
    begin_stage(o, "repair");
    // Where diagonal collapses alone remove every fold and leave the quads within the distance
    // target, that is the repair: the rounds below cost a map each and, on fandisk at 1,500
    // quads, one round (not kept) was a third of the whole run. Where the quads are farther,
    // the rounds still go first (three_peaks at the default size: 0.77% of the diagonal with a
    // thicker patch, 1.91% with the collapses alone).
    // The collapsed copy also serves below if no round is kept (the quads are then these).
    std::optional<std::pair<QuadMesh, UntangleReport>> collapsed;
    if (o.fold_rounds > 0 && run.untangle_report.degenerate > 0) {
      collapsed.emplace(run.quads, run.untangle_report);
      auto& [quads, report] = *collapsed;
      collapse_folds(quads, report);
      const double target = (o.tolerance > 0 ? o.tolerance : kTipTarget) * diagonal;
      if (report.degenerate == 0 && far_points(surface, surface_tree(run), quads, target).empty()) {
        run.quads = std::move(quads);
        run.untangle_report = std::move(report);
        return;
      }
    }
    const uint32_t kept_before = run.fold_rounds_kept;
    // Quads still folded after untangling: give their patches more quads across and solve again,
    // while a round leaves fewer folded quads. A round that does not is undone and is the last: on
    // the corpus at 1,500 quads no round after one had helped (fandisk, mech-holes-shark and the
    // double torus spent a second map on nothing).
    std::vector<SideMinimum> minimums;
    // Each repair has its own rounds (a second choice of corners got none where the first had
    // used them up); run.fold_rounds counts them all.
    for (uint32_t round = 0; round < o.fold_rounds && !run.untangle_report.folded.empty();
         ++round) {
      std::vector<uint32_t> patches;
      for (const uint32_t q : run.untangle_report.folded)
        patches.push_back(run.quads.quad_patch[q]);
      std::sort(patches.begin(), patches.end());
      patches.erase(std::unique(patches.begin(), patches.end()), patches.end());
      thicken_patches(run.seg.meta, run.layout, patches, minimums);
      ComponentRun before = run;
      auto undo = [&] { undo_try(before); };
      ++run.fold_rounds;
      try {
        begin_stage(o, "layout");
        t0 = Clock::now();
        std::optional<Layout> thicker =
            relayout_lengths(run.seg.refined.mesh, run.seg.labels, run.seg.meta, run.layout,
                             minimums, lo, run.layout_report);
        run.layout_seconds += seconds_since(t0);
        if (!thicker) {  // too many quads
          undo();
          break;
        }
        run.layout = std::move(*thicker);
        param_and_extract();
      } catch (const Error& e) {
        if (e.code() != "E553" && e.code() != "E502") throw;
        undo();
        break;
      }
      if (run.untangle_report.nonpositive >= before.untangle_report.nonpositive) {
        undo();
        break;
      }
      ++run.fold_rounds_kept;
    }

    // What folds are left go by diagonal collapses. After the rounds: a collapse can cut a little
    // off the surface, a thicker patch does not, and its extra quads also follow the surface
    // closer (collapsing instead of the rounds left the elephant and the anchor at 1,500 quads
    // with a fold each that their rounds had removed). With no round kept, the quads are those
    // the copy above was collapsed from, so its result is taken.
    if (run.untangle_report.degenerate == 0) return;
    if (collapsed && run.fold_rounds_kept == kept_before) {
      run.quads = std::move(collapsed->first);
      run.untangle_report = std::move(collapsed->second);
    } else {
      collapse_folds(run.quads, run.untangle_report);
    }
  };
  repair_folds();

  // Folds left still: choose the corners again with other prices, and repair again; the run
  // with the fewest invalid quads is kept (ties: the earlier). In order, while quads fold:
  //  - a price on corners on straight creases, where the mesh has creases (such a corner's quad
  //    opens to 180 degrees between vertices that may only slide along the crease);
  //  - a price on every corner at a flat place (above 150 degrees);
  //  - twice the angle weight (corners nearer the patches' geometric corners).
  // None is the first choice. The layout's outcome is chaotic in these prices: over the corpus at
  // 1,500 quads the flat price moved folds around (10 -> 13 in all; the elephant 0 -> 3, rotor
  // 2 -> 0), the crease price cost fandisk 0.49 -> 0.93% and rotor 1.67 -> 2.06% Hausdorff while
  // folds went 9 -> 8, and twice the angle weight took folds 8 -> 3 at 1,500 quads but 5 -> 9 at
  // the default size. As tries where quads still fold, each can only help (knot1 at the default
  // size: 25 -> 0 by the flat price, its strip ends had corners at flat places).
  // The layout, map, quads and fold repairs again (after new corners or patches): whether fewer
  // quads are invalid than in `before` (invalid_score: a quad at a scaled Jacobian of 0.0005
  // fails the output as one at -0.5 does, and a 180-degree corner held to a crease is one that
  // no pass after this opens).
  auto solve_again = [&](const UntangleReport& before) {
    begin_stage(o, "layout");
    t0 = Clock::now();
    layout();
    run.layout_seconds += seconds_since(t0);
    param_and_extract();
    repair_folds();
    return invalid_score(run.untangle_report) < invalid_score(before);
  };
  struct CornerTry {
    double flat = 0, crease = 0, angle_weight = 0;
  };
  std::vector<CornerTry> tries;
  if (segmented && !run.quad_split && o.fold_rounds > 0 && o.corner_retry_penalty > 0 &&
      lo.flat_corner_penalty == 0 && lo.flat_crease_corner_penalty == 0) {
    const double beta = lo.angle_weight;
    if (std::any_of(segmented->edges.begin(), segmented->edges.end(),
                    [](const MetaEdge& e) { return e.feature; }))
      tries.push_back({0, o.corner_retry_penalty, beta});
    tries.push_back({o.corner_retry_penalty, 0, beta});
    if (beta > 0) tries.push_back({0, 0, 2 * beta});
  }
  for (const CornerTry& t : tries) {
    if (run.untangle_report.degenerate == 0) break;
    ComponentRun before = run;
    lo.flat_corner_penalty = t.flat;
    lo.flat_crease_corner_penalty = t.crease;
    lo.angle_weight = t.angle_weight;
    bool keep = false;
    // The refined corners first, even where they were given up for the first choice: with the
    // new price they differ (knot1 at the default size).
    for (const bool refine : {true, false}) {
      run.seg.meta = *segmented;
      lo.improve_corners = refine;
      try {
        keep = solve_again(before.untangle_report);
        break;
      } catch (const Error& e) {
        if (e.code() != "E553" && e.code() != "E502" && e.code() != "E402" && e.code() != "E401")
          throw;
        if (e.code() != "E553") break;
      }
    }
    ++run.corner_tries;
    if (!keep) {
      undo_try(before);
    } else {
      run.corner_try_kept = run.corner_tries;
    }
  }
  // Folds left still, and patches whose shape no rectangle follows (layout/layout.hpp
  // misfit_patches): their VSA regions are cut in two (seg/vsa.hpp split_vsa_regions) and the
  // stages run again from there; kept if fewer quads are invalid. The last try: it changes the
  // patches.
  if (o.misfit_split && !run.field_used && !run.quad_split && o.fold_rounds > 0 &&
      run.untangle_report.degenerate > 0) {
    // Each patch's VSA region (for a patch that took in a tiny neighbour in the disk repair,
    // one of the two).
    std::vector<uint32_t> region_of(run.seg.num_patches, kInvalid);
    for (uint32_t f = 0; f < run.seg.labels.size(); ++f)
      region_of[run.seg.labels[f]] = run.seg.vsa_labels[run.seg.refined.base_face[f]];
    std::vector<uint32_t> regions;
    for (const uint32_t p : misfit_patches(run.seg.meta, run.layout))
      regions.push_back(region_of[p]);
    std::sort(regions.begin(), regions.end());
    regions.erase(std::unique(regions.begin(), regions.end()), regions.end());
    if (!regions.empty()) {
      ComponentRun before = run;
      bool keep = false;
      run.misfit_split.folded_before = run.misfit_split.folded_after =
          run.untangle_report.nonpositive;
      try {
        begin_stage(o, "segment");
        t0 = Clock::now();
        SegmentOptions so = SegmentOptions::sized(h, o.patches, o.seed);
        so.piecewise_disks = o.piecewise_disks;
        const FaceData<uint32_t> split =
            split_vsa_regions(surface, run.surface_feature, run.seg.vsa_labels, regions, so.vsa);
        so.tips = tips;
        so.vsa_labels = &split;
        run.seg = segment(surface, run.surface_feature, so);
        run.segment_seconds += seconds_since(t0);
        ranks.clear();
        lo = sized_layout;
        keep = solve_again(before.untangle_report);
        run.misfit_split.folded_after = run.untangle_report.nonpositive;
      } catch (const Error& e) {
        // A run that fails (a patch not cut into a disk, no layout, a map that does not
        // certify) is a try not kept; a bug is not.
        if (e.kind() == ErrorKind::internal) throw;
      }
      run.misfit_split.regions = uint32_t(regions.size());
      run.misfit_split.kept = keep;
      if (!keep) undo_try(before);
    }
  }
  finish_quads(o, run, run.quads, run.snap_report);
  to_component_points();
}

}  // namespace

namespace {

// Seconds of the runs tried and not kept, added to the kept run's stages so that they sum to the
// time spent.
struct UnkeptSeconds {
  double segment = 0, layout = 0, param = 0, extract = 0;
  void add(const ComponentRun& r) {
    segment += r.segment_seconds, layout += r.layout_seconds;
    param += r.param_seconds, extract += r.extract_seconds;
  }
  void charge(ComponentRun& r) const {
    r.segment_seconds += segment, r.layout_seconds += layout;
    r.param_seconds += param, r.extract_seconds += extract;
  }
};

// PipelineOptions::tip_split: the run again with the tips of `run` made meta-vertices, from
// the same VSA partition; the closer run with no more folded quads is kept. Then the tips of
// the kept run are added to those, and so on, at most kTipRounds runs with tips. After a run
// that is not kept and added several tips to the kept run, tips are added to the kept run one at
// a time (the farthest first); after any other run not kept, the next run adds the tips found on
// that run.
void split_tips(double h, const PipelineOptions& o, double diagonal, ComponentRun& run) {
  if (!o.tip_split || run.field_used || o.last != Stage::extract || run.quads.quads.empty()) return;
  const AabbTree& surface = surface_tree(run);
  const double edge = run.layout.edge_length;
  const double target = o.tolerance > 0 ? o.tolerance : kTipTarget;
  std::vector<ComponentRun::TipRound> rounds;
  uint32_t kept = 0;
  UnkeptSeconds unkept;
  bool one_at_a_time = false;
  std::optional<ComponentRun> latest;  // a run not kept that the next one starts from
  while (rounds.size() <= kTipRounds) {
    const bool from_kept = !latest;
    const ComponentRun& from = from_kept ? run : *latest;
    double farthest = 0;
    const std::vector<uint32_t> found = cut_off_tips(from.surface.mesh, surface, from.quads,
                                                     kTipFar * edge, kTipSpacing * edge, farthest);
    if (found.empty() || farthest <= target * diagonal) break;
    // The new tips after the earlier ones. Not kept apart from them: the armadillo's second
    // round at 1,500 quads (2.89% -> 1.80%) took a tip less than h from one of the first.
    std::vector<uint32_t> tips = from.tips;
    for (const uint32_t t : found) {
      if (std::find(tips.begin(), tips.end(), t) != tips.end()) continue;
      tips.push_back(t);
      if (one_at_a_time) break;  // the farthest new one only
    }
    if (tips.size() == from.tips.size()) break;  // all made corners already
    if (rounds.empty()) rounds.push_back({0, measure_run(run, surface, diagonal)});
    ComponentRun again;
    again.component = run.component;
    again.area_share = run.area_share;
    again.surface = run.surface;
    again.surface_feature = run.surface_feature;
    again.subdivisions = run.subdivisions;
    again.surface_ranks = run.surface_ranks;
    again.surface_tree = run.surface_tree;
    again.subdivision_retreats = run.subdivision_retreats;
    again.corners_unrefined = run.corners_unrefined;
    again.field_log = run.field_log;  // why the traced patches were not used, if they were tried
    try {
      run_stages(h, o, tips, &run.seg.vsa_labels, diagonal, again);
    } catch (const Error&) {
      break;  // the run before stands
    }
    again.seg.energy_log = run.seg.energy_log;
    const std::size_t added = tips.size() - from.tips.size();
    again.tips = std::move(tips);
    const SizeRound r = measure_run(again, surface, diagonal);
    rounds.push_back({uint32_t(again.tips.size()), r});
    const SizeRound& best = rounds[kept].result;
    // With a count asked for, not past it (unless the run without tips is past it already).
    const double most = o.quads > 0 ? std::max(kCountSlack * o.quads * run.area_share,
                                               double(rounds[0].result.quads))
                                    : INFINITY;
    const bool better =
        r.folded <= best.folded && r.distance < best.distance && double(r.quads) <= most;
    const ComponentRun& loser = better ? run : again;
    unkept.add(loser);
    if (better) {
      kept = uint32_t(rounds.size() - 1);
      run = std::move(again);
      latest.reset();
    } else if (from_kept && added >= 2 && !one_at_a_time) {
      // Many tips at once change the whole layout: the cow at the default size went 2.55% and
      // 2 folded quads -> 2.79% and 1 with its 8 tips, then 2.43% and none with the farthest
      // alone, and 2.32% with the next.
      one_at_a_time = true;
      latest.reset();
    } else {
      // A tip moves the layout near it, and the quads there cut off other points: the rotor at
      // 1,500 quads, its map factored supernodally, went 2.18% -> 1.11% with 3 folded quads (one
      // tip), 1.51% with 2 (three tips), 0.90% and none (four tips).
      latest = std::move(again);
    }
  }
  unkept.charge(run);
  run.tip_rounds = std::move(rounds);
  run.tip_round_kept = kept;
}

// PipelineOptions::refine: where the kept run's quads still fold against the surface or are
// farther than the distance target from it, the lattice is cut finer in the same map
// (refine_lattice_quads) around the lattice point nearest to each folded quad, to the farthest
// point and to every other point beyond the target (with a count asked for, and beyond
// kRefineFocus of the farthest), in that order. Where that would pass the count (kRefineGrowth
// times the first, kRefineGrowthSized times a count asked for, or the first with an edge length
// asked for), only around the longest prefix of them that stays within it (the cow at 1,500 quads,
// at 1,598 of the 1,650 allowed, had refined nothing before: every far point at once passed the
// count). The finer quads are untangled and finished like the first. Rounds follow, each cutting
// again where the round before still folds or is far, at most kRefineRounds. A round is kept over
// the first with fewer folded quads, or with as many where it reaches the target or (with a count
// asked for) is nearer than kRefineGain of the first; over a round kept before it with fewer folds,
// or as many and nearer. A round that reaches the target with no fold is the last (the cow at 1,500
// quads: 3.36% and a fold -> 2.03% and none in four rounds, 1,644 quads). A round that folds more
// quads than the first is tried again without the marks near them (kRefineAttempts tries), and
// those points are not marked again.
void refine_far(const PipelineOptions& o, double diagonal, ComponentRun& run) {
  if (!o.refine || !o.untangle || o.last != Stage::extract || run.quads.quads.empty()) return;
  const AabbTree& tree = surface_tree(run);
  const double target = (o.tolerance > 0 ? o.tolerance : kTipTarget) * diagonal;
  const QualityOptions measure;
  SurfaceDistance d =
      surface_distance(fan_triangles(run.quads), tree, measure.samples, measure.seed);
  run.measured =
      SizeRound{run.quads.quads.size(), d.max / diagonal, run.untangle_report.nonpositive};
  if (d.max <= target && run.untangle_report.nonpositive == 0) return;
  const auto t0 = Clock::now();
  const TriMesh& surface = run.surface.mesh;
  const SizeRound first{run.quads.quads.size(), d.max / diagonal, run.untangle_report.nonpositive};
  // A count asked for stays within kRefineGrowthSized of it.
  const double most = o.quads > 0         ? kRefineGrowthSized * o.quads * run.area_share
                      : o.edge_length > 0 ? kRefineGrowthSized * double(first.quads)
                                          : kRefineGrowth * double(first.quads);
  std::vector<ComponentRun::RefineRound> rounds{{0, first}};
  LatticeQuads lattice = lattice_quads(run.seg.meta, run.layout);
  // The lattice quads where the map puts them (before untangling): far points are matched to
  // the quad nearest to them here.
  ExtractReport placed_report;
  QuadMesh placed = place_quads(run.seg.refined, surface, run.seg.labels, run.seg.meta, run.layout,
                                run.param, lattice, placed_report);
  QuadMesh latest = run.quads;  // the last round's quads, finished
  // The centres of the quads folded there.
  auto folded_centres = [](const QuadMesh& quads, const UntangleReport& report) {
    std::vector<Vec3> out;
    for (const uint32_t f : report.folded) {
      const auto& q = quads.quads[f];
      const auto& x = quads.positions;
      out.push_back(0.25 * (x[q[0]] + x[q[1]] + x[q[2]] + x[q[3]]));
    }
    return out;
  };
  std::vector<Vec3> folds = folded_centres(latest, run.untangle_report);
  std::vector<char> spared(lattice.points.size(), 0);
  const double seconds_before = run.extract_seconds;
  struct Kept {
    uint32_t round = 0;
    double distance = 0;
    uint32_t folded = 0;
    QuadMesh quads;
    ExtractReport extract;
    UntangleReport untangle;
    SnapReport snap;
  };
  std::optional<Kept> best;  // the round to keep
  for (uint32_t round = 0; round < kRefineRounds && (d.max > target || !folds.empty()); ++round) {
    begin_stage(o, "repair");
    const AabbTree placed_tree(fan_triangles(placed));
    // Marks the lattice point nearest to x: the four quads around it are cut by the one-corner
    // template, eight quads more. Marking all four corners of the quad there instead cuts about
    // 40 more: at the default size the hand had 1,494 quads and 165 irregular vertices that way,
    // 1,344 and 73 this way, within 1% both; in one round, the cow at 1,500 quads went 3.36% ->
    // 2.59% this way within the count, and not below 3.36% that way.
    auto mark_near = [&](std::vector<char>& marks, const Vec3& x) {
      const uint32_t q = placed_tree.closest(x).triangle / 2;
      const auto& c = lattice.quads[q];
      if (lattice.level[q] >= LatticeQuads::kMaxLevel ||
          std::any_of(c.begin(), c.end(), [&](uint32_t v) { return spared[v] != 0; }))
        return;
      uint32_t nearest = c[0];
      for (const uint32_t v : c)
        if (norm(placed.positions[v] - x) < norm(placed.positions[nearest] - x)) nearest = v;
      marks[nearest] = 1;
    };
    // Where to cut, in order: the folded quads, the farthest point, the other points beyond
    // the target (with a count asked for, and kRefineFocus of the farthest), from the farthest.
    std::vector<Vec3> at = folds;
    if (d.max > target) {
      at.push_back(d.at);
      const double near_farthest = o.quads > 0 ? std::max(target, kRefineFocus * d.max) : target;
      for (const FarPoint& f : far_points(surface, tree, latest, near_farthest)) at.push_back(f.at);
    }
    auto marks_of = [&](std::size_t k) {  // near the first k
      std::vector<char> marks(lattice.points.size(), 0);
      for (std::size_t i = 0; i < k; ++i) mark_near(marks, at[i]);
      return marks;
    };
    auto cut = [&](const std::vector<char>& marks) {
      LatticeQuads finer = lattice;
      refine_lattice_quads(finer, run.layout, marks);
      return finer;
    };
    std::vector<char> marks;
    std::optional<std::pair<LatticeQuads, QuadMesh>> done;  // the round's lattice and placement
    UntangleReport untangle_report;
    ExtractReport extract_report;
    QuadMesh quads;
    for (uint32_t attempt = 0; attempt < kRefineAttempts && !done; ++attempt) {
      marks = marks_of(at.size());
      if (std::count(marks.begin(), marks.end(), 1) == 0) break;
      LatticeQuads finer = cut(marks);
      if (double(finer.quads.size()) > most) {
        // Past the count: the first places only, as many as the count allows (the count grows
        // with k; the armadillo at 1,500 quads cut 2,432 with every far point marked).
        std::size_t fits = 0, over = at.size();
        while (over - fits > 1) {
          const std::size_t k = fits + (over - fits) / 2;
          LatticeQuads trial = cut(marks_of(k));
          if (double(trial.quads.size()) > most) {
            over = k;
          } else {
            fits = k;
            finer = std::move(trial);
          }
        }
        marks = marks_of(fits);
        if (std::count(marks.begin(), marks.end(), 1) == 0) break;
      }
      extract_report = {};
      QuadMesh finer_placed = place_quads(run.seg.refined, surface, run.seg.labels, run.seg.meta,
                                          run.layout, run.param, finer, extract_report);
      quads = finer_placed;
      UntangleOptions uo;
      uo.edge_length = run.layout.edge_length;
      untangle_report = {};
      untangle_quads(quads, surface, run.seg.refined.mesh, run.seg.meta, uo, untangle_report,
                     &tree);
      if (untangle_report.nonpositive > first.folded && attempt + 1 < kRefineAttempts) {
        for (const Vec3& centre : folded_centres(quads, untangle_report))
          for (const uint32_t v : lattice.quads[placed_tree.closest(centre).triangle / 2])
            spared[v] = 1;
        continue;
      }
      done.emplace(std::move(finer), std::move(finer_placed));
    }
    if (!done) break;
    SnapReport snap_report;
    finish_quads(o, run, quads, snap_report);
    d = surface_distance(fan_triangles(quads), tree, measure.samples, measure.seed);
    rounds.push_back({uint32_t(std::count(marks.begin(), marks.end(), 1)),
                      {quads.quads.size(), d.max / diagonal, untangle_report.nonpositive}});
    if (double(quads.quads.size()) > most) break;
    lattice = std::move(done->first);
    placed = std::move(done->second);
    spared.resize(lattice.points.size(), 0);
    // Fewer folded quads win; with as many, a nearer round, and over the first only one that
    // reaches the target or, with a count asked for, is nearer than kRefineGain of it. A round
    // that reaches the target with no fold ends the rounds.
    const uint32_t folded = untangle_report.nonpositive;
    const bool reached = d.max <= target;
    const bool gain = o.quads > 0 && d.max / diagonal <= kRefineGain * first.distance;
    const bool better =
        best ? folded < best->folded || (folded == best->folded && d.max < best->distance)
             : folded < first.folded || (folded == first.folded && (reached || gain));
    if (better) {
      best = Kept{uint32_t(rounds.size() - 1),
                  d.max,
                  folded,
                  quads,
                  extract_report,
                  untangle_report,
                  snap_report};
      if (run.subdivisions > 0)
        for (SurfacePoint& p : best->quads.surface) p = to_component(run.surface, p);
      if (reached && folded == 0) break;
    }
    folds = folded_centres(quads, untangle_report);
    latest = std::move(quads);
  }
  if (best) {
    run.refine_round_kept = best->round;
    run.quads = std::move(best->quads);
    run.extract_report = std::move(best->extract);
    run.untangle_report = std::move(best->untangle);
    run.snap_report = best->snap;
  }
  run.extract_seconds = seconds_before + seconds_since(t0);
  run.measured = rounds[run.refine_round_kept].result;
  run.refine_rounds = std::move(rounds);
}

// The component at the size `o` asks for, with the patch count it asks for (or VSA's).
ComponentRun run_sized_once(const PreparedMesh& prep, uint32_t c, const PipelineOptions& o) {
  const PreparedComponent& comp = prep.components.at(c);
  const ComponentSize size = component_size(prep, c, {o.edge_length, o.quads});
  ComponentRun run;
  run.component = c;
  run.area_share = size.area_share;
  const double h = size.edge_length;
  const double diagonal = mesh_diagonal(prep);
  // A big patch with a long protrusion crowds its tip exponentially in any harmonic map; on a
  // finer surface the crowded triangles get too small to certify (E553), and few patches on a
  // fine surface may not be cut into disks (E201). Refined corners can ask such a patch for a
  // rectangle it fills even worse (knot1 with 8 patches), so the corner ILP's own choice is
  // tried first; then one level coarser, down to the component itself.
  uint32_t max_levels = 64;
  PipelineOptions stages = o;
  for (;;) {
    const auto t0 = Clock::now();
    run.surface = subdivide_coarse(comp.mesh, comp.feature, h, o.triangles_per_quad,
                                   run.surface_feature, run.subdivisions, max_levels);
    run.surface_tree.reset();
    run.segment_seconds += seconds_since(t0);
    try {
      run_stages(h, stages, {}, nullptr, diagonal, run);
      split_tips(h, stages, diagonal, run);
      refine_far(stages, diagonal, run);
      // The promise is a valid output: traced quads that the untangler left folded (against
      // their own normal or the surface's) or with a straight corner are not kept while VSA's
      // patches may map this component without them.
      const uint32_t invalid = run.field_used ? invalid_quads(run.quads) : 0;
      const uint32_t folded = run.field_used ? run.untangle_report.nonpositive : 0;
      if (invalid > 0 || folded > 0) {
        run.field_log.failure = fmt::format(
            "of the traced layout's {} quads, {} have scaled Jacobian <= {} against their own "
            "normal and {} are folded against the surface",
            run.quads.quads.size(), invalid, kMinValidScaledJacobian, folded);
        stages.field_layout = false;
        continue;
      }
      return run;
    } catch (const Error& e) {
      // A traced layout that a later stage cannot use: this component takes VSA's patches.
      if (run.field_used && e.kind() != ErrorKind::internal) {
        run.field_log.failure = fmt::format("a stage after the traced layout failed: {}", e.what());
        stages.field_layout = false;
        continue;
      }
      if (e.code() == "E553" && stages.layout.improve_corners) {
        stages.layout.improve_corners = false;
        run.corners_unrefined = true;
        continue;
      }
      if ((e.code() != "E553" && e.code() != "E201") || run.subdivisions == 0) throw;
      max_levels = run.subdivisions - 1;
      ++run.subdivision_retreats;
    }
  }
}

// The component at the size `o` asks for; with PipelineOptions::patch_rounds, again with more
// patches while it is farther than the distance target.
ComponentRun run_sized(const PreparedMesh& prep, uint32_t c, const PipelineOptions& o) {
  ComponentRun run = run_sized_once(prep, c, o);
  if (!o.patch_rounds || run.field_used || o.patches > 0 || o.last != Stage::extract ||
      run.quads.quads.empty())
    return run;
  const double diagonal = mesh_diagonal(prep);
  const double target = o.tolerance > 0 ? o.tolerance : kTipTarget;
  auto result_of = [&](ComponentRun& r) {
    if (!r.measured) r.measured = measure_run(r, surface_tree(r), diagonal);
    return *r.measured;
  };
  const SizeRound first = result_of(run);
  if (first.distance <= target) return run;
  const uint32_t automatic = run.seg.vsa_patches;
  const bool counted = o.quads > 0;
  const double most = kCountSlack * o.quads * run.area_share;
  std::vector<ComponentRun::PatchRound> rounds{{automatic, first}};
  FieldLayoutLog traced = run.field_log;
  uint32_t kept = 0;
  UnkeptSeconds unkept;
  for (const double growth : kPatchGrowth) {
    PipelineOptions more = o;
    more.patches = uint32_t(std::ceil(growth * automatic));
    more.field_layout = false;  // this component's traced patches were not used
    std::optional<ComponentRun> again;
    try {
      again = run_sized_once(prep, c, more);
    } catch (const Error&) {
      continue;  // the runs before stand
    }
    const SizeRound r = result_of(*again);
    rounds.push_back({again->seg.vsa_patches, r});
    const SizeRound& best = rounds[kept].result;
    const bool reached = r.distance <= target;
    // Fewer folded quads win whatever the distance: a fold makes the output invalid, a distance
    // does not.
    const bool keep = (!counted || double(r.quads) <= most) &&
                      (r.folded < best.folded ||
                       (r.folded == best.folded &&
                        (reached || (counted && r.distance <= kRefineGain * best.distance))));
    const ComponentRun& loser = keep ? run : *again;
    unkept.add(loser);
    if (keep) {
      run = std::move(*again);
      kept = uint32_t(rounds.size() - 1);
      if (reached) break;
    } else if (counted) {
      // Within a count, a round that brings no clear gain ends the rounds: the next, with more
      // patches again, costs more (bunny00 at 800 quads: 1.50% -> 1.33% with 75 patches, then
      // 2.14% with 95 in another 9 s).
      break;
    }
  }
  unkept.charge(run);
  run.patch_rounds = std::move(rounds);
  run.patch_round_kept = kept;
  run.field_log = std::move(traced);  // why this component's traced patches were not used
  return run;
}

// The last pass of a component, on the quads every pass before kept: `o.smooth` sweeps of
// tangential smoothing on the component's surface (extract/smooth.hpp), guarded so that no quad
// ends below min(its scaled Jacobian before, 0.2), against its own normal or the surface's, and
// no distance between the quads and the surface grows beyond max(before, 0.1 h); the corners
// the tip snapping moved stay on their tips. Last, so that it changes no decision of
// the passes before (which measure folds and distances on the quads as extracted).
void smooth_last(const PreparedMesh& prep, uint32_t c, const PipelineOptions& o,
                 ComponentRun& run) {
  if (o.smooth == 0 || o.last != Stage::extract || run.triangle_split || run.quads.quads.empty())
    return;
  const auto t0 = Clock::now();
  const TriMesh& mesh = prep.components.at(c).mesh;
  const AabbTree tree(face_triangles(mesh));
  SmoothOptions so;
  so.iterations = o.smooth;
  so.edge_length = run.layout.edge_length;
  smooth_quads(run.quads, mesh, run.seg.meta, so, run.smooth_report, &tree, run.snap_report.moved);
  run.extract_seconds += seconds_since(t0);
}

ComponentRun triangle_split_run(const PreparedMesh& prep, uint32_t c, const PipelineOptions& o,
                                std::string reason);

ComponentRun run_component_unsmoothed(const PreparedMesh& prep, uint32_t c,
                                      const PipelineOptions& o) {
  const TriMesh& mesh = prep.components.at(c).mesh;
  if (mesh.num_faces() < kTriangleSplitBelowFaces) return triangle_split_run(prep, c, o, "");
  ComponentRun run = run_sized(prep, c, o);
  if (o.edge_length > 0 || o.quads > 0 || o.tolerance <= 0 || o.tolerance_rounds == 0 ||
      o.last != Stage::extract || run.quads.quads.empty())
    return run;
  const double diagonal = mesh_diagonal(prep);
  const AabbTree surface(face_triangles(prep.components[c].mesh));
  auto round_of = [&](const ComponentRun& r) { return measure_run(r, surface, diagonal); };
  std::vector<SizeRound> rounds{round_of(run)};
  uint32_t kept = 0;
  const double first = double(rounds[0].quads);
  double quads = first;
  UnkeptSeconds unkept;
  for (uint32_t i = 0; i < o.tolerance_rounds && rounds.back().distance > o.tolerance; ++i) {
    // The farthest points are mostly where quads are too big for the shape (a patch's facing
    // sides made equal), not chords of a smooth curve, so the distance falls about with h:
    // h scaled by tolerance / distance, with a margin, at least 1.5 times the quads.
    const double ratio = rounds.back().distance / o.tolerance;
    const double next = std::min(quads * std::clamp(1.2 * ratio * ratio, 1.5, kToleranceMaxGrowth),
                                 kToleranceMaxGrowth * first);
    if (next < 1.25 * quads) break;
    quads = next;
    PipelineOptions finer = o;
    finer.quads = quads / run.area_share;  // sizing.hpp shares a count out by area
    std::optional<ComponentRun> candidate;
    try {
      candidate = run_sized(prep, c, finer);
    } catch (const Error&) {
      break;  // the coarser run stands
    }
    const SizeRound r = round_of(*candidate);
    rounds.push_back(r);
    const bool better = r.folded <= rounds[kept].folded && r.distance < rounds[kept].distance;
    const ComponentRun& loser = better ? run : *candidate;
    unkept.add(loser);
    if (better) {
      run = std::move(*candidate);
      kept = uint32_t(rounds.size() - 1);
    }
  }
  unkept.charge(run);
  run.size_rounds = std::move(rounds);
  run.size_round_kept = kept;
  return run;
}

}  // namespace

namespace {

// How the quads' topology differs from the component's (metrics/quality.hpp topology_change;
// empty: it does not).
std::string topology_change_of(const TriMesh& mesh, const QuadMesh& quads) {
  const Topology input{mesh.euler_characteristic(), mesh.num_components(),
                       uint32_t(mesh.boundary_loops().size())};
  return topology_change(input,
                         topology_of(as_poly(quads), nullptr, nullptr, nullptr, nullptr, nullptr));
}

// The component's triangles each split into three quads (split_triangles.hpp): valid on any
// edge-manifold, oriented component, of its topology, but with no layout and as many quads as
// the surface has corners, edges and faces.
ComponentRun triangle_split_run(const PreparedMesh& prep, uint32_t c, const PipelineOptions& o,
                                std::string reason) {
  const TriMesh& mesh = prep.components.at(c).mesh;
  ComponentRun small;
  small.component = c;
  small.area_share = component_size(prep, c, {o.edge_length, o.quads}).area_share;
  small.triangle_split = true;
  small.triangle_split_reason = std::move(reason);
  small.surface = identity_refinement(mesh);
  small.quads = split_triangles_into_quads(mesh);
  return small;
}

}  // namespace

ComponentRun run_component(const PreparedMesh& prep, uint32_t c, const PipelineOptions& o) {
  if (o.last != Stage::extract) return run_component_unsmoothed(prep, c, o);
  // A promise: every edge-manifold, oriented component gets valid quads of its topology. Where
  // the stages end in an error after every alternative they try, or in quads that are not valid
  // once smoothed, as they are output (another topology than the component's: a component given too
  // few quads for its patches, a hole narrower than a quad; a quad at scaled Jacobian <= 0.001
  // against its own normal, or folded against the surface), VSA's patches each split into
  // four-sided ones (the paper's section 5) are tried once, then the triangle split; each said as
  // such. Not for the stages' internal errors (bugs), an edge length the caller gave that is too
  // large for the component (E501 says which to give), nor where the triangle split is not valid
  // itself (zero-area triangles): then the stages' error or quads stand, whatever the alternatives
  // ended in.
  const TriMesh& mesh = prep.components.at(c).mesh;
  // Why r's quads are not valid (empty: they are); `quads` also checks each quad. Spared that:
  // four-sided patches the caller forced (PipelineOptions::quad_split: asking for the section 5
  // split itself, with its known quads at 180-degree crease corners) and quads from a run with
  // a repair switched off (the caller looks at what the others leave).
  const bool repairs_on = o.repairs_on();
  const auto defect = [&](const ComponentRun& r, bool quads) -> std::string {
    if (r.triangle_split) return "";
    if (!o.allow_topology_change)
      if (const std::string change = topology_change_of(mesh, r.quads); !change.empty())
        return fmt::format("the quads' topology was not the component's ({})", change);
    const uint32_t invalid = invalid_quads(r.quads), folded = r.untangle_report.nonpositive;
    if (quads && repairs_on && (invalid > 0 || folded > 0))
      return fmt::format(
          "{} of its {} quads with scaled Jacobian <= {} against their own normal, {} folded "
          "against the surface",
          invalid, r.quads.quads.size(), kMinValidScaledJacobian, folded);
    return "";
  };
  ComponentRun run;
  std::exception_ptr error;
  std::string failure;
  try {
    run = run_component_unsmoothed(prep, c, o);
    smooth_last(prep, c, o, run);
    failure = defect(run, !o.quad_split);
  } catch (const Error& e) {
    if (e.kind() == ErrorKind::internal || (e.code() == "E501" && o.edge_length > 0)) throw;
    error = std::current_exception();
    failure = e.what();
  }
  if (failure.empty()) return run;
  std::vector<std::string> failed{
      fmt::format("{}: {}", o.field_layout ? "the patches" : "VSA's patches", failure)};
  if (!o.quad_split) {
    PipelineOptions split = o;
    split.field_layout = false;
    split.quad_split = true;
    split.piecewise_disks = true;
    try {
      ComponentRun four_sided = run_component_unsmoothed(prep, c, split);
      smooth_last(prep, c, o, four_sided);
      const std::string defect_four = defect(four_sided, true);
      if (defect_four.empty()) {
        four_sided.four_sided_reason = failure;
        return four_sided;
      }
      failed.push_back("four-sided patches: " + defect_four);
    } catch (const Error& e) {
      // Even an internal error here (a bug of the section 5 split on this input) leaves the
      // error or the quads the stages ended in as the answer, not this alternative's.
      failed.push_back(fmt::format("four-sided patches: {}", e.what()));
    }
  }
  ComponentRun split = triangle_split_run(prep, c, o, failure);
  const uint32_t split_invalid = invalid_quads(split.quads);
  if (split_invalid == 0) return split;
  failed.push_back(fmt::format("the triangle split: {} of its {} quads with scaled Jacobian <= {}",
                               split_invalid, split.quads.quads.size(), kMinValidScaledJacobian));
  if (error) std::rethrow_exception(error);
  run.alternatives_failed = std::move(failed);
  return run;
}

std::vector<ComponentRun> run_pipeline(const PreparedMesh& prep, const PipelineOptions& o) {
  std::vector<ComponentRun> runs;
  for (uint32_t c = 0; c < prep.components.size(); ++c) runs.push_back(run_component(prep, c, o));
  return runs;
}

}  // namespace isoquad

namespace isoquad {

PolyMesh merge_quads(const PreparedMesh& prep, const std::vector<ComponentRun>& runs) {
  PolyMesh out;
  uint32_t patch_base = 0;
  for (const ComponentRun& run : runs) {
    const uint32_t base = uint32_t(out.positions.size());
    for (const Vec3& p : run.quads.positions) out.positions.push_back(prep.normalization.invert(p));
    for (std::size_t q = 0; q < run.quads.quads.size(); ++q) {
      const auto& v = run.quads.quads[q];
      out.add_face({base + v[0], base + v[1], base + v[2], base + v[3]});
      out.face_group.push_back(int32_t(patch_base + run.quads.quad_patch[q]));
    }
    patch_base +=
        run.triangle_split ? run.surface.mesh.num_faces() : uint32_t(run.layout.charts.size());
  }
  return out;
}

}  // namespace isoquad
