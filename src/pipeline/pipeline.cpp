#include "pipeline/pipeline.hpp"

#include <chrono>

#include "pipeline/sizing.hpp"

namespace isoquad {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace

ComponentRun run_component(const PreparedMesh& prep, uint32_t c, const PipelineOptions& o) {
  double total_area = 0;
  for (const auto& comp : prep.components) total_area += surface_area(comp.mesh);
  const PreparedComponent& comp = prep.components.at(c);
  ComponentRun run;
  run.component = c;
  run.area_share = total_area > 0 ? surface_area(comp.mesh) / total_area : 1.0;
  const double h = component_edge_length(comp.mesh, run.area_share, {o.edge_length, o.quads},
                                         prep.normalization.scale);
  auto t0 = Clock::now();
  run.seg = segment(comp.mesh, comp.feature, SegmentOptions::sized(h, o.patches, o.seed));
  run.segment_seconds = seconds_since(t0);
  if (o.last == Stage::segment) return run;

  LayoutOptions lo = o.layout;
  lo.edge_length = o.edge_length > 0 ? h : 0;
  lo.quads = o.edge_length > 0 ? 0 : (o.quads > 0 ? o.quads * run.area_share : 0);
  t0 = Clock::now();
  run.layout = solve_layout(run.seg.refined.mesh, run.seg.labels, run.seg.feature, run.seg.meta, lo,
                            run.layout_report);
  run.layout_seconds = seconds_since(t0);
  if (o.last == Stage::layout) return run;

  t0 = Clock::now();
  run.param = parametrize(run.seg.refined.mesh, run.seg.labels, run.seg.meta, run.layout, o.param,
                          run.param_report);
  run.param_seconds = seconds_since(t0);
  if (o.last == Stage::param) return run;

  t0 = Clock::now();
  run.quads = extract_quads(run.seg.refined, comp.mesh, run.seg.labels, run.seg.meta, run.layout,
                            run.param, run.extract_report);
  if (o.smooth > 0) smooth_quads(run.quads, comp.mesh, run.seg.meta, o.smooth, run.smooth_report);
  run.extract_seconds = seconds_since(t0);
  return run;
}

std::vector<ComponentRun> run_pipeline(const PreparedMesh& prep, const PipelineOptions& o) {
  std::vector<ComponentRun> runs;
  for (uint32_t c = 0; c < prep.components.size(); ++c) runs.push_back(run_component(prep, c, o));
  return runs;
}

}  // namespace isoquad

namespace isoquad {

PolyMesh merge_quads(const PreparedMesh& prep, const std::vector<ComponentRun>& runs) {
  PolyMesh out;
  uint32_t patch_base = 0;
  for (const ComponentRun& run : runs) {
    const uint32_t base = uint32_t(out.positions.size());
    for (const Vec3& p : run.quads.positions) out.positions.push_back(prep.normalization.invert(p));
    for (std::size_t q = 0; q < run.quads.quads.size(); ++q) {
      const auto& v = run.quads.quads[q];
      out.add_face({base + v[0], base + v[1], base + v[2], base + v[3]});
      out.face_group.push_back(int32_t(patch_base + run.quads.quad_patch[q]));
    }
    patch_base += uint32_t(run.layout.charts.size());
  }
  return out;
}

}  // namespace isoquad
