// Seed corpora for the fuzz targets: every mesh given, written in every format and encoding a
// reader takes (OBJ, OFF, PLY ascii and binary, STL ascii and binary), cut to its first faces
// until the file fits the fuzzers' -max_len, so that each seed reaches preparation whole.
//   make_seeds OUT_DIR MAX_BYTES MESH...   writes OUT_DIR/<format>/<mesh>[_binary].<format>
#include <fmt/format.h>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unordered_map>

#include "io/read_mesh.hpp"
#include "io/write_mesh.hpp"
#include "isoquad/error.hpp"

namespace fs = std::filesystem;
using namespace isoquad;

namespace {

// The first `faces` faces and the vertices they use, renumbered in order of first use.
PolyMesh first_faces(const PolyMesh& m, std::size_t faces) {
  PolyMesh out;
  std::unordered_map<uint32_t, uint32_t> renumber;
  std::vector<uint32_t> face;
  for (std::size_t f = 0; f < faces; ++f) {
    face.clear();
    for (uint32_t v : m.face(f)) {
      const auto [it, added] = renumber.emplace(v, uint32_t(out.positions.size()));
      if (added) out.positions.push_back(m.positions[v]);
      face.push_back(it->second);
    }
    out.add_face(face);
  }
  return out;
}

// STL has no writer in the library (remesh never writes triangles): polygons as fans, each
// triangle with its own three vertices, the normal left zero as many exporters leave it.
std::string write_stl(const PolyMesh& m, bool binary) {
  std::vector<std::array<Vec3, 3>> tris;
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    const auto face = m.face(f);
    for (std::size_t k = 1; k + 1 < face.size(); ++k)
      tris.push_back({m.positions[face[0]], m.positions[face[k]], m.positions[face[k + 1]]});
  }
  std::string s;
  if (!binary) {
    s = "solid seed\n";
    for (const auto& t : tris) {
      s += "facet normal 0 0 0\nouter loop\n";
      for (const Vec3& p : t) s += fmt::format("vertex {} {} {}\n", p.x, p.y, p.z);
      s += "endloop\nendfacet\n";
    }
    return s + "endsolid seed\n";
  }
  s.assign(80, ' ');
  auto put = [&s](auto v) {
    char b[sizeof v];
    std::memcpy(b, &v, sizeof v);  // little endian, as the reader assumes
    s.append(b, sizeof v);
  };
  put(uint32_t(tris.size()));
  for (const auto& t : tris) {
    for (int k = 0; k < 3; ++k) put(0.f);
    for (const Vec3& p : t)
      for (int k = 0; k < 3; ++k) put(float(p[k]));
    put(uint16_t(0));
  }
  return s;
}

std::string write(const PolyMesh& m, MeshFormat format, bool binary) {
  if (format == MeshFormat::stl) return write_stl(m, binary);
  std::ostringstream out;
  write_mesh(out, m, format, {.ply_binary = binary});
  return out.str();
}

// Halves the face count until the file fits in max_bytes.
void write_seed(const PolyMesh& m, MeshFormat format, bool binary, const fs::path& path,
                std::size_t max_bytes) {
  for (std::size_t faces = m.num_faces(); faces > 0; faces /= 2) {
    const std::string bytes =
        write(faces == m.num_faces() ? m : first_faces(m, faces), format, binary);
    if (bytes.size() > max_bytes) continue;
    std::ofstream(path, std::ios::binary) << bytes;
    return;
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t max_bytes = 0;
  if (argc < 4 ||
      std::from_chars(argv[2], argv[2] + std::strlen(argv[2]), max_bytes).ec != std::errc()) {
    std::fprintf(stderr, "usage: make_seeds OUT_DIR MAX_BYTES MESH...\n");
    return 2;
  }
  const fs::path out = argv[1];
  try {
    for (int i = 3; i < argc; ++i) {
      const PolyMesh mesh = read_mesh(argv[i]).mesh;
      const std::string stem = fs::path(argv[i]).stem().string();
      for (MeshFormat format :
           {MeshFormat::obj, MeshFormat::off, MeshFormat::ply, MeshFormat::stl}) {
        const std::string ext(to_string(format));
        fs::create_directories(out / ext);
        write_seed(mesh, format, false, out / ext / (stem + "." + ext), max_bytes);
        if (format == MeshFormat::ply || format == MeshFormat::stl)
          write_seed(mesh, format, true, out / ext / (stem + "_binary." + ext), max_bytes);
      }
    }
  } catch (const Error& e) {
    std::fprintf(stderr, "make_seeds: %s\n", e.what());
    return 1;
  }
  return 0;
}
