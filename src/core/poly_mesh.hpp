// A polygon mesh as plain arrays: what the readers return (a "soup": nothing is checked beyond
// index ranges) and what the quad extraction produces. Faces are stored CSR-style.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/vec.hpp"

namespace isoquad {

struct PolyMesh {
  std::vector<Vec3> positions;
  std::vector<uint32_t> face_offsets{
      0};  // face f is face_vertices[face_offsets[f] .. face_offsets[f+1])
  std::vector<uint32_t> face_vertices;
  std::vector<int32_t> face_group;  // optional per-face group (patch id); empty or one per face
  std::vector<std::array<uint8_t, 3>> face_color;  // optional per-face RGB; empty or one per face

  std::size_t num_vertices() const { return positions.size(); }
  std::size_t num_faces() const { return face_offsets.size() - 1; }
  std::span<const uint32_t> face(std::size_t f) const {
    return {face_vertices.data() + face_offsets[f], face_offsets[f + 1] - face_offsets[f]};
  }
  void add_face(std::span<const uint32_t> vertices) {
    face_vertices.insert(face_vertices.end(), vertices.begin(), vertices.end());
    face_offsets.push_back(static_cast<uint32_t>(face_vertices.size()));
  }
  void add_face(std::initializer_list<uint32_t> vertices) {
    add_face(std::span<const uint32_t>(vertices.begin(), vertices.size()));
  }
  bool all_faces_have(std::size_t n) const {
    for (std::size_t f = 0; f < num_faces(); ++f)
      if (face(f).size() != n) return false;
    return true;
  }
};

}  // namespace isoquad
