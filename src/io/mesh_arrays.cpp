#include "io/mesh_arrays.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "io/read_mesh.hpp"
#include "io/write_mesh.hpp"
#include "isoquad/error.hpp"
#include "isoquad/io.hpp"

namespace isoquad {

PolyMesh poly_mesh_from_arrays(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  if (V.cols() != 3 || F.cols() < 3)
    throw Error(ErrorKind::invalid_input, "E020",
                fmt::format("V must be #V x 3 and F #F x 3 (or #F x k polygons padded with -1; "
                            "got {} x {} and {} x {})",
                            V.rows(), V.cols(), F.rows(), F.cols()));
  PolyMesh m;
  m.positions.resize(std::size_t(V.rows()));
  for (Eigen::Index i = 0; i < V.rows(); ++i) m.positions[i] = {V(i, 0), V(i, 1), V(i, 2)};
  std::vector<uint32_t> face;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    ErrorContext where;
    where.faces = {uint32_t(f)};
    face.clear();
    for (Eigen::Index k = 0; k < F.cols() && F(f, k) != -1; ++k) {
      if (F(f, k) < 0 || F(f, k) >= V.rows())
        throw Error(
            ErrorKind::invalid_input, "E020",
            fmt::format("face {} refers to vertex {}, but V has {} rows", f, F(f, k), V.rows()),
            where);
      face.push_back(uint32_t(F(f, k)));
    }
    if (face.size() < 3)
      throw Error(ErrorKind::invalid_input, "E020",
                  fmt::format("face {} has {} vertices before its first -1", f, face.size()),
                  where);
    m.add_face(face);
  }
  return m;
}

void arrays_from_poly_mesh(const PolyMesh& mesh, Eigen::MatrixXd& V, Eigen::MatrixXi& F) {
  V.resize(Eigen::Index(mesh.num_vertices()), 3);
  for (std::size_t i = 0; i < mesh.num_vertices(); ++i)
    V.row(Eigen::Index(i)) << mesh.positions[i].x, mesh.positions[i].y, mesh.positions[i].z;
  std::size_t k = 3;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) k = std::max(k, mesh.face(f).size());
  F.setConstant(Eigen::Index(mesh.num_faces()), Eigen::Index(k), -1);
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const auto face = mesh.face(f);
    for (std::size_t c = 0; c < face.size(); ++c)
      F(Eigen::Index(f), Eigen::Index(c)) = int(face[c]);
  }
}

MeshArrays read_mesh_arrays(const std::string& path, bool drop_degenerate_faces) {
  const ReadResult read = read_mesh(path, {.drop_degenerate_faces = drop_degenerate_faces});
  MeshArrays out;
  arrays_from_poly_mesh(read.mesh, out.V, out.F);
  out.unshared_vertices = read.unshared_vertices;
  return out;
}

void write_mesh_arrays(const std::string& path, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                       const Eigen::VectorXi& group) {
  PolyMesh m = poly_mesh_from_arrays(V, F);
  if (group.size() != 0 && group.size() != F.rows())
    throw Error(
        ErrorKind::invalid_input, "E020",
        fmt::format("group must have one entry per face ({}), not {}", F.rows(), group.size()));
  m.face_group.assign(group.data(), group.data() + group.size());
  write_mesh(path, m);
}

}  // namespace isoquad
