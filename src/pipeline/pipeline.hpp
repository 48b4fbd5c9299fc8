// The method's stages for one prepared mesh, component by component: segmentation, layout and
// parametrization (extraction follows). The command line and the library call share it, so both
// size components the same way (a requested quad count is shared out by area).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "core/poly_mesh.hpp"
#include "extract/extract.hpp"
#include "extract/smooth.hpp"
#include "extract/snap.hpp"
#include "extract/untangle.hpp"
#include "field/field_segment.hpp"
#include "layout/layout.hpp"
#include "param/param.hpp"
#include "prep/prepare.hpp"
#include "seg/quad_split.hpp"
#include "seg/segment.hpp"

namespace isoquad {

enum class Stage { segment, layout, param, extract };

struct PipelineOptions {
  // Patches from the cross field's traced separatrices (field/field_segment.hpp) instead of VSA;
  // a component whose field layout fails falls back to VSA.
  bool field_layout = false;
  uint32_t patches = 0;    // K; 0: automatic
  double edge_length = 0;  // target quad edge length in input units; 0: from quads
  double quads = 0;        // target quad count for the whole mesh; 0: the default
  uint64_t seed = 1;
  LayoutOptions layout;  // corners and length solver (size fields are set per component)
  ParamOptions param;
  uint32_t smooth = 3;   // tangential smoothing sweeps, the component's last pass (0: off)
  bool untangle = true;  // repair quads folded against the surface (extract/untangle.hpp)
  bool snap = true;      // move quad corners onto tips the quads cut off (extract/snap.hpp)
  // Rounds of more quads across the patches whose quads are still folded after untangling
  // (layout/layout.hpp thicken_patches); a round is kept only if fewer quads fold.
  uint32_t fold_rounds = 2;
  // If quads still fold after those rounds and the collapses, the corners are chosen again, with
  // this as LayoutOptions::flat_crease_corner_penalty (where the mesh has creases), then as
  // LayoutOptions::flat_corner_penalty, while quads fold (0: never; nor with fold_rounds 0,
  // which solves nothing again).
  double corner_retry_penalty = 2;
  // Split every patch into four-sided ones before the layout (seg/quad_split.hpp). Otherwise
  // this happens only when no corner choice or meta-vertex insertion makes the layout feasible.
  bool quad_split = false;
  // Midpoint subdivisions of a coarse component until it has this many triangles per target
  // quad (0: never; 8 is also the default size's density, so default runs subdivide only small
  // inputs). The map is linear on each triangle, so on a coarse input every quad straddling two
  // big triangles bends with the map's kink between them; finer triangles let the harmonic map
  // be smooth. The geometry does not change.
  double triangles_per_quad = 8;
  // At the default size (neither `quads` nor `edge_length` given): a component whose quads are
  // farther than this fraction of the mesh's bounding-box diagonal from its surface (two-sided,
  // sampled as `isoquad quality` does) is remeshed with more quads, at most `tolerance_rounds`
  // times and up to kToleranceMaxGrowth times its first count; the closest run with no more
  // folded quads is kept. 0: off (the default: each round is a whole run, and finer runs
  // need more fold repairs).
  double tolerance = 0;
  uint32_t tolerance_rounds = 2;
  // Where the quads are farther than the distance target (`tolerance`, or kTipTarget of the
  // diagonal) from the surface, every point farther than kTipFar h (a tip they cut off, a valley
  // they bridge) becomes a meta-vertex (seg/tip_split.hpp), hence a lattice point, and the
  // component runs again from the same VSA partition; the run with the smaller two-sided
  // distance and no more folded quads is kept. A kept run is searched for tips again, with the
  // earlier ones kept, at most kTipRounds runs with tips; a run not kept is searched in turn,
  // except one that added several tips to the kept run: then tips are added to the kept run one
  // at a time.
  bool tip_split = true;
  // Where the quads (after the tip rounds) still fold or are farther than the distance target,
  // the lattice quads there are cut at thirds in the same map, again where still so, within the
  // count; kept with fewer folds, or as many and a distance within the target or clearly nearer
  // (pipeline.cpp refine_far).
  bool refine = true;
  // Unless a patch count is asked for: where the quads (after the tip rounds and the
  // refinement) are still farther than the distance target, the component runs again with
  // kPatchGrowth[i] times the automatic patch count, at the same size. A run is kept over the
  // one kept before with no more folded quads where it reaches the target (which ends the
  // rounds) or, with a quad count asked for, within kCountSlack of it and nearer than
  // kRefineGain of the kept distance (a round not kept then ends the rounds); and, within the
  // count, wherever it folds fewer quads, whatever its distance. Patches too big for
  // the detail they hold make the harmonic map crowd it into a few stretched quads, which neither
  // tips nor refinement undo (the cow's head at the default size and at 1,500 quads).
  bool patch_rounds = true;
  // Where quads still fold after the fold rounds, the collapses and the corner tries, the
  // patches no rectangle fits (layout/layout.hpp misfit_patches) have their VSA regions cut in
  // two (seg/vsa.hpp split_vsa_regions) and the stages run again from the segmentation; kept if
  // fewer quads fold.
  bool misfit_split = true;
  // Quads of another topology than the component's are kept (RemeshOptions::
  // allow_topology_change), not replaced by the triangle split of run_component.
  bool allow_topology_change = false;
  // SegmentOptions::piecewise_disks: run_component's four-sided alternative cuts VSA's patches
  // into disks however small the handle or hole that keeps one from being a disk.
  bool piecewise_disks = false;
  Stage last = Stage::extract;
  // Called as each stage begins, with its name in pipeline/progress.hpp kComponentStages, on the
  // thread that called run_component (never inside a parallel region), for a progress bar: the
  // stages compute nothing from it.
  std::function<void(const char* stage)> stage_begins;

