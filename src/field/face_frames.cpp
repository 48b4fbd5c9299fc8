#include "field/face_frames.hpp"

#include <cmath>
#include <numbers>

#include <tbb/parallel_for.h>

namespace isoquad {

double wrap_angle(double a, double period) {
  a = std::remainder(a, period);  // in [-period/2, period/2]
  return a <= -period / 2 ? a + period : a;
}

double FaceFrames::arg(uint32_t f, Vec3 d) const { return std::atan2(dot(d, y[f]), dot(d, x[f])); }

Vec3 FaceFrames::direction(uint32_t f, double t) const {
  return std::cos(t) * x[f] + std::sin(t) * y[f];
}

FaceFrames face_frames(const TriMesh& mesh) {
  const uint32_t nf = mesh.num_faces();
  FaceFrames fr;
  fr.x = FaceData<Vec3>(nf);
  fr.y = FaceData<Vec3>(nf);
  fr.normal = FaceData<Vec3>(nf);
  // Per face and per edge in parallel: each iteration writes its own entries.
  tbb::parallel_for(uint32_t(0), nf, [&](uint32_t f) {
    const Tri& t = mesh.face(f);
    const Vec3 e[3] = {mesh.position(t[1]) - mesh.position(t[0]),
                       mesh.position(t[2]) - mesh.position(t[1]),
                       mesh.position(t[0]) - mesh.position(t[2])};
    Vec3 n = normalized(cross(e[0], -e[2]));
    Vec3 x = normalized(e[0]);
    if (squared_norm(n) == 0) {
      int longest = 0;
      for (int i = 1; i < 3; ++i)
        if (squared_norm(e[i]) > squared_norm(e[longest])) longest = i;
      x = normalized(e[longest]);
      if (squared_norm(x) == 0) x = {1, 0, 0};  // all three corners at one point
      // Any unit normal perpendicular to x: the axis least aligned with x, crossed.
      const Vec3 axis = std::abs(x.x) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
      n = normalized(cross(x, axis));
    }
    fr.x[f] = x;
    fr.normal[f] = n;
    fr.y[f] = cross(n, x);
  });
  fr.rho = HalfedgeData<double>(mesh.num_halfedges(), 0.0);
  tbb::parallel_for(uint32_t(0), mesh.num_halfedges(), [&](uint32_t h) {
    const uint32_t tw = mesh.twin(h);
    if (tw == kInvalid || tw < h) return;  // each edge once: the twin gets exactly -rho
    const Vec3 d = mesh.position(mesh.to(h)) - mesh.position(mesh.from(h));
    const uint32_t f = TriMesh::face_of(h), g = TriMesh::face_of(tw);
    fr.rho[h] = wrap_angle(fr.arg(g, d) - fr.arg(f, d), 2 * std::numbers::pi);
    fr.rho[tw] = -fr.rho[h];
  });
  return fr;
}

}  // namespace isoquad
