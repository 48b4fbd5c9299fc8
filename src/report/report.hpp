// The run report (paper §4, Figures 1 to 3; DESIGN.md §9.3): the four panels of Figure 1 under
// one camera, the layout picture, the locked-versus-relaxed comparison of Figure 3, the numbers
// as JSON and one self-contained HTML page that shows it all.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/poly_mesh.hpp"
#include "pipeline/remesh.hpp"
#include "viz/render.hpp"

namespace isoquad {

struct ReportOptions {
  std::optional<Vec3> view;  // viewing direction; default: the three-quarter view showing most
  int width = 1200;          // of each panel in pixels (height 5/6 of it)
  std::string title;         // the input's name, for the page's heading
};

struct ReportFiles {
  std::vector<std::string> names;  // relative to the report folder, in writing order
};

// Writes into `dir` (created if needed): input.png, patches.png, contours.png, quads.png,
// layout.svg (layout-<c>.svg for component c > 0), weights.png, report.json and index.html.
// `run.result.report` must hold the quality report (RemeshOptions::quality). Every file is
// written atomically. \throw Error(invalid_input, E001) when the folder cannot be written.
ReportFiles write_report(const std::filesystem::path& dir, const PolyMesh& input,
                         const RemeshRun& run, const ReportOptions& options = {});

// Standard base64 (RFC 4648) with padding, for data URIs.
std::string base64(const std::string& bytes);

}  // namespace isoquad
