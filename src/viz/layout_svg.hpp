// The layout picture (DESIGN.md §9.3): every patch drawn as its W x H rectangle with the integer
// lattice and its triangles as the map places them; flipped or degenerate triangles in red.
#pragma once

#include <filesystem>
#include <vector>

#include "layout/layout.hpp"
#include "param/param.hpp"

namespace isoquad {

// Writes an SVG, or a PNG when the path ends in .png (atomically). `bad_faces` are filled red.
void write_layout_svg(const std::filesystem::path& path, const TriMesh& mesh,
                      const FaceData<uint32_t>& labels, const Layout& layout, const ParamMap& map,
                      const std::vector<uint32_t>& bad_faces);

}  // namespace isoquad
