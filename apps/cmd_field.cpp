// isoquad field MESH: the cross field the field-aligned layout follows (FIELD_LAYOUT.md §1-§2),
// its singularities, and a picture of both.
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <tuple>

#include "commands.hpp"
#include "field/cross_field.hpp"
#include "field/trace.hpp"
#include "io/read_mesh.hpp"
#include "io/write_mesh.hpp"
#include "pipeline/sizing.hpp"
#include "prep/prepare.hpp"
#include "prep_options.hpp"
#include "viz/render.hpp"

namespace isoquad::cli {

namespace {

struct FieldArgs {
  std::string mesh, png;
  double edge_length = 0, quads = 0;
  double smoothing = CrossFieldOptions{}.smoothing;
  double min_feature = CrossFieldOptions{}.min_feature_length;
  bool no_curvature = false, json = false;
  PrepArgs prep;
};

struct ComponentField {
  const PreparedComponent* component;
  RefinedMesh refined;
  EdgeData<char> feature;
  CrossField field;
  TraceResult traces;
  double h = 0;
};

// Faces at least `spacing` apart (centroids, on a grid of that cell size), in face order: where
// the picture draws a cross.
std::vector<uint32_t> spread_faces(const TriMesh& m, double spacing) {
  std::map<std::tuple<int64_t, int64_t, int64_t>, bool> taken;
  std::vector<uint32_t> faces;
  for (uint32_t f = 0; f < m.num_faces(); ++f) {
    const Tri& t = m.face(f);
    const Vec3 c = (m.position(t[0]) + m.position(t[1]) + m.position(t[2])) / 3.0;
    const auto key =
        std::tuple(int64_t(std::floor(c.x / spacing)), int64_t(std::floor(c.y / spacing)),
                   int64_t(std::floor(c.z / spacing)));
    if (taken.emplace(key, true).second) faces.push_back(f);
  }
  return faces;
}

void draw_field(const std::vector<ComponentField>& fields, const std::string& png) {
  std::vector<const TriMesh*> meshes;
  Box3 box;
  for (const ComponentField& c : fields) {
    meshes.push_back(&c.refined.mesh);
    box.add(c.refined.mesh.bounding_box().lo), box.add(c.refined.mesh.bounding_box().hi);
  }
  Canvas canvas(1400, 1100, box, best_view(meshes));
  for (const ComponentField& c : fields) {
    const TriMesh& m = c.refined.mesh;
    canvas.fill(m, [&](uint32_t f) {
      return c.field.constrained[f] ? Rgb{0.80, 0.84, 0.92} : Rgb{0.86, 0.86, 0.84};
    });
    for (uint32_t e = 0; e < m.num_edges(); ++e) {
      if (!c.field.feature[e]) continue;
      const uint32_t h = m.edge_halfedge(e);
      canvas.line(m.position(m.from(h)), m.position(m.to(h)), {0.15, 0.15, 0.15}, 1.6);
    }
    const double arm = 0.22 * c.h;
    for (uint32_t f : spread_faces(m, 0.5 * c.h)) {
      const Tri& t = m.face(f);
      const Vec3 mid = (m.position(t[0]) + m.position(t[1]) + m.position(t[2])) / 3.0;
      for (int k = 0; k < 2; ++k) {
        const Vec3 d = arm * c.field.direction_on(m, f, k);
        canvas.line(mid - d, mid + d, k == 0 ? Rgb{0.1, 0.35, 0.75} : Rgb{0.2, 0.6, 0.3}, 1.3);
      }
    }
    for (const Trace& t : c.traces.traces)
      for (std::size_t k = 0; k + 1 < t.points.size(); ++k)
        canvas.line(position_on(m, t.points[k]), position_on(m, t.points[k + 1]),
                    t.end == TraceEnd::cap || t.end == TraceEnd::sink ? Rgb{0.95, 0.5, 0.0}
                                                                      : Rgb{0.75, 0.1, 0.45},
                    2.0);
    for (uint32_t v : c.field.singular) {
      const int32_t i = c.field.index4[v];
      const Rgb col =
          i > 0 ? Rgb{0.1, 0.3, 0.95} : (i < 0 ? Rgb{0.9, 0.1, 0.1} : Rgb{0.8, 0.2, 0.8});
      canvas.point(m.position(v), col, std::abs(i) > 1 || m.is_boundary_vertex(v) ? 7 : 5);
    }
  }
  uint32_t plus = 0, minus = 0, other = 0;
  for (const ComponentField& c : fields)
    for (uint32_t v : c.field.singular) {
      const int32_t i = c.field.index4[v];
      (i == 1 ? plus : i == -1 ? minus : other)++;
    }
  std::size_t traces = 0;
  for (const ComponentField& c : fields) traces += c.traces.traces.size();
  canvas.caption(
      fmt::format("cross field: {} singularities +1/4 (blue), {} -1/4 (red), {} other; "
                  "{} traces",
                  plus, minus, other, traces));
  canvas.save_png(png);
}

nlohmann::json trace_summary(const TraceResult& r, double seconds) {
  std::map<std::string, uint32_t> ends;
  for (const Trace& t : r.traces)
    ++ends[t.end == TraceEnd::boundary  ? "boundary"
           : t.end == TraceEnd::feature ? "feature"
           : t.end == TraceEnd::track   ? "track"
           : t.end == TraceEnd::cap     ? "cap"
           : t.end == TraceEnd::node    ? "node"
                                        : "sink"];
  return {{"nodes", r.nodes.size()},
          {"traces", r.traces.size()},
          {"ends", ends},
          {"ray_mismatches", r.ray_mismatches},
          {"connections", r.connections},
          {"deleted", r.deleted},
          {"rounds", r.rounds},
          {"truncated", r.truncated},
          {"straight_crossings", r.straight_crossings},
          {"head_on", r.head_on},
          {"seconds", seconds}};
}

nlohmann::json field_summary(const ComponentField& c, double seconds) {
  std::map<int32_t, uint32_t> by_index;
  uint32_t boundary = 0;
  for (uint32_t v : c.field.singular) {
    if (c.refined.mesh.is_boundary_vertex(v))
      ++boundary;
    else
      ++by_index[c.field.index4[v]];
  }
  nlohmann::json indices = nlohmann::json::object();
  for (const auto& [i, n] : by_index) indices[fmt::format("{}/4", i)] = n;
  return {{"component", c.component->report_index},
          {"faces", c.refined.mesh.num_faces()},
          {"split_faces", c.refined.mesh.num_faces() - c.component->mesh.num_faces()},
          {"variant", c.field.variant == FieldVariant::eigen ? "eigen" : "linear"},
          {"constrained_faces", c.field.constrained_faces},
          {"short_feature_networks_dropped", c.field.short_feature_networks},
          {"guided_area_share", c.field.guided_area_share},
          {"solves", c.field.solves},
          {"energy", c.field.energy},
          {"interior_singularities", indices},
          {"boundary_singularities", boundary},
          {"seconds", seconds}};
}

}  // namespace

Runner add_field(CLI::App& app) {
  auto a = std::make_shared<FieldArgs>();
  CLI::App* sub = app.add_subcommand(
      "field", "Compute the cross field of the field-aligned layout and its singularities");
  sub->add_option("mesh", a->mesh, "Input mesh")->required();
  sub->add_option("--png", a->png, "Picture of the crosses, features and singularities");
  auto* el = sub->add_option("--edge-length", a->edge_length,
                             "Target quad edge length (input units): the field's scale")
                 ->check(number_in(std::numeric_limits<double>::min(),
                                   std::numeric_limits<double>::max(), "a positive length"));
  sub->add_option("--quads", a->quads, "Target number of quads, for the field's scale")
      ->check(number_in(1, 1e9, "a quad count in [1, 1e9]"))
      ->excludes(el);
  sub->add_option("--smoothing", a->smoothing,
                  "Solve on the surface smoothed by mean curvature flow for this many h^2; 0: off")
      ->check(number_in(0, 100, "a smoothing time in [0, 100] h^2"))
      ->capture_default_str();
  sub->add_option("--min-feature", a->min_feature,
                  "Feature networks shorter than this many h in all do not constrain the field")
      ->check(number_in(0, 1e9, "a length in h, at least 0"))
      ->capture_default_str();
  sub->add_flag("--no-curvature", a->no_curvature, "No pull towards principal directions");
  sub->add_flag("--json", a->json, "Print a JSON summary");
  add_prep_options(*sub, a->prep);
  return [a] {
    if (!a->png.empty()) check_output_path(a->png);
    const ReadResult read = read_mesh(a->mesh, a->prep.read_options());
    const PreparedMesh prep = prepare(read.mesh, a->prep.prep_options(read));
    std::vector<ComponentField> fields;
    nlohmann::json out = nlohmann::json::array();
    for (uint32_t ci = 0; ci < prep.components.size(); ++ci) {
      const PreparedComponent& c = prep.components[ci];
      const auto t0 = std::chrono::steady_clock::now();
      ComponentField cf{&c, {}, {}, {}, {}, 0};
      cf.h = component_size(prep, ci, {a->edge_length, a->quads}).edge_length;
      cf.feature = c.feature;
      cf.refined = split_constraint_conflicts(identity_refinement(c.mesh), cf.feature);
      CrossFieldOptions o;
      o.edge_length = cf.h;
      o.smoothing = a->smoothing;
      o.curvature = !a->no_curvature;
      o.min_feature_length = a->min_feature;
      cf.field = compute_cross_field(cf.refined.mesh, cf.feature, o);
      const auto t1 = std::chrono::steady_clock::now();
      TraceOptions to;
      to.edge_length = cf.h;
      cf.traces = trace_separatrices(cf.field, to);
      const auto t2 = std::chrono::steady_clock::now();
      out.push_back(field_summary(cf, std::chrono::duration<double>(t1 - t0).count()));
      out.back()["tracing"] =
          trace_summary(cf.traces, std::chrono::duration<double>(t2 - t1).count());
      fields.push_back(std::move(cf));
    }
    if (a->json) {
      std::cout << out.dump(2) << '\n';
    } else {
      for (const auto& c : out)
        fmt::print(
            "component {}: {} faces, {} field, {} constrained faces, singularities {} "
            "interior, {} on the boundary, {:.3f} s; {} traces from {} nodes, ends {}, {:.3f} s\n",
            c["component"].get<uint32_t>(), c["faces"].get<uint32_t>(),
            c["variant"].get<std::string>(), c["constrained_faces"].get<uint32_t>(),
            c["interior_singularities"].dump(), c["boundary_singularities"].get<uint32_t>(),
            c["seconds"].get<double>(), c["tracing"]["traces"].get<std::size_t>(),
            c["tracing"]["nodes"].get<std::size_t>(), c["tracing"]["ends"].dump(),
            c["tracing"]["seconds"].get<double>());
    }
    if (!a->png.empty()) draw_field(fields, a->png);
    return 0;
  };
}

}  // namespace isoquad::cli
