#include "seg/tip_split.hpp"

#include <algorithm>
#include <cmath>

#include "seg/geodesic.hpp"
#include "seg/patch_topology.hpp"

namespace isoquad {

namespace {

// The faces of `fan` (CCW around v) in `parts` runs of about equal angle at v.
std::vector<std::vector<uint32_t>> sectors(const TriMesh& mesh, uint32_t v,
                                           const std::vector<uint32_t>& fan, uint32_t parts) {
  std::vector<double> angle(fan.size());
  double total = 0;
  for (std::size_t i = 0; i < fan.size(); ++i) {
    const Tri& t = mesh.face(fan[i]);
    const uint32_t k = t[0] == v ? 0 : t[1] == v ? 1 : 2;
    angle[i] = corner_angle(mesh, 3 * fan[i] + k);
    total += angle[i];
  }
  std::vector<std::vector<uint32_t>> out(parts);
  double before = 0;
  for (std::size_t i = 0; i < fan.size(); ++i) {
    // A face goes to the sector its middle angle falls in.
    const uint32_t s =
        std::min(parts - 1, uint32_t(std::floor((before + 0.5 * angle[i]) / total * parts)));
    out[s].push_back(fan[i]);
    before += angle[i];
  }
  return out;
}

}  // namespace

void split_patches_at_tips(const TriMesh& mesh, const std::vector<uint32_t>& tips,
                           FaceData<uint32_t>& labels, uint32_t& num_patches, TipSplitLog& log) {
  for (const uint32_t t : tips) {
    ++log.tips;
    if (mesh.is_boundary_vertex(t)) {
      log.boundary.push_back(t);
      continue;
    }
    const std::vector<Wedge> wedges = wedges_at(mesh, labels, t);
    if (wedges.size() >= 3) continue;
    // The wedge to cut: the only one, or the one of the two with the larger angle.
    std::size_t cut = 0;
    if (wedges.size() == 2 && patch_angle(mesh, labels, t, wedges[1].patch) >
                                  patch_angle(mesh, labels, t, wedges[0].patch))
      cut = 1;
    const uint32_t patch = wedges[cut].patch;
    const auto parts = sectors(mesh, t, wedges[cut].faces, wedges.size() == 1 ? 3 : 2);
    if (std::any_of(parts.begin(), parts.end(), [](const auto& p) { return p.empty(); })) continue;
    std::vector<uint32_t> sources, sector_of_source;
    for (uint32_t s = 0; s < parts.size(); ++s)
      for (const uint32_t f : parts[s]) sources.push_back(f), sector_of_source.push_back(s);
    const ShortestPaths paths = face_dijkstra(mesh, sources, [&](uint32_t h) {
      const uint32_t o = mesh.twin(h);
      return o != kInvalid && labels[TriMesh::face_of(o)] == patch;
    });
    std::vector<uint32_t> label_of(parts.size(), patch);
    for (std::size_t s = 1; s < parts.size(); ++s) label_of[s] = num_patches++;
    for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
      if (labels[f] != patch || paths.source[f] == kInvalid) continue;
      const auto at = std::find(sources.begin(), sources.end(), paths.source[f]);
      labels[f] = label_of[sector_of_source[std::size_t(at - sources.begin())]];
    }
    ++log.split;
  }
}

}  // namespace isoquad
