// isoquad info MESH: what the file holds and what remesh would repair or reject (by remesh's
// own checks before the stages, pipeline/remesh.hpp check_input).
#include <fmt/format.h>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "io/read_mesh.hpp"
#include "io/report_json.hpp"
#include "isoquad/error.hpp"
#include "pipeline/remesh.hpp"
#include "prep/prepare.hpp"
#include "prep_options.hpp"

namespace isoquad::cli {

namespace {

struct InfoArgs {
  std::string mesh;
  bool json = false;
  PrepArgs prep;
};

void print_text(const std::string& file, const ReadResult& read, const InputReport& r) {
  fmt::print("{}: {} {}, {} vertices, {} faces ({} with more than 3 sides)\n", file,
             to_string(read.format), read.binary ? "binary" : "ascii", r.input_vertices,
             r.input_faces, r.input_polygons);
  const Box3& b = r.bounding_box;
  fmt::print(
      "bounding box: ({:.6g}, {:.6g}, {:.6g}) to ({:.6g}, {:.6g}, {:.6g}), diagonal {:.6g}\n",
      b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z, b.diagonal());
  fmt::print("manifold: {}; orientable: {}; components: {}\n",
             r.non_manifold_edges == 0 && r.split_vertices == 0 ? "yes" : "no",
             r.orientable ? "yes" : "no", r.components.size());
  for (std::size_t c = 0; c < r.components.size(); ++c) {
    const ComponentReport& k = r.components[c];
    fmt::print("  component {}: {} vertices, {} edges, {} faces, {}, euler {} , {} {}{}\n", c,
               k.vertices, k.edges, k.faces,
               k.boundary_loops == 0 ? std::string("closed")
                                     : fmt::format("{} boundary loop{}", k.boundary_loops,
                                                   k.boundary_loops == 1 ? "" : "s"),
               k.euler, k.orientable ? "genus" : "non-orientable genus", k.genus,
               k.kept ? "" : " (not remeshed)");
    if (k.kept)
      fmt::print("    area {:.6g}, {} feature edges, min angle {:.3g} deg, {} zero-area faces\n",
                 k.area, k.feature_edges, k.min_angle_deg, k.zero_area_faces);
  }
  for (const InputIssue& i : r.issues) {
    const char* what = i.severity == InputIssue::Severity::error      ? "reject"
                       : i.severity == InputIssue::Severity::repaired ? "repair"
                                                                      : "warning";
    fmt::print("{} {}: {}\n", what, i.code, i.message);
  }
  fmt::print("remesh: {}\n",
             r.has_errors() ? "would reject this input (see above)" : "would accept this input");
}

int exit_status_of(const InputReport& r) {
  for (const InputIssue& i : r.issues)
    if (i.severity == InputIssue::Severity::error)
      return static_cast<int>(i.code == "E102" ? ErrorKind::unsupported_topology
                                               : ErrorKind::invalid_input);
  return 0;
}

}  // namespace

Runner add_info(CLI::App& app) {
  auto args = std::make_shared<InfoArgs>();
  CLI::App* sub = app.add_subcommand(
      "info",
      "Report counts, topology and problems of a mesh, and what remesh would repair or reject");
  sub->add_option("mesh", args->mesh, "Input mesh (.obj, .off, .ply, .stl)")->required();
  sub->add_flag("--json", args->json, "Print a JSON report instead of text");
  add_prep_options(*sub, args->prep);
  return [args] {
    const ReadResult read = read_mesh(args->mesh, args->prep.read_options());
    // remesh's own checks, so that "would accept" holds for remesh with the same options.
    const PreparedMesh prepared =
        check_input(read.mesh, args->prep.remesh_options(), read.unshared_vertices, true);
    if (args->json) {
      nlohmann::json j = prepared.report;
      j["file"] = args->mesh;
      j["format"] = to_string(read.format);
      j["binary"] = read.binary;
      j["dropped_degenerate_faces_on_read"] = read.dropped_faces;
      std::cout << j.dump(2) << '\n';
    } else {
      print_text(args->mesh, read, prepared.report);
    }
    return exit_status_of(prepared.report);
  };
}

}  // namespace isoquad::cli