  // Every repair pass on and the patches not forced four-sided: run_component then tries its
  // alternatives where quads are not valid. Otherwise the caller looks at what the passes leave.
  bool repairs_on() const {
    return untangle && fold_rounds > 0 && refine && patch_rounds && misfit_split && tip_split &&
           !quad_split;
  }
};

constexpr double kToleranceMaxGrowth = 4;
// Tips are farther than kTipFar h from the other side, and kTipSpacing h from one another; they
// are split when the farthest is beyond kTipTarget of the bounding-box diagonal (the distance
// the default size aims at) or the tolerance asked for.
constexpr double kTipFar = 0.3, kTipSpacing = 3, kTipTarget = 0.01;
// A second and third round of tips, each from the run the round before kept: the armadillo at
// 1,500 quads went 3.81% -> 2.89% -> 1.80% -> 1.37% of the diagonal, mech-holes-shark at the
// default size 2.52% -> 1.45% -> 1.19% (its third round, 4.27% and a fold, undone).
constexpr uint32_t kTipRounds = 3;
// Local refinement (PipelineOptions::refine): at most kRefineRounds rounds, while the quads are
// at most kRefineGrowth times as many as before (kRefineGrowthSized times the count asked for,
// or as many as before with an edge length asked for); a round that folds quads is tried again
// without the marks near them, up to kRefineAttempts tries. Rounds must stay below
// LatticeQuads::kMaxLevel.
constexpr uint32_t kRefineRounds = 5, kRefineAttempts = 2;
constexpr double kRefineGrowthSized = 1.1, kRefineGrowth = 2;
// With a count asked for (--quads), a refinement that does not reach the target, with as many
// folded quads as before, is kept where it is at least this much nearer (the distance times
// kRefineGain or less): each round adds irregular vertices where the finer quads end, worth it
// only for a clear gain, and only within the count. Without a count the rounds may double the
// quads, and the patch rounds follow: the elephant at the default size, with OpenBLAS's SkylakeX
// kernels, kept 2.20% -> 1.61% with 1,840 -> 2,148 quads and 255 irregular vertices, and its
// patch rounds then reached 1.01% only (the cow at the default size once went 2.32% -> 2.15%
// with 56 -> 369 irregular vertices).
constexpr double kRefineGain = 0.75;
// With a count asked for, a round cuts near the points at least this fraction as far as the
// farthest (and beyond the target), so that the count is spent where the quads are farthest,
// round after round: the cow at 1,500 quads, its 52 quads left to the count, went 3.36% ->
// 2.59% in one round with every point beyond the target marked, 2.03% in four with these.
// Without a count (twice the quads allowed) every point beyond the target is cut at once, which
// reaches it in fewer rounds: the elephant at the default size, with OpenBLAS's SkylakeX
// kernels, came to 0.90% that way in its patch round of 112 patches and to 1.50% this way.
constexpr double kRefineFocus = 0.75;
// A quad count asked for (--quads) is met within this factor where the layout allows: a tip
// run past it is not kept (the hand at 800 quads went 820 -> 1,185 quads with nine tips, 3.07%
// -> 1.51%), nor a refinement round (kRefineGrowthSized).
constexpr double kCountSlack = kRefineGrowthSized;
static_assert(kRefineRounds < LatticeQuads::kMaxLevel);

// The patch counts tried by PipelineOptions::patch_rounds, as multiples of the automatic count.
// Asked for by hand at the default size, more patches brought the elephant within 1% from
// --patches 96 (64 automatic), mech-holes-shark from 32 (16) and the cow from 120 (59; its
// rounds at 1.5 and 2 times fold a quad). Each round is a whole run.
constexpr double kPatchGrowth[] = {1.5, 2};

// One size tried for a component: its quads, their two-sided distance to the component over
// the mesh's bounding-box diagonal, and how many quads were left folded.
struct SizeRound {
  uint64_t quads = 0;
  double distance = 0;
  uint32_t folded = 0;  // UntangleReport::nonpositive
};

struct ComponentRun {
  uint32_t component = 0;  // index into PreparedMesh::components
  double area_share = 1;   // ComponentSize::area_share (sizing.hpp)
  // Too small for patches (sizing.hpp kTriangleSplitBelowFaces): the quads are its triangles split
  // in three, patch per triangle, and the stages' results are empty.
  bool triangle_split = false;
  // Why a component with enough faces for patches was split that way instead (empty: it was
  // not): every stage's alternatives failed with an error, or the quads had another topology
  // than the component's. The last resort of run_component, said as a warning.
  std::string triangle_split_reason;
  // Why VSA's patches were split into four-sided ones (PipelineOptions::quad_split) though not
  // asked for: the error every other alternative of the stages ended in (run_component).
  std::string four_sided_reason;
  // Where no alternative gave valid quads: what each one ended in, in the order tried
  // (run_component; remesh names them in its error E604 or warning W117).
  std::vector<std::string> alternatives_failed;
  // The surface the stages work on: the prepared component, subdivided `subdivisions` times,
  // with provenance in the component; its feature edges are the children of feature edges.
  RefinedMesh surface;
  EdgeData<char> surface_feature;
  uint32_t subdivisions = 0;
  // The surface's elimination order (param/ordering.hpp) for large surfaces, and a tree of its
  // faces (snapping, tip search), each computed once.
  std::vector<uint32_t> surface_ranks;
  std::shared_ptr<const AabbTree> surface_tree;
  uint32_t subdivision_retreats = 0;  // levels given up because the finer map did not certify
  bool corners_unrefined = false;     // the refined corners' map did not certify: the ILP's used
  uint32_t fold_rounds = 0, fold_rounds_kept = 0;  // thickening rounds tried and kept
  // Corners chosen again for folds: how many tries, and which was kept (1-based; 0: none).
  uint32_t corner_tries = 0, corner_try_kept = 0;
  // Misfit patches split for folds (the last fold repair in the stages): how many VSA regions
  // were cut in two (0: no such try), the quads folded (scaled Jacobian <= 0 against the
  // surface) before and with the try (before again if it failed), and whether it was kept.
  struct MisfitSplit {
    uint32_t regions = 0;
    uint32_t folded_before = 0, folded_after = 0;
    bool kept = false;
  };
  MisfitSplit misfit_split;
  // The sizes tried for PipelineOptions::tolerance (empty when it was not used), and which one
  // was kept.
  std::vector<SizeRound> size_rounds;
  uint32_t size_round_kept = 0;
  // PipelineOptions::tip_split: the runs tried (empty when no tip was searched for: the first
  // run was close enough), the first without tips and each next with more, with their tip
  // counts, two-sided distances (over the mesh's bounding-box diagonal) and folds, and which
  // run is the one here. `tips` (vertices of `surface`) are the kept run's (empty for the first).
  struct TipRound {
    uint32_t tips = 0;
    SizeRound result;
  };
  std::vector<TipRound> tip_rounds;
  uint32_t tip_round_kept = 0;
  std::vector<uint32_t> tips;
  // PipelineOptions::refine: the quads before (marked 0) and after each round of local
  // refinement, with the points marked, and which is the one here (0: the quads before; empty:
  // no round, the quads were close enough).
  struct RefineRound {
    uint32_t marked = 0;
    SizeRound result;
  };
  std::vector<RefineRound> refine_rounds;
  uint32_t refine_round_kept = 0;
  // PipelineOptions::patch_rounds: the VSA patch counts tried, the automatic one first, with
  // their results, and which run is the one here (empty: the first run was close enough).
  struct PatchRound {
    uint32_t patches = 0;
    SizeRound result;
  };
  std::vector<PatchRound> patch_rounds;
  uint32_t patch_round_kept = 0;
  // The kept quads' distance and folds, where refine_far or the patch rounds measured them.
  std::optional<SizeRound> measured;
  SegmentResult seg;
  // The field-aligned layout: whether `seg` is it (false: VSA, asked for or fallen back to), its
  // patches' corners, and what it found or why it failed.
  bool field_used = false;
  std::vector<std::array<uint32_t, 4>> field_corners;
  std::vector<char> field_preferred;     // FieldSegmentation::preferred
  std::vector<int> field_quarter_turns;  // FieldSegmentation::quarter_turns
  FieldLayoutLog field_log;
  std::optional<QuadSplitReport> quad_split;  // when the patches were split into quads
  Layout layout;
  LayoutReport layout_report;
  Param param;
  ParamReport param_report;
  QuadMesh quads;
  ExtractReport extract_report;
  SmoothReport smooth_report;
  UntangleReport untangle_report;
  SnapReport snap_report;
  double segment_seconds = 0, layout_seconds = 0, param_seconds = 0, extract_seconds = 0;
};

// Runs the stages up to options.last on component `c` of `prep`.
ComponentRun run_component(const PreparedMesh& prep, uint32_t c, const PipelineOptions& options);

// Midpoint (1-to-4) subdivisions of `mesh` while it has fewer than triangles_per_quad
// triangles per quad of edge h (area / h^2 quads), at most max_levels of them and while under
// 250,000 faces after the level; features are inherited by both halves.
RefinedMesh subdivide_coarse(const TriMesh& mesh, const EdgeData<char>& feature, double h,
                             double triangles_per_quad, EdgeData<char>& out_feature,
                             uint32_t& levels, uint32_t max_levels = 64);

// Every component, in order.
std::vector<ComponentRun> run_pipeline(const PreparedMesh& prep, const PipelineOptions& options);

// The components' quads as one mesh in input coordinates; face_group is the patch id, numbered
// across components (a triangle-split component has one patch per triangle).
PolyMesh merge_quads(const PreparedMesh& prep, const std::vector<ComponentRun>& runs);

}  // namespace isoquad
