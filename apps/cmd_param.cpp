// isoquad param MESH -o param.obj: the seamless map (paper §3.2, §3.4), certified injective.
#include <fmt/format.h>

#include <algorithm>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "io/read_mesh.hpp"
#include "io/write_mesh.hpp"
#include "pipeline/pipeline.hpp"
#include "prep/prepare.hpp"
#include "prep_options.hpp"
#include "viz/layout_svg.hpp"

namespace isoquad::cli {

namespace {

struct ParamArgs {
  std::string mesh, output, svg, weights = "smvc", relax = "adaptive", corners = "global",
                                 segmentation = "vsa";
  PatchArgs patch;
  bool json = false;
  PrepArgs prep;
};

// OBJ with one `vt` per face corner: chart coordinates divided by the chart's longer side, so
// every chart fills the unit square; one group per patch.
void write_param_obj(const std::filesystem::path& path, const PreparedMesh& prep,
                     const std::vector<ComponentRun>& runs) {
  write_file_atomically(path, [&](std::ostream& out) {
    out << "# isoquad param: per-corner vt in chart coordinates / max(W, H) of the chart\n";
    uint64_t vbase = 1, tbase = 1;
    for (const ComponentRun& run : runs) {
      const TriMesh& mesh = run.seg.refined.mesh;
      for (const Vec3& p : mesh.positions()) {
        const Vec3 q = prep.normalization.invert(p);
        out << fmt::format("v {} {} {}\n", q.x, q.y, q.z);
      }
      for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
        const Chart& ch = run.layout.charts[run.seg.labels[f]];
        const double s = 1.0 / double(std::max<int64_t>({ch.width, ch.height, 1}));
        for (const UV& uv : run.param.map.uv[f])
          out << fmt::format("vt {} {}\n", s * uv[0], s * uv[1]);
      }
      for (uint32_t p = 0; p < run.seg.num_patches; ++p) {
        out << fmt::format("g component_{}_patch_{}\n", run.component, p);
        for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
          if (run.seg.labels[f] != p) continue;
          out << 'f';
          for (int c = 0; c < 3; ++c)
            out << ' ' << vbase + mesh.face(f)[c] << '/' << tbase + 3 * uint64_t(f) + c;
          out << '\n';
        }
      }
      vbase += mesh.num_vertices();
      tbase += 3 * uint64_t(mesh.num_faces());
    }
  });
}

}  // namespace

