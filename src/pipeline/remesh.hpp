// The whole method on a polygon mesh, with progress and a JSON report: shared by the command
// line and the Eigen entry point (isoquad/remesh.hpp).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/poly_mesh.hpp"
#include "isoquad/remesh.hpp"
#include "metrics/quality.hpp"
#include "pipeline/pipeline.hpp"
#include "prep/prepare.hpp"

namespace isoquad {

struct PolyRemesh {
  PolyMesh quads;      // face_group: patch id
  std::string report;  // JSON
};

// Everything a run made, for pictures and reports (report/report.hpp).
struct RemeshRun {
  PreparedMesh prep;
  std::vector<ComponentRun> runs;
  PolyRemesh result;
  // Every repair and warning of the run, in order: said through the progress as it happens and
  // listed in the report's "warnings".
  std::vector<InputIssue> warnings;
};

// The preparation a remesh with `options` applies (repair, welding, feature angle). The commands
// that stop before the quads prepare with it too.
PrepOptions prep_options(const RemeshOptions& options, bool unshared_vertices);

// What remesh checks before the stages: its options (E003), then the input as prepare()
// checks it (prep/prepare.hpp); with `diagnose`, the input's errors are listed in the report
// instead of thrown. `isoquad info` runs it, so that "would accept" means that remesh does not
// reject the input.
PreparedMesh check_input(const PolyMesh& input, const RemeshOptions& options,
                         bool unshared_vertices = false, bool diagnose = false);

// The check remesh makes on each component's quads: their topology (topology_of) against the
// prepared component's. Nothing if they are the same; if not, with `allow`
// (RemeshOptions::allow_topology_change) the warning W113 that says what changed, for the run's
// warnings. `component`: the input's component index, for the message.
// \throw Error(extraction, E603) naming the component and what changed, without `allow`.
std::optional<InputIssue> check_component_topology(uint32_t component, const Topology& input,
                                                   const Topology& quads, bool allow);

// `progress` gets every line as it is said; `advance` the same lines with how far the run is,
// and the stage boundaries (isoquad::Progress).
RemeshRun remesh_run(const PolyMesh& input, const RemeshOptions& options,
                     bool unshared_vertices = false,
                     const std::function<void(const std::string&)>& progress = {},
                     const ProgressCallback& advance = {});

PolyRemesh remesh_polymesh(const PolyMesh& input, const RemeshOptions& options,
                           bool unshared_vertices = false,
                           const std::function<void(const std::string&)>& progress = {},
                           const ProgressCallback& advance = {});

}  // namespace isoquad
