// The injectivity certificate (DESIGN.md §7.7) and distortion measures of a map.
#include <cmath>
#include <numbers>

#include "param/param.hpp"

namespace isoquad {

namespace {

double corner_angle_uv(const std::array<UV, 3>& uv, int c) {
  const UV& p = uv[c];
  const UV& q = uv[(c + 1) % 3];
  const UV& r = uv[(c + 2) % 3];
  const double ax = q[0] - p[0], ay = q[1] - p[1], bx = r[0] - p[0], by = r[1] - p[1];
  return std::atan2(ax * by - ay * bx, ax * bx + ay * by);  // signed: negative if flipped
}

double corner_angle_3d(const TriMesh& mesh, uint32_t f, int c) {
  const Tri& t = mesh.face(f);
  const Vec3 a = mesh.position(t[(c + 1) % 3]) - mesh.position(t[c]);
  const Vec3 b = mesh.position(t[(c + 2) % 3]) - mesh.position(t[c]);
  return angle_between(a, b);
}

}  // namespace

Certificate certify(const TriMesh& mesh, const FaceData<uint32_t>& labels, const MetaMesh& meta,
                    const Layout& layout, const ParamMap& map) {
  Certificate cert;
  std::vector<uint32_t> faces_in(layout.charts.size(), 0);
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) ++faces_in[labels[f]];
  std::vector<double> angle_sum(mesh.num_vertices(), 0.0);
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
    const auto& uv = map.uv[f];
    const Chart& chart = layout.charts[labels[f]];
    const double mean_area = double(chart.width * chart.height) / double(faces_in[labels[f]]);
    const double o = orient2d(uv[0], uv[1], uv[2]);
    if (o <= 0) {
      ++cert.flipped;
      cert.bad_faces.push_back(f);
    } else if (0.5 * o <= 1e-12 * mean_area) {
      ++cert.degenerate;
      cert.bad_faces.push_back(f);
    }
    for (int c = 0; c < 3; ++c) angle_sum[mesh.face(f)[c]] += corner_angle_uv(uv, c);
  }
  constexpr double kQuarter = std::numbers::pi / 2;
  for (uint32_t v = 0; v < mesh.num_vertices(); ++v) {
    const uint32_t mv = meta.vertex_meta_vertex[v];
    const double expected = mv != kInvalid               ? layout.quarter_turns[mv] * kQuarter
                            : mesh.is_boundary_vertex(v) ? 2 * kQuarter
                                                         : 4 * kQuarter;
    if (!(std::fabs(angle_sum[v] - expected) <= 1e-6)) {
      ++cert.bad_angle_sums;
      cert.bad_vertices.push_back(v);
    }
  }
  return cert;
}

double mean_angle_distortion(const TriMesh& mesh, const ParamMap& map,
                             const std::vector<char>& mask) {
  double sum = 0;
  uint64_t count = 0;
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
    if (!mask.empty() && !mask[f]) continue;
    for (int c = 0; c < 3; ++c) {
      sum += std::fabs(corner_angle_uv(map.uv[f], c) - corner_angle_3d(mesh, f, c));
      ++count;
    }
  }
  return count ? sum / double(count) : 0.0;
}

std::vector<char> faces_near_seams(const TriMesh& mesh, const FaceData<uint32_t>& labels,
                                   uint32_t rings) {
  std::vector<char> near(mesh.num_faces(), 0);
  std::vector<uint32_t> frontier;
  for (uint32_t h = 0; h < mesh.num_halfedges(); ++h) {
    const uint32_t t = mesh.twin(h);
    if (t != kInvalid && labels[TriMesh::face_of(h)] != labels[TriMesh::face_of(t)] &&
        !near[TriMesh::face_of(h)]) {
      near[TriMesh::face_of(h)] = 1;
      frontier.push_back(TriMesh::face_of(h));
    }
  }
  for (uint32_t ring = 1; ring < rings; ++ring) {
    std::vector<uint32_t> next;
    for (const uint32_t f : frontier)
      for (int c = 0; c < 3; ++c) {
        const uint32_t t = mesh.twin(3 * f + c);
        if (t == kInvalid || near[TriMesh::face_of(t)]) continue;
        near[TriMesh::face_of(t)] = 1;
        next.push_back(TriMesh::face_of(t));
      }
    frontier = std::move(next);
  }
  return near;
}

}  // namespace isoquad
