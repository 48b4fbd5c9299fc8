// Mesh files as plain arrays, for callers of isoquad::remesh (isoquad/remesh.hpp): the readers
// and writers of the command line (OBJ, OFF, PLY, STL in; OBJ, OFF, PLY out) without the
// library's internal mesh types.
//
//   isoquad::MeshArrays in = isoquad::read_mesh_arrays("bunny.off");
//   isoquad::RemeshResult r = isoquad::remesh(in.V, in.F, {.weld_all = in.unshared_vertices});
//   isoquad::write_mesh_arrays("bunny_quads.obj", r.V, r.Q, r.patch);
#pragma once

#include <Eigen/Core>
#include <string>

namespace isoquad {

struct MeshArrays {
  Eigen::MatrixXd V;  // #V x 3 positions
  // #F x k vertex indices (0-based), k the largest face size; a face with fewer corners is
  // padded with -1 after its last one (a triangle mesh is #F x 3, a quad mesh #F x 4).
  Eigen::MatrixXi F;
  // STL: every face has its own vertices; remesh welds them when RemeshOptions::weld_all is set
  // (as `isoquad remesh` does for STL files).
  bool unshared_vertices = false;
};

// Format from the extension (case-insensitive), else from the content. With
// `drop_degenerate_faces` (the command line's --repair), faces with fewer than 3 distinct
// vertices are dropped instead of refused.
// \throw Error(invalid_input): E001 unreadable, E002 unknown format, E010..E016 malformed.
MeshArrays read_mesh_arrays(const std::string& path, bool drop_degenerate_faces = false);

// Format from the extension (.obj, .off, .ply, binary PLY); written atomically, coordinates in
// their shortest round-trip form. `group` (one per face, or empty), e.g. RemeshResult::patch, is
// written as OBJ groups `g patch_N` and as the PLY face property `patch`. Rows of F end at their
// first -1.
// \throw Error(invalid_input): E002 unknown extension, E001 not writable, E020 wrong shapes or
//        an index out of range.
void write_mesh_arrays(const std::string& path, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                       const Eigen::VectorXi& group = {});

}  // namespace isoquad
