// The method's stages for one prepared mesh, component by component: segmentation, layout and
// parametrization (extraction follows). The command line and the library call share it, so both
// size components the same way (a requested quad count is shared out by area).
#pragma once

#include <cstdint>
#include <vector>

#include "core/poly_mesh.hpp"
#include "extract/extract.hpp"
#include "extract/smooth.hpp"
#include "layout/layout.hpp"
#include "param/param.hpp"
#include "prep/prepare.hpp"
#include "seg/segment.hpp"

namespace isoquad {

enum class Stage { segment, layout, param, extract };

struct PipelineOptions {
  uint32_t patches = 0;    // K; 0: automatic
  double edge_length = 0;  // target quad edge length in input units; 0: from quads
  double quads = 0;        // target quad count for the whole mesh; 0: the default
  uint64_t seed = 1;
  LayoutOptions layout;  // corners and length solver (size fields are set per component)
  ParamOptions param;
  uint32_t smooth = 0;  // tangential smoothing iterations after extraction
  Stage last = Stage::extract;
};

struct ComponentRun {
  uint32_t component = 0;  // index into PreparedMesh::components
  double area_share = 1;   // of the whole surface
  SegmentResult seg;
  Layout layout;
  LayoutReport layout_report;
  Param param;
  ParamReport param_report;
  QuadMesh quads;
  ExtractReport extract_report;
  SmoothReport smooth_report;
  double segment_seconds = 0, layout_seconds = 0, param_seconds = 0, extract_seconds = 0;
};

// Runs the stages up to options.last on component `c` of `prep`.
ComponentRun run_component(const PreparedMesh& prep, uint32_t c, const PipelineOptions& options);

// Every component, in order.
std::vector<ComponentRun> run_pipeline(const PreparedMesh& prep, const PipelineOptions& options);

// The components' quads as one mesh in input coordinates; face_group is the patch id, numbered
// across components.
PolyMesh merge_quads(const PreparedMesh& prep, const std::vector<ComponentRun>& runs);

}  // namespace isoquad
