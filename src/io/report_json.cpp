#include "io/report_json.hpp"

#include <nlohmann/json.hpp>

namespace isoquad {

namespace {
const char* severity_name(InputIssue::Severity s) {
  switch (s) {
    case InputIssue::Severity::error:
      return "error";
    case InputIssue::Severity::repaired:
      return "repaired";
    case InputIssue::Severity::warning:
      return "warning";
  }
  return "?";
}
}  // namespace

void to_json(nlohmann::json& j, const ComponentReport& r) {
  j = {{"vertices", r.vertices},
       {"edges", r.edges},
       {"faces", r.faces},
       {"boundary_loops", r.boundary_loops},
       {"euler_characteristic", r.euler},
       {"genus", r.genus},
       {"orientable", r.orientable},
       {"closed", r.boundary_loops == 0},
       {"kept", r.kept},
       {"area", r.area},
       {"feature_edges", r.feature_edges},
       {"min_angle_deg", r.min_angle_deg},
       {"zero_area_faces", r.zero_area_faces},
       {"zero_area_collapsed", r.zero_area_collapsed},
       {"zero_area_flipped", r.zero_area_flipped},
       {"zero_area_dropped", r.zero_area_dropped},
       {"flat_flips", r.flat_flips}};
}

void to_json(nlohmann::json& j, const InputIssue& i) {
  j = {{"severity", severity_name(i.severity)},
       {"code", i.code},
       {"message", i.message},
       {"count", i.count}};
}

void to_json(nlohmann::json& j, const InputReport& r) {
  j = {{"input_vertices", r.input_vertices},
       {"input_faces", r.input_faces},
       {"input_polygons", r.input_polygons},
       {"welded_vertices", r.welded_vertices},
       {"unused_vertices", r.unused_vertices},
       {"degenerate_faces", r.degenerate_faces},
       {"duplicate_faces", r.duplicate_faces},
       {"non_manifold_edges", r.non_manifold_edges},
       {"split_vertices", r.split_vertices},
       {"flipped_faces", r.flipped_faces},
       {"removed_faces", r.removed_faces},
       {"manifold", r.non_manifold_edges == 0 && r.split_vertices == 0},
       {"orientable", r.orientable},
       {"bounding_box",
        {{"min", {r.bounding_box.lo.x, r.bounding_box.lo.y, r.bounding_box.lo.z}},
         {"max", {r.bounding_box.hi.x, r.bounding_box.hi.y, r.bounding_box.hi.z}},
         {"diagonal", r.bounding_box.diagonal()}}},
       {"components", r.components},
       {"issues", r.issues},
       {"remesh_would_accept", !r.has_errors()}};
}

void to_json(nlohmann::json& j, const Topology& t) {
  j = {{"euler", t.euler},
       {"genus", t.genus()},
       {"components", t.components},
       {"boundary_loops", t.boundary_loops}};
}

void to_json(nlohmann::json& j, const QualityReport& q) {
  nlohmann::json valence = nlohmann::json::object();
  for (const auto& [k, n] : q.valence) valence[std::to_string(k)] = n;
  j = {{"vertices", q.vertices},
       {"faces", q.faces},
       {"non_quads", q.non_quads},
       {"pure_quad", q.pure_quad},
       {"edge_manifold", q.edge_manifold},
       {"vertex_manifold", q.vertex_manifold},
       {"oriented", q.oriented},
       {"topology", q.topology},
       {"interior_valence", valence},
       {"irregular_vertices", q.irregular},
       // Against each quad's own (Newell) normal; at_most_0.001: not valid.
       {"scaled_jacobian",
        {{"min", q.sj_min},
         {"mean", q.sj_mean},
         {"percent_below_0.5", q.sj_below_half},
         {"at_most_0.001", q.sj_invalid},
         {"nonpositive", q.sj_nonpositive}}},
       {"angle_deviation_deg", {{"mean", q.angle_deviation_mean}, {"max", q.angle_deviation_max}}},
       {"edge_length", {{"mean", q.edge_mean}, {"cv", q.edge_cv}}},
       {"aspect_ratio",
        {{"mean", q.aspect_mean}, {"p95", q.aspect_p95}, {"percent_above_2", q.aspect_above_2}}},
       {"area", {{"cv", q.area_cv}}}};
  if (q.has_reference) {
    j["reference_topology"] = *q.reference_topology;
    j["same_topology"] = q.same_topology;
    j["scaled_jacobian_surface"] = {{"min", q.sj_surface_min},
                                    {"nonpositive", q.sj_surface_nonpositive}};
    j["hausdorff"] = q.hausdorff;
    j["mean_distance"] = q.mean_distance;
    j["feature_coverage"] = {{"angle_deg", q.feature_angle_deg},
                             {"length", q.feature_length},
                             {"covered", q.feature_coverage}};
    j["hausdorff_at"] = {{"point", {q.hausdorff_at.x, q.hausdorff_at.y, q.hausdorff_at.z}},
                         {"on", q.hausdorff_on_input ? "input" : "quads"}};
  }
}

}  // namespace isoquad
