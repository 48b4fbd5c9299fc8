// isoquad layout MESH: corners, integer lengths and transitions (paper §3.3, §5).
#include <fmt/format.h>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "field/field_segment.hpp"
#include "io/read_mesh.hpp"
#include "layout/layout.hpp"
#include "pipeline/pipeline.hpp"
#include "pipeline/sizing.hpp"
#include "prep/prepare.hpp"
#include "prep_options.hpp"
#include "seg/segment.hpp"

namespace isoquad::cli {

namespace {
struct LayoutArgs {
  std::string mesh, corners = "global", ilp = "cbc", segmentation = "vsa";
  PatchArgs patch;
  bool json = false, improve_corners = true;
  PrepArgs prep;
};
}  // namespace

Runner add_layout(CLI::App& app) {
  auto a = std::make_shared<LayoutArgs>();
  CLI::App* sub = app.add_subcommand(
      "layout", "Lay every patch out as an integer rectangle and print the layout");
  sub->add_option("mesh", a->mesh, "Input mesh")->required();
  add_patch_options(*sub, a->patch);
  sub->add_option("--segmentation", a->segmentation,
                  "vsa (the paper's planar regions) or field (along a cross field's streamlines, "
                  "corners included; VSA where it fails)")
      ->check(CLI::IsMember({"vsa", "field"}))
      ->capture_default_str();
  sub->add_option("--corners", a->corners,
                  "global: one ILP over all patches; local: the paper's per-patch choice")
      ->check(CLI::IsMember({"global", "local"}))
      ->capture_default_str();
  sub->add_option("--ilp", a->ilp,
                  "Integer lengths: cbc, or flow (LEMON network simplex when the system is a "
                  "network matrix, CBC otherwise)")
      ->check(CLI::IsMember({"cbc", "flow"}))
      ->capture_default_str();
  sub->add_flag("--improve-corners,!--no-improve-corners", a->improve_corners,
                "Refine the corners patch by patch against the relaxed length program (default; "
                "--no-improve-corners keeps the corner ILP's choice)");
  sub->add_flag("--json", a->json, "Print the full layout as JSON");
  add_prep_options(*sub, a->prep);
  refuse_vsa_only_with_field(*sub, a->segmentation, {"--patches", "--corners"});
  return [a] {
    const ReadResult read = read_mesh(a->mesh, a->prep.read_options());
    const PreparedMesh prep = prepare(read.mesh, a->prep.prep_options(read));
    nlohmann::json out = nlohmann::json::array();
    for (uint32_t ci = 0; ci < prep.components.size(); ++ci) {
      const PreparedComponent& c = prep.components[ci];
      const ComponentSize size = component_size(prep, ci, {a->patch.edge_length, a->patch.quads});
      const SegmentOptions so = segment_options(a->patch, prep, ci);
      const double h = so.vsa.target_edge_length;
      // The surface the pipeline works on (coarse components subdivided, pipeline.hpp).
      EdgeData<char> feature;
      uint32_t subdivisions = 0;
      const RefinedMesh surface =
          subdivide_coarse(c.mesh, c.feature, so.vsa.target_edge_length,
                           PipelineOptions{}.triangles_per_quad, feature, subdivisions);
      FieldLayoutLog field_log;
      FieldSegmentation fs;
      if (a->segmentation == "field") {
        fs = field_segment(surface.mesh, feature, h, field_log);
        if (!field_log.failure.empty())
          fmt::print(stderr, "isoquad: component {}: the field layout failed, VSA instead: {}\n",
                     c.report_index, field_log.failure);
      }
      const bool field = a->segmentation == "field" && field_log.failure.empty();
      SegmentResult seg = field ? std::move(fs.seg) : segment(surface.mesh, feature, so);
      LayoutOptions lo;
      if (field) {
        lo.given_corners = &fs.corners;
        lo.preferred_corners = &fs.preferred;
        lo.field_quarter_turns = &fs.quarter_turns;
      }
      lo.corners = a->corners == "local" ? CornerMode::local : CornerMode::global;
      lo.length_solver = a->ilp == "flow" ? LengthSolver::flow : LengthSolver::cbc;
      lo.improve_corners = a->improve_corners;
      lo.edge_length = a->patch.edge_length > 0 ? h : 0;
      lo.quads = size.quads;
      lo.default_share = size.area_share;
      LayoutReport report;
      const Layout layout =
          solve_layout(seg.refined.mesh, seg.labels, seg.feature, seg.meta, lo, report);
      const MetaMesh& mm = seg.meta;
      std::map<int, int> valence;
      for (uint32_t v = 0; v < mm.vertices.size(); ++v)
        if (!mm.vertices[v].on_boundary) ++valence[layout.quarter_turns[v]];
      nlohmann::json j = {{"component", c.report_index},
                          {"subdivisions", subdivisions},
                          {"layout_source", field ? "field" : "vsa"},
                          {"patches", mm.faces.size()},
                          {"meta_vertices", mm.vertices.size()},
                          {"meta_edges", mm.edges.size()},
                          {"quads", layout.quads()},
                          {"edge_length", layout.edge_length / prep.normalization.scale},
                          {"objective", layout.objective},
                          {"repairs", report.repairs},
                          {"corner_rounds", report.corner_rounds},
                          {"size_rounds", report.size_rounds},
                          {"solver", report.length_solver},
                          {"optimal", report.length_optimal},
                          {"corner_seconds", report.corner_seconds},
                          {"length_seconds", report.length_seconds}};
      for (const auto& [a_v, n] : valence) j["interior_valence"][std::to_string(a_v)] = n;
      if (a->json) {
        for (uint32_t p = 0; p < layout.charts.size(); ++p) {
          nlohmann::json corners = nlohmann::json::array();
          for (uint32_t k : layout.charts[p].corners)
            corners.push_back(mm.faces[p].start_vertex(k, mm.edges));
          // Per side (0..3, side 0 from corner 0), its meta-edges and the sum of their targets:
          // how far the chart's integer size is from the patch's shape.
          nlohmann::json side_edges =
              nlohmann::json::array({nlohmann::json::array(), nlohmann::json::array(),
                                     nlohmann::json::array(), nlohmann::json::array()});
          std::array<double, 4> side_target{};
          const Chart& chart = layout.charts[p];
          for (uint32_t i = 0; i < mm.faces[p].cycle.size(); ++i) {
            const uint32_t e = mm.faces[p].cycle[i].edge;
            side_edges[chart.item_side[i]].push_back(e);
            side_target[chart.item_side[i]] += layout.target[e];
          }
          j["charts"].push_back({{"patch", p},
                                 {"width", chart.width},
                                 {"height", chart.height},
                                 {"corner_meta_vertices", corners},
                                 {"side_edges", side_edges},
                                 {"side_targets", side_target}});
        }
        for (uint32_t e = 0; e < mm.edges.size(); ++e)
          j["meta_edges_detail"].push_back(
              {{"id", e},
               {"target", layout.target[e]},
               {"length", layout.length[e]},
               {"rotation", layout.transition[e].k},
               {"jump", {layout.transition[e].t[0], layout.transition[e].t[1]}}});
      } else {
        fmt::print(
            "component {}: {} patches, {} meta-vertices, {} meta-edges; {} quads at h = {:.4g}; "
            "objective {:.3g}; interior valences {}; {} corner ILP{}, {} length ILP{} ({}{}), "
            "{:.0f} + {:.0f} ms\n",
            c.report_index, mm.faces.size(), mm.vertices.size(), mm.edges.size(), layout.quads(),
            layout.edge_length / prep.normalization.scale, layout.objective,
            j["interior_valence"].dump(), report.corner_rounds,
            report.corner_rounds == 1 ? "" : "s", report.size_rounds,
            report.size_rounds == 1 ? "" : "s", report.length_solver,
            report.length_optimal ? ", optimal" : "", 1e3 * report.corner_seconds,
            1e3 * report.length_seconds);
        for (const std::string& r : report.repairs) fmt::print("  repair: {}\n", r);
      }
      out.push_back(std::move(j));
    }
    if (a->json) std::cout << out.dump(2) << '\n';
    return 0;
  };
}

}  // namespace isoquad::cli