Runner add_param(CLI::App& app) {
  auto a = std::make_shared<ParamArgs>();
  CLI::App* sub = app.add_subcommand(
      "param", "Compute the seamless integer-grid map and certify that it is injective");
  sub->add_option("mesh", a->mesh, "Input mesh")->required();
  sub->add_option("-o,--output", a->output, "OBJ with per-corner texture coordinates");
  sub->add_option("--svg", a->svg,
                  "SVG of every patch's rectangle with its mapped triangles (flips in red)");
  add_patch_options(*sub, a->patch);
  sub->add_option("--segmentation", a->segmentation,
                  "vsa (the paper's planar regions) or field (along a cross field's streamlines, "
                  "corners included; VSA where it fails)")
      ->check(CLI::IsMember({"vsa", "field"}))
      ->capture_default_str();
  sub->add_option("--weights", a->weights,
                  "smvc: symmetrized mean value weights (SPD, CHOLMOD); mvc: the paper's mean "
                  "value weights (UMFPACK)")
      ->check(CLI::IsMember({"smvc", "mvc"}))
      ->capture_default_str();
  sub->add_option("--relax", a->relax,
                  "Seam weights: adaptive (stiffen near flips only), bisection (the paper's "
                  "global bisection), locked (straight seams), none (weights 1, may flip)")
      ->check(CLI::IsMember({"adaptive", "bisection", "locked", "none"}))
      ->capture_default_str();
  sub->add_option("--corners", a->corners, "Corner choice: global or local")
      ->check(CLI::IsMember({"global", "local"}))
      ->capture_default_str();
  sub->add_flag("--json", a->json, "Print the report as JSON");
  add_prep_options(*sub, a->prep);
  refuse_vsa_only_with_field(*sub, a->segmentation, {"--patches", "--corners"});
  return [a] {
    if (!a->output.empty()) check_output_path(a->output);
    if (!a->svg.empty()) check_output_path(a->svg);
    const ReadResult read = read_mesh(a->mesh, a->prep.read_options());
    const PreparedMesh prep = prepare(read.mesh, a->prep.prep_options(read));
    PipelineOptions o;
    o.last = Stage::param;
    o.patches = a->patch.patches;
    o.edge_length = a->patch.edge_length;
    o.quads = a->patch.quads;
    o.seed = a->patch.seed;
    o.field_layout = a->segmentation == "field";
    o.layout.corners = a->corners == "local" ? CornerMode::local : CornerMode::global;
    o.param.weights = a->weights == "mvc" ? WeightKind::mvc : WeightKind::smvc;
    o.param.relax = a->relax == "bisection" ? RelaxMode::bisection
                    : a->relax == "locked"  ? RelaxMode::locked
                    : a->relax == "none"    ? RelaxMode::none
                                            : RelaxMode::adaptive;
    const std::vector<ComponentRun> runs = run_pipeline(prep, o);
    nlohmann::json out = nlohmann::json::array();
    for (const ComponentRun& run : runs) {
      const ParamReport& r = run.param_report;
      const Certificate& cert = run.param.certificate;
      nlohmann::json j = {{"component", prep.components[run.component].report_index},
                          {"layout_source", run.field_used ? "field" : "vsa"},
                          {"patches", run.seg.num_patches},
                          {"quads", run.layout.quads()},
                          {"weights", r.weights},
                          {"relax", r.relax},
                          {"unknowns", r.unknowns},
                          {"symbolic_factorizations", r.symbolic},
                          {"numeric_factorizations", r.factorizations},
                          {"solves", r.solves},
                          {"iterations", r.iterations},
                          {"flipped_unstiffened", r.flipped_unstiffened},
                          {"flipped_first_solve", r.flipped_first},
                          {"flipped_final", r.flipped_final},
                          {"bad_per_solve", r.bad_per_solve},
                          {"bad_angle_sums", cert.bad_angle_sums},
                          {"certified", cert.ok()},
                          {"fell_back_to_locked", r.fell_back_to_locked},
                          {"locked_meta_edges", r.locked_meta_edges},
                          {"meta_edges", r.meta_edges},
                          {"stiffened_edges", r.stiffened_edges},
                          {"max_residual", r.max_residual},
                          {"seam_angle_distortion", r.seam_angle_distortion},
                          {"seconds",
                           {{"segment", run.segment_seconds},
                            {"layout", run.layout_seconds},
                            {"param", r.total_seconds},
                            {"param_setup", r.setup_seconds},
                            {"analyze", r.analyze_seconds},
                            {"assemble", r.assemble_seconds},
                            {"factorize", r.factorize_seconds},
                            {"solve", r.solve_seconds},
                            {"certify", r.certify_seconds}}}};
      if (!a->json)
        fmt::print(
            "component {}: {} patches, {} quads; {} / {}: {} unknowns, {} factorization{}, "
            "{} solves; flipped in the first solve: {}, final: {}{}; {} of {} meta-edges locked, "
            "{} seam edges stiffened; {} ({:.0f} ms; segment {:.0f} ms, layout {:.0f} ms)\n",
            j["component"].get<int>(), run.seg.num_patches, run.layout.quads(), r.weights, r.relax,
            r.unknowns, r.factorizations, r.factorizations == 1 ? "" : "s", r.solves,
            r.flipped_first, r.flipped_final,
            r.fell_back_to_locked ? " (fell back to the locked map)" : "", r.locked_meta_edges,
            r.meta_edges, r.stiffened_edges, cert.ok() ? "certified injective" : "NOT injective",
            1e3 * r.total_seconds, 1e3 * run.segment_seconds, 1e3 * run.layout_seconds);
      out.push_back(std::move(j));
    }
    if (!a->output.empty()) write_param_obj(a->output, prep, runs);
    if (!a->svg.empty() && !runs.empty()) {  // the first component
      const ComponentRun& run = runs.front();
      write_layout_svg(a->svg, run.seg.refined.mesh, run.seg.labels, run.layout, run.param.map,
                       run.param.certificate.bad_faces);
    }
    if (a->json) std::cout << out.dump(2) << '\n';
    for (const ComponentRun& run : runs)
      if (!run.param.certificate.ok()) return 6;
    return 0;
  };
}

}  // namespace isoquad::cli
