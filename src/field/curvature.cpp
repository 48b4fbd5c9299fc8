#include "field/curvature.hpp"

#include <algorithm>
#include <cmath>

#include "seg/geodesic.hpp"

namespace isoquad {

namespace {

using Complex = std::complex<double>;

// Signed dihedral angle at the edge of halfedge h (positive where the surface is convex).
double signed_dihedral(const TriMesh& mesh, const FaceFrames& frames, uint32_t h) {
  const uint32_t f = TriMesh::face_of(h), g = TriMesh::face_of(mesh.twin(h));
  const Vec3 d = normalized(mesh.position(mesh.to(h)) - mesh.position(mesh.from(h)));
  const Vec3 nf = frames.normal[f], ng = frames.normal[g];
  return std::atan2(dot(cross(nf, ng), d), dot(nf, ng));
}

// The deviator (S_xx - S_yy)/2 + i S_xy of the edge-based shape operator over each face, half of
// each edge's bending given to each of its faces: magnitude about |k1 - k2|/2.
FaceData<Complex> face_deviators(const TriMesh& mesh, const FaceFrames& frames) {
  FaceData<Complex> dev(mesh.num_faces(), Complex(0, 0));
  for (uint32_t f = 0; f < mesh.num_faces(); ++f) {
    const double area = mesh.face_area(f);
    if (!(area > 0)) continue;
    Complex sum(0, 0);
    for (uint32_t i = 0; i < 3; ++i) {
      const uint32_t h = 3 * f + i;
      if (mesh.twin(h) == kInvalid) continue;
      const Vec3 d = mesh.position(mesh.to(h)) - mesh.position(mesh.from(h));
      const double phi = frames.arg(f, d);
      sum += 0.25 * signed_dihedral(mesh, frames, h) * norm(d) * std::polar(1.0, 2 * phi);
    }
    dev[f] = sum / area;
  }
  return dev;
}

}  // namespace

CurvatureGuidance curvature_guidance(const TriMesh& mesh, const FaceFrames& frames,
                                     const EdgeData<char>& feature, double h) {
  const uint32_t nf = mesh.num_faces();
  FaceData<Complex> dev = face_deviators(mesh, frames);

  // Averaging over a radius of about h: area-weighted Jacobi rounds over the neighbours, each
  // spreading by about one edge, so about (h / mean edge)^2 rounds for a diffusion of radius h.
  double edge_sum = 0;
  for (uint32_t e = 0; e < mesh.num_edges(); ++e) {
    const uint32_t he = mesh.edge_halfedge(e);
    edge_sum += norm(mesh.position(mesh.to(he)) - mesh.position(mesh.from(he)));
  }
  const double mean_edge = edge_sum / std::max<uint32_t>(1, mesh.num_edges());
  const double spread = h / std::max(mean_edge, 1e-300);
  const int rounds = std::clamp(int(std::lround(spread * spread)), 1, 40);
  FaceData<double> area(nf);
  for (uint32_t f = 0; f < nf; ++f) area[f] = mesh.face_area(f);
  // A 2-direction at angle t in the twin's face is at t - rho in the halfedge's face.
  HalfedgeData<Complex> to_face(mesh.num_halfedges());
  for (uint32_t he = 0; he < mesh.num_halfedges(); ++he)
    to_face[he] = std::polar(1.0, -2 * frames.rho[he]);
  FaceData<Complex> next(nf);
  for (int round = 0; round < rounds; ++round) {
    for (uint32_t f = 0; f < nf; ++f) {
      Complex sum = area[f] * dev[f];
      double weight = area[f];
      for (uint32_t i = 0; i < 3; ++i) {
        const uint32_t he = 3 * f + i, tw = mesh.twin(he);
        if (tw == kInvalid) continue;
        const uint32_t g = TriMesh::face_of(tw);
        sum += area[g] * to_face[he] * dev[g];
        weight += area[g];
      }
      next[f] = weight > 0 ? sum / weight : Complex(0, 0);
    }
    std::swap(dev, next);
  }

  // Distance from the hard constraints (feature and boundary edges), centroid to centroid.
  std::vector<uint32_t> sources;
  for (uint32_t f = 0; f < nf; ++f)
    for (uint32_t i = 0; i < 3; ++i) {
      const uint32_t he = 3 * f + i;
      if (mesh.twin(he) == kInvalid || feature[mesh.edge(he)]) {
        sources.push_back(f);
        break;
      }
    }
  const ShortestPaths near = face_dijkstra(mesh, sources, [](uint32_t) { return true; });

  CurvatureGuidance g;
  g.target = FaceData<Complex>(nf, Complex(0, 0));
  g.weight = FaceData<double>(nf, 0.0);
  for (uint32_t f = 0; f < nf; ++f) {
    const double m = std::abs(dev[f]);
    if (!(m > 0)) continue;
    const Complex unit = dev[f] / m;
    g.target[f] = unit * unit;  // e^{2i phi} squared: the 4-direction
    const double s = 2 * h * m;
    const double fade = std::min(1.0, near.distance[f] / (2 * h));
    g.weight[f] = s * s / (s * s + 0.01) * fade;
  }
  return g;
}

}  // namespace isoquad
