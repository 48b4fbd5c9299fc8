// Mesh readers: OBJ, OFF, PLY (ascii, binary little and big endian) and STL (ascii, binary),
// all in double precision. Every malformed file gets an isoquad::Error naming the file, the
// line (text) or byte offset (binary) and what is wrong; nothing is skipped silently.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "core/poly_mesh.hpp"

namespace isoquad {

enum class MeshFormat { obj, off, ply, stl };
std::string_view to_string(MeshFormat format);

struct ReadOptions {
  // Faces with fewer than 3 distinct vertices are an error (E014) unless this is set, in which
  // case they are dropped and counted (the command line's --repair).
  bool drop_degenerate_faces = false;
};

struct ReadResult {
  PolyMesh mesh;  // faces as in the file (polygons allowed), 0-based indices, all in range
  MeshFormat format = MeshFormat::obj;
  bool binary = false;
  uint32_t dropped_faces = 0;      // faces with < 3 distinct vertices (only with the option)
  bool unshared_vertices = false;  // STL: every face has its own vertices; weld everything
};

// Picks the format from the extension (case-insensitive), or from the content when the
// extension is unknown.
// \throw Error(invalid_input): E001 unreadable, E002 unknown format, E010..E016 malformed.
ReadResult read_mesh(const std::filesystem::path& path, const ReadOptions& options = {});

// The same, from bytes in memory; `name` is used in messages.
ReadResult read_mesh_from_memory(std::string_view bytes, MeshFormat format, const std::string& name,
                                 const ReadOptions& options = {});

}  // namespace isoquad
