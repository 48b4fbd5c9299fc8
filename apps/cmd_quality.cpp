// isoquad quality QUADS --reference IN: validity, shape and distance of a quad mesh.
#include <fmt/format.h>

#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "io/read_mesh.hpp"
#include "io/report_json.hpp"
#include "metrics/quality.hpp"

namespace isoquad::cli {

namespace {
struct QualityArgs {
  std::string mesh, reference;
  bool json = false;
};
}  // namespace

void print_quality(const QualityReport& q) {
  fmt::print(
      "{} vertices, {} faces ({}), {}manifold, {}oriented; chi {}, genus {}, {} component{}, "
      "{} boundary loop{}{}\n",
      q.vertices, q.faces, q.pure_quad ? "all quads" : fmt::format("{} not quads", q.non_quads),
      q.edge_manifold && q.vertex_manifold ? "" : "NOT ", q.oriented ? "" : "NOT ",
      q.topology.euler, q.topology.genus(), q.topology.components,
      q.topology.components == 1 ? "" : "s", q.topology.boundary_loops,
      q.topology.boundary_loops == 1 ? "" : "s",
      q.has_reference ? (q.same_topology ? " (same as the input)" : " (DIFFERENT from the input)")
                      : "");
  std::string val;
  for (const auto& [k, n] : q.valence) val += fmt::format(" {}:{}", k, n);
  fmt::print("irregular vertices {}; interior valences{}\n", q.irregular, val);
  fmt::print("scaled Jacobian min {:.3f}, mean {:.3f}, {:.1f}% below 0.5, {} <= 0", q.sj_min,
             q.sj_mean, q.sj_below_half, q.sj_nonpositive);
  if (q.has_reference)
    fmt::print("; against the surface normal min {:.3f}, {} <= 0", q.sj_surface_min,
               q.sj_surface_nonpositive);
  fmt::print(
      "\nangle deviation mean {:.1f} deg, max {:.1f} deg; edge length mean {:.4g}, cv {:.3f}\n",
      q.angle_deviation_mean, q.angle_deviation_max, q.edge_mean, q.edge_cv);
  if (q.has_reference)
    fmt::print(
        "distance to the input: Hausdorff {:.3f}% (reached at ({:.4g}, {:.4g}, {:.4g}) on the "
        "{}), mean {:.4f}% of the bounding-box diagonal\n",
        100 * q.hausdorff, q.hausdorff_at.x, q.hausdorff_at.y, q.hausdorff_at.z,
        q.hausdorff_on_input ? "input" : "quads", 100 * q.mean_distance);
}

Runner add_quality(CLI::App& app) {
  auto a = std::make_shared<QualityArgs>();
  CLI::App* sub = app.add_subcommand("quality", "Measure a quad mesh: validity, shape, distance");
  sub->add_option("quads", a->mesh, "Quad mesh")->required();
  sub->add_option("--reference", a->reference,
                  "Input surface: topology comparison, surface-normal Jacobians, distances");
  sub->add_flag("--json", a->json, "Print the report as JSON");
  return [a] {
    const ReadResult quads = read_mesh(a->mesh);
    std::optional<ReadResult> ref;
    if (!a->reference.empty()) ref = read_mesh(a->reference);
    const QualityReport q = measure_quality(quads.mesh, ref ? &ref->mesh : nullptr);
    if (a->json)
      std::cout << nlohmann::json(q).dump(2) << '\n';
    else
      print_quality(q);
    return 0;
  };
}

}  // namespace isoquad::cli
