// isoquad remesh IN -o OUT: the whole method, from a triangle mesh to a pure quad mesh. A thin
// shell over the library's remesh (pipeline/remesh.hpp).
#include <fmt/format.h>

#include <chrono>
#include <iostream>
#include <optional>

#include "commands.hpp"
#include "io/read_mesh.hpp"
#include "io/write_mesh.hpp"
#include "pipeline/remesh.hpp"
#include "progress_bar.hpp"
#include "remesh_args.hpp"
#include "report/report.hpp"

namespace isoquad::cli {

void add_remesh_options(CLI::App& app, RemeshArgs& args) {
  CLI::App* sub = &app;
  RemeshArgs* a = &args;
  add_patch_options(*sub, a->patch);
  sub->add_option("--weights", a->weights, "smvc (symmetrized, SPD) or mvc (the paper's)")
      ->check(CLI::IsMember({"smvc", "mvc"}))
      ->capture_default_str();
  sub->add_option("--relax", a->relax, "Seam weights: adaptive, bisection (the paper's), locked")
      ->check(CLI::IsMember({"adaptive", "bisection", "locked"}))
      ->capture_default_str();
  sub->add_option("--segmentation", a->segmentation,
                  "Patches: vsa (the paper's planar regions) or field (cut along the streamlines "
                  "of a cross field, corners included; VSA where it fails)")
      ->check(CLI::IsMember({"vsa", "field"}))
      ->capture_default_str();
  sub->add_option("--corners", a->corners, "Corner choice: global or local (the paper's)")
      ->check(CLI::IsMember({"global", "local"}))
      ->capture_default_str();
  sub->add_flag("--improve-corners,!--no-improve-corners", a->improve_corners,
                "Refine the corners patch by patch against the relaxed length program (default; "
                "--no-improve-corners keeps the corner ILP's choice: faster, more stretched "
                "quads)");
  sub->add_option(
         "--smooth", a->smooth,
         "Tangential smoothing sweeps, the last pass, vertices kept on the input surface; a "
         "move is taken only if no quad around the vertex gets below a scaled Jacobian of "
         "min(its value, 0.2), against its own or the surface's normal, and no distance "
         "between the quads and the surface grows beyond max(its value, 0.1 h); 0: off")
      ->capture_default_str();
  sub->add_flag("--split-patches", a->split_patches,
                "Split every patch into four-sided ones before the layout (the paper's section 5 "
                "repair, which always admits a layout; done anyway when nothing else does): more "
                "singularities");
  sub->add_flag("--no-untangle", a->no_untangle,
                "Keep the lattice points where the map puts them, even where a quad folds "
                "against the surface (by default such quads' corners are moved along it)");
  sub->add_flag("--no-snap", a->no_snap,
                "Leave the quads' corners where extraction and untangling put them, even where "
                "the quads cut off a tip of the surface (by default nearby corners are moved "
                "onto such tips where that makes no quad worse than a scaled Jacobian of 0.2)");
  sub->add_flag("--no-tip-split", a->no_tip_split,
                "Run once, even where the quads are farther than 1% of the bounding-box "
                "diagonal (or --tolerance) from the surface (by default the surface vertices "
                "where they cut off a tip or bridge a valley become patch corners, the mesh is "
                "remeshed from the same patches, and the closer result with no more folded "
                "quads is kept; from a kept result, again with its tips added, up to three "
                "runs with tips, one new tip at a time after a run not kept; with --quads N, "
                "no run with more than 1.1 N quads is kept)");
  sub->add_flag("--no-refine", a->no_refine,
                "Keep the quads as the layout made them, even where they are still farther than "
                "1% of the bounding-box diagonal (or --tolerance) from the surface after the tip "
                "runs (by default the quads nearest to the far points are cut at thirds in the "
                "same map, again where still far, up to five times and to twice the quads, or "
                "1.1 times with --quads or --edge-length; kept only if that reaches the distance "
                "with no more folded quads: it adds irregular vertices where the finer quads end)");
  sub->add_flag("--no-patch-rounds", a->no_patch_rounds,
                "Keep the automatic patch count, even where the quads are still farther than 1% "
                "of the bounding-box diagonal (or --tolerance) after the tip runs and the "
                "refinement (by default, unless --patches is given, the component runs again "
                "with 1.5, then 2 times as many patches at the same size, and the first run "
                "that reaches the distance with no more folded quads is kept; with --quads N, "
                "also a run at least a quarter nearer than the one kept before, with no more "
                "folded quads and at most 1.1 N quads, and a run not kept ends the rounds; a run "
                "with fewer folded quads is kept whatever its distance)");
  sub->add_flag("--no-misfit-split", a->no_misfit_split,
                "Keep the patches as they are where quads still fold after every other repair "
                "(by default the patches whose rectangle cannot follow their shape, one side "
                "more than 3 times the facing one, are cut in two by VSA and the stages run "
                "again; kept only if fewer quads fold)");
  sub->add_option("--fold-rounds", a->fold_rounds,
                  "Where quads still fold after untangling, give their patches one more quad "
                  "across and solve the lengths, map and quads again, at most this often (a round "
                  "is kept only if fewer quads fold; 0: never). If quads still fold after those "
                  "rounds and the diagonal collapses, the corners are chosen once more, avoiding "
                  "patch corners at flat places (not with 0)")
      ->capture_default_str();
  sub->add_option("--tolerance", a->tolerance,
                  "At the default size (neither --quads nor --edge-length): where the quads are "
                  "farther than this fraction of the bounding-box diagonal from the input "
                  "(two-sided Hausdorff distance, as `isoquad quality` measures it), remesh with "
                  "more quads, at most --tolerance-rounds times and up to 4 times the first "
                  "count; the closest result with no more folded quads is kept. Each round is a "
                  "whole run (0: off, the default; refused with --quads or --edge-length)")
      ->check(number_in(0, 1, "a fraction in [0, 1]"))
      ->capture_default_str();
  sub->add_option("--tolerance-rounds", a->tolerance_rounds,
                  "How often at most --tolerance asks for more quads")
      ->check(CLI::Range(1u, 8u))
      ->capture_default_str();
  sub->add_flag("--allow-topology-change", a->allow_topology_change,
                "Keep quads whose topology (genus, boundary loops, connected pieces) differs "
                "from their input component's, with a warning (W113; by default that is an "
                "error, E603)");
  sub->add_flag("--allow-invalid", a->allow_invalid,
                "Where no alternative gives a component valid quads (scaled Jacobian above "
                "0.001 against their own normal), keep its best quads with a warning (W117; by "
                "default that is an error, E604)");
  sub->add_option("--threads", a->threads,
                  "Worker threads at most (0: one per core); the output is the same for any count")
      ->check(number_in(0, 1e6, "a thread count (0: one per core)"))
      ->capture_default_str();
  sub->add_option("--view", a->view,
                  "Viewing direction x y z for the report's pictures (default: the three-quarter "
                  "view that shows the most surface)")
      ->expected(3);
  sub->add_option("--report-width", a->report_width, "Width of each report picture in pixels")
      ->check(CLI::Range(200, 4000))
      ->capture_default_str();
  add_prep_options(*sub, a->prep);
  refuse_vsa_only_with_field(*sub, a->segmentation,
                             {"--patches", "--corners", "--split-patches", "--no-tip-split",
                              "--no-patch-rounds", "--no-misfit-split"});
}

RemeshOptions remesh_options(const RemeshArgs& a) {
  RemeshOptions o = a.prep.remesh_options();
  o.patches = a.patch.patches;
  o.edge_length = a.patch.edge_length;
  o.quads = a.patch.quads;
  o.seed = a.patch.seed;
  o.paper_weights = a.weights == "mvc";
  o.relax = a.relax;
  o.segmentation = a.segmentation;
  o.local_corners = a.corners == "local";
  o.smooth = a.smooth;
  o.untangle = !a.no_untangle;
  o.snap = !a.no_snap;
  o.fold_rounds = a.fold_rounds;
  o.split_patches = a.split_patches;
  o.tip_split = !a.no_tip_split;
  o.refine = !a.no_refine;
  o.patch_rounds = !a.no_patch_rounds;
  o.misfit_split = !a.no_misfit_split;
  o.tolerance = a.tolerance;
  o.tolerance_rounds = a.tolerance_rounds;
  o.improve_corners = a.improve_corners;
  o.threads = a.threads;
  o.allow_topology_change = a.allow_topology_change;
  o.allow_invalid = a.allow_invalid;
  return o;
}

std::string remesh_file(const RemeshArgs& a, const std::string& input, const std::string& output,
                        const std::string& report_dir, bool quality, const Say& say,
                        const ProgressCallback& advance) {
  const auto t0 = std::chrono::steady_clock::now();
  check_mesh_output(output);
  if (!report_dir.empty()) check_output_folder(report_dir);
  const ReadResult read = read_mesh(input, a.prep.read_options());
  say(fmt::format("read {}: {} vertices, {} faces", input, read.mesh.num_vertices(),
                  read.mesh.num_faces()));
  RemeshOptions o = remesh_options(a);
  o.quality = quality || !report_dir.empty();
  const RemeshRun run = remesh_run(read.mesh, o, read.unshared_vertices, say, advance);
  const PolyRemesh& r = run.result;
  write_mesh(output, r.quads);
  if (!report_dir.empty()) {
    ReportOptions ro;
    if (a.view.size() == 3) ro.view = Vec3{a.view[0], a.view[1], a.view[2]};
    ro.width = a.report_width;
    ro.title = input;
    const auto t1 = std::chrono::steady_clock::now();
    const ReportFiles files = write_report(report_dir, read.mesh, run, ro);
    say(fmt::format("wrote {} report files to {} ({:.2f} s)", files.names.size(), report_dir,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count()));
  }
  say(fmt::format("wrote {} quads to {} ({:.2f} s in all)", r.quads.num_faces(), output,
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()));
  return r.report;
}

Runner add_remesh(CLI::App& app) {
  auto a = std::make_shared<RemeshArgs>();
  CLI::App* sub = app.add_subcommand("remesh", "Remesh a triangle mesh into a pure quad mesh");
  sub->add_option("input", a->input, "Input mesh (OBJ, OFF, PLY, STL)")->required();
  sub->add_option("-o,--output", a->output, "Quad mesh (OBJ, OFF or PLY)")->required();
  add_remesh_options(*sub, *a);
  sub->add_option("--report", a->report_dir,
                  "Write pictures (Figures 1 and 3 of the paper), layout.svg, report.json and "
                  "index.html into this folder");
  sub->add_flag("--json", a->json, "Print the run and quality report as JSON");
  sub->add_flag("-q,--quiet", a->quiet,
                "No progress on stderr (by default a bar per stage on a terminal, else a line "
                "per stage and one every 10 s in a long stage)");
  return [a] {
    std::optional<RemeshProgress> shown;
    if (!a->quiet) shown.emplace(stderr_is_terminal());
    const std::string report = remesh_file(
        *a, a->input, a->output, a->report_dir, a->json,
        [&](const std::string& s) {
          if (shown) shown->say(s);
        },
        [&](const Progress& p) {
          if (shown) shown->advance(p);
        });
    if (shown) shown->finish();
    if (a->json) std::cout << report << '\n';
    return 0;
  };
}

}  // namespace isoquad::cli
