// isoquad quality QUADS --reference IN: validity, shape and distance of a quad mesh.
#include <fmt/format.h>

#include <algorithm>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "io/read_mesh.hpp"
#include "io/report_json.hpp"
#include "metrics/feature_coverage.hpp"
#include "metrics/quality.hpp"
#include "prep_options.hpp"

namespace isoquad::cli {

namespace {
struct QualityArgs {
  std::string mesh, reference;
  bool json = false;
  uint32_t worst = 0;
  double feature_angle = QualityOptions{}.feature_angle_deg;
};

struct WorstFace {
  uint32_t face = 0;
  double sj = 0;
  Vec3 centroid;
};

// The `count` faces with the smallest scaled Jacobian against the reference's normal (ties by
// face id), so that a user can find the folded or worst-shaped elements.
std::vector<WorstFace> worst_faces(const PolyMesh& quads, const PolyMesh& reference,
                                   uint32_t count) {
  const std::vector<double> sj = surface_scaled_jacobians(quads, reference);
  std::vector<uint32_t> order(sj.size());
  for (uint32_t f = 0; f < order.size(); ++f) order[f] = f;
  const std::size_t n = std::min<std::size_t>(count, order.size());
  std::partial_sort(order.begin(), order.begin() + std::ptrdiff_t(n), order.end(),
                    [&](uint32_t a, uint32_t b) { return sj[a] != sj[b] ? sj[a] < sj[b] : a < b; });
  std::vector<WorstFace> out;
  for (std::size_t i = 0; i < n; ++i) {
    WorstFace w{order[i], sj[order[i]], {}};
    const auto& face = quads.face(order[i]);
    for (const uint32_t v : face) w.centroid += quads.positions[v];
    w.centroid = w.centroid / double(face.size());
    out.push_back(w);
  }
  return out;
}
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
  fmt::print(
      "scaled Jacobian against each quad's own normal: min {:.3f}, mean {:.3f}, {:.1f}% below 0.5, "
      "{} at most {} (not valid; {} of them <= 0)\n",
      q.sj_min, q.sj_mean, q.sj_below_half, q.sj_invalid, kMinValidScaledJacobian,
      q.sj_nonpositive);
  if (q.has_reference)
    fmt::print("scaled Jacobian against the surface normal: min {:.3f}, {} <= 0 (folded)\n",
               q.sj_surface_min, q.sj_surface_nonpositive);
  fmt::print(
      "angle deviation mean {:.1f} deg, max {:.1f} deg; edge length mean {:.4g}, cv {:.3f}\n",
      q.angle_deviation_mean, q.angle_deviation_max, q.edge_mean, q.edge_cv);
  fmt::print(
      "aspect ratio (opposite sides' mean lengths, larger over smaller) mean {:.3f}, 95th "
      "percentile {:.3f}, {:.1f}% above 2; area cv {:.3f}\n",
      q.aspect_mean, q.aspect_p95, q.aspect_above_2, q.area_cv);
  if (q.has_reference) {
    if (q.feature_length > 0)
      fmt::print(
          "feature coverage {:.1f}%: of the input's feature edges (dihedral angle above {:g} "
          "deg, length {:.4g}), the part within {:g} x the mean edge length of a quad edge\n",
          100 * q.feature_coverage, q.feature_angle_deg, q.feature_length,
          kFeatureCoverageTolerance);
    else
      fmt::print(
          "feature coverage: the input has no feature edge (dihedral angle above {:g} deg)\n",
          q.feature_angle_deg);
  }
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
  sub->add_option("--worst", a->worst,
                  "Also list the N faces with the smallest scaled Jacobian against the surface "
                  "(id from 0 in file order, value, centroid)")
      ->needs(sub->get_option("--reference"));
  sub->add_option("--feature-angle", a->feature_angle,
                  "Feature coverage: the input's edges with a dihedral angle above this (degrees; "
                  "0: none), as remesh --feature-angle")
      ->capture_default_str()
      ->check(number_in(0, 180, "an angle in [0, 180] degrees"))
      ->needs(sub->get_option("--reference"));
  return [a] {
    const ReadResult quads = read_mesh(a->mesh);
    std::optional<ReadResult> ref;
    if (!a->reference.empty()) ref = read_mesh(a->reference);
    QualityOptions options;
    options.feature_angle_deg = a->feature_angle;
    const QualityReport q = measure_quality(quads.mesh, ref ? &ref->mesh : nullptr, options);
    const std::vector<WorstFace> worst =
        a->worst > 0 ? worst_faces(quads.mesh, ref->mesh, a->worst) : std::vector<WorstFace>{};
    if (a->json) {
      nlohmann::json j = q;
      if (a->worst > 0) {
        j["worst"] = nlohmann::json::array();
        for (const WorstFace& w : worst)
          j["worst"].push_back({{"face", w.face},
                                {"scaled_jacobian_surface", w.sj},
                                {"centroid", {w.centroid.x, w.centroid.y, w.centroid.z}}});
      }
      std::cout << j.dump(2) << '\n';
    } else {
      print_quality(q);
      for (const WorstFace& w : worst)
        fmt::print(
            "face {}: scaled Jacobian against the surface {:.3f}, centroid ({:.4g}, {:.4g}, "
            "{:.4g})\n",
            w.face, w.sj, w.centroid.x, w.centroid.y, w.centroid.z);
    }
    return 0;
  };
}

}  // namespace isoquad::cli
