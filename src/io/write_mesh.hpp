// Mesh writers for OBJ, OFF and PLY. Files are written atomically: to a temporary file in the
// target's folder, then renamed over the target, so a failed run never leaves a truncated file.
// Coordinates are written in their shortest round-trip form: reading them back is bit-exact.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>

#include "core/poly_mesh.hpp"
#include "io/read_mesh.hpp"

namespace isoquad {

struct WriteOptions {
  bool ply_binary = true;  // binary little endian PLY (ascii otherwise)
};

// Format from the extension (.obj, .off, .ply). Per-face groups are written as OBJ groups
// (`g patch_N`) and as the PLY face property `patch`.
// \throw Error(invalid_input, E002) for an unknown extension, Error(invalid_input, E001) when
// the file cannot be written.
void write_mesh(const std::filesystem::path& path, const PolyMesh& mesh,
                const WriteOptions& options = {});
void write_mesh(std::ostream& out, const PolyMesh& mesh, MeshFormat format,
                const WriteOptions& options = {});

// What write_mesh and write_file_atomically would refuse, checked before any work (a remesh of
// seconds should not end on a path it cannot write): `path` is not a folder and its folder exists
// and is writable (else E001); for check_mesh_output, also a writable mesh format (E002).
// \throw Error(invalid_input) as above.
void check_output_path(const std::filesystem::path& path);
void check_mesh_output(const std::filesystem::path& path);
// For a folder to be created (with its parents) and written: the nearest existing one of it
// and its ancestors is a writable folder.
void check_output_folder(const std::filesystem::path& folder);

// Writes through `fill` into a temporary file, then renames it to `path`. The one atomic-write
// helper (reports and pictures use it too).
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& fill, bool binary = false);

}  // namespace isoquad
