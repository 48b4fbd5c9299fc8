// isoquad segment MESH: VSA patches (paper §3.1), as a coloured PLY, a summary and a picture.
#include <fmt/format.h>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "field/field_segment.hpp"
#include "io/read_mesh.hpp"
#include "io/write_mesh.hpp"
#include "pipeline/pipeline.hpp"
#include "pipeline/sizing.hpp"
#include "prep/prepare.hpp"
#include "prep_options.hpp"
#include "seg/segment.hpp"
#include "viz/render.hpp"

namespace isoquad::cli {

namespace {
struct SegmentArgs {
  std::string mesh, output, png, segmentation = "vsa";
  PatchArgs patch;
  bool json = false;
  PrepArgs prep;
};
}  // namespace

Runner add_segment(CLI::App& app) {
  auto a = std::make_shared<SegmentArgs>();
  CLI::App* sub = app.add_subcommand(
      "segment", "Split the surface into disk patches (VSA) and build the meta-mesh");
  sub->add_option("mesh", a->mesh, "Input mesh")->required();
  sub->add_option("-o,--output", a->output, "Output PLY with per-face patch ids and colours");
  sub->add_option("--png", a->png, "Picture of the patches");
  add_patch_options(*sub, a->patch);
  sub->add_option("--segmentation", a->segmentation,
                  "vsa (the paper's planar regions) or field (along a cross field's streamlines)")
      ->check(CLI::IsMember({"vsa", "field"}))
      ->capture_default_str();
  sub->add_flag("--json", a->json, "Print a JSON summary");
  add_prep_options(*sub, a->prep);
  refuse_vsa_only_with_field(*sub, a->segmentation, {"--patches"});
  return [a] {
    if (!a->output.empty()) check_mesh_output(a->output);
    if (!a->png.empty()) check_output_path(a->png);
    const ReadResult read = read_mesh(a->mesh, a->prep.read_options());
    const PreparedMesh prep = prepare(read.mesh, a->prep.prep_options(read));
    PolyMesh out;
    std::vector<SegmentResult> shown;
    nlohmann::json summary = nlohmann::json::array();
    uint32_t offset = 0;
    for (uint32_t ci = 0; ci < prep.components.size(); ++ci) {
      const PreparedComponent& c = prep.components[ci];
      const SegmentOptions so = segment_options(a->patch, prep, ci);
      // The surface the pipeline works on (coarse components subdivided, pipeline.hpp).
      EdgeData<char> feature;
      uint32_t subdivisions = 0;
      const RefinedMesh surface =
          subdivide_coarse(c.mesh, c.feature, so.vsa.target_edge_length,
                           PipelineOptions{}.triangles_per_quad, feature, subdivisions);
      FieldLayoutLog field_log;
      SegmentResult seg;
      if (a->segmentation == "field") {
        seg = field_segment(surface.mesh, feature, so.vsa.target_edge_length, field_log).seg;
        if (!field_log.failure.empty())
          fmt::print(stderr, "isoquad: component {}: the field layout failed: {}\n", c.report_index,
                     field_log.failure);
        if (seg.labels.size() != seg.refined.mesh.num_faces()) {
          seg.refined = surface;
          seg.feature = feature;
          seg.labels = FaceData<uint32_t>(surface.mesh.num_faces(), 0);
          seg.num_patches = 1;
        }
      } else {
        seg = segment(surface.mesh, feature, so);
      }
      const MetaMesh& mm = seg.meta;
      summary.push_back(
          {{"component", c.report_index},
           {"subdivisions", subdivisions},
           {"patches", seg.num_patches},
           {"vsa_patches", seg.vsa_patches},
           {"meta_vertices", mm.vertices.size()},
           {"meta_edges", mm.edges.size()},
           {"meta_faces", mm.faces.size()},
           {"inserted_meta_vertices", mm.inserted},
           {"euler", mm.euler()},
           {"dividing_edges_split", seg.dividing_splits},
           {"repairs",
            {{"disconnected_split", seg.repair.disconnected_split},
             {"pinches_fixed", seg.repair.pinches_fixed},
             {"voronoi_splits", seg.repair.voronoi_splits},
             {"two_path_cuts", seg.repair.two_path_cuts},
             {"islands_merged", seg.repair.islands_merged},
             {"strips_cut", seg.repair.strips_cut},
             {"handles_cut", seg.repair.handles_cut},
             {"tiny_merged", seg.repair.tiny_merged}}},
           {"straighten",
            {{"ears", seg.straighten.ears},
             {"geodesic", seg.straighten.geodesic},
             {"seam_length_before", seg.straighten.seam_length_before / prep.normalization.scale},
             {"seam_length_after", seg.straighten.seam_length_after / prep.normalization.scale}}},
           {"vsa_iterations", seg.energy_log.size()},
           {"vsa_energy", seg.energy_log.empty() ? 0.0 : seg.energy_log.back()},
           {"field_failure", field_log.failure}});
      if (!a->json)
        fmt::print(
            "component {}: {} patches ({} from VSA), {} meta-vertices ({} inserted), {} "
            "meta-edges, "
            "euler {}; repairs: {} split, {} pinches, {} voronoi, {} two-path, {} islands, {} "
            "strips, {} handles, {} tiny; "
            "straightened {} ears, {} "
            "geodesic, seams {:.3g} -> {:.3g}\n",
            c.report_index, seg.num_patches, seg.vsa_patches, mm.vertices.size(), mm.inserted,
            mm.edges.size(), mm.euler(), seg.repair.disconnected_split, seg.repair.pinches_fixed,
            seg.repair.voronoi_splits, seg.repair.two_path_cuts, seg.repair.islands_merged,
            seg.repair.strips_cut, seg.repair.handles_cut, seg.repair.tiny_merged,
            seg.straighten.ears, seg.straighten.geodesic, seg.straighten.seam_length_before,
            seg.straighten.seam_length_after);
      const TriMesh& rm = seg.refined.mesh;
      const uint32_t base = uint32_t(out.positions.size());
      for (const Vec3& p : rm.positions()) out.positions.push_back(prep.normalization.invert(p));
      for (uint32_t f = 0; f < rm.num_faces(); ++f) {
        const Tri& t = rm.face(f);
        out.add_face({t[0] + base, t[1] + base, t[2] + base});
        out.face_group.push_back(int32_t(seg.labels[f] + offset));
        const Rgb col = distinct_color(seg.labels[f] + offset);
        out.face_color.push_back(
            {uint8_t(col.r * 255), uint8_t(col.g * 255), uint8_t(col.b * 255)});
      }
      offset += seg.num_patches;
      shown.push_back(std::move(seg));
    }
    if (a->json) std::cout << summary.dump(2) << '\n';
    if (!a->output.empty()) write_mesh(a->output, out);
    if (!a->png.empty()) {
      Box3 box;
      for (const SegmentResult& s : shown)
        box.add(s.refined.mesh.bounding_box().lo), box.add(s.refined.mesh.bounding_box().hi);
      Canvas canvas(1200, 1000, box, Camera{});
      for (const SegmentResult& s : shown) {
        const TriMesh& m = s.refined.mesh;
        canvas.fill(m, [&](uint32_t f) { return distinct_color(s.labels[f]); });
        for (const MetaEdge& e : s.meta.edges)
          for (std::size_t k = 0; k + 1 < e.vertices.size(); ++k)
            canvas.line(m.position(e.vertices[k]), m.position(e.vertices[k + 1]), {0.1, 0.1, 0.1},
                        1.6);
        for (const MetaVertex& v : s.meta.vertices)
          canvas.point(m.position(v.vertex), v.inserted ? Rgb{1.0, 0.85, 0.1} : Rgb{0.9, 0.1, 0.1},
                       4.5);
      }
      canvas.save_png(a->png);
    }
    return 0;
  };
}

}  // namespace isoquad::cli
