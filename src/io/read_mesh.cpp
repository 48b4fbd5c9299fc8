#include "io/read_mesh.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <fstream>
#include <system_error>

#include "io/parse_util.hpp"

namespace isoquad {

std::string_view to_string(MeshFormat format) {
  switch (format) {
    case MeshFormat::obj: return "obj";
    case MeshFormat::off: return "off";
    case MeshFormat::ply: return "ply";
    case MeshFormat::stl: return "stl";
  }
  return "?";
}

namespace {

std::string read_bytes(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    io::fail_at_line(name, -1, io::kUnreadable, "is a directory, not a mesh file");
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    ErrorContext ctx;
    ctx.file = name;
    const bool exists = std::filesystem::exists(path, ec);
    throw Error(ErrorKind::invalid_input, io::kUnreadable,
                exists ? "cannot be opened (permission denied?)" : "no such file", ctx);
  }
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) io::fail_at_line(name, -1, io::kUnreadable, "read error");
  return bytes;
}

bool format_from_extension(const std::filesystem::path& path, MeshFormat& out) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".obj") out = MeshFormat::obj;
  else if (ext == ".off") out = MeshFormat::off;
  else if (ext == ".ply") out = MeshFormat::ply;
  else if (ext == ".stl") out = MeshFormat::stl;
  else return false;
  return true;
}

bool format_from_content(std::string_view bytes, MeshFormat& out) {
  const std::size_t first = bytes.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos) return false;
  const std::string_view head = bytes.substr(first, 16);
  if (head.starts_with("ply")) out = MeshFormat::ply;
  else if (head.starts_with("solid") || (bytes.size() >= 84 && bytes.find('\0') < 84))
    out = MeshFormat::stl;
  else if (head.find("OFF") != std::string_view::npos && head.find("OFF") < 5) out = MeshFormat::off;
  else if (head.starts_with("v ") || head.starts_with("#") || head.starts_with("o ") ||
           head.starts_with("mtllib") || head.starts_with("g "))
    out = MeshFormat::obj;
  else return false;
  return true;
}

}  // namespace

ReadResult read_mesh_from_memory(std::string_view bytes, MeshFormat format, const std::string& name,
                                 const ReadOptions& options) {
  if (bytes.find_first_not_of(" \t\r\n") == std::string_view::npos)
    io::fail_at_line(name, -1, io::kEmpty, "the file is empty");
  ReadResult r;
  switch (format) {
    case MeshFormat::obj: r = io::read_obj(bytes, name, options); break;
    case MeshFormat::off: r = io::read_off(bytes, name, options); break;
    case MeshFormat::ply: r = io::read_ply(bytes, name, options); break;
    case MeshFormat::stl: r = io::read_stl(bytes, name, options); break;
  }
  if (r.mesh.num_faces() == 0)
    io::fail_at_line(name, -1, io::kEmpty,
                     r.dropped_faces ? fmt::format("no face is left after dropping {} degenerate faces",
                                                   r.dropped_faces)
                                     : std::string("the file has no faces"));
  return r;
}

ReadResult read_mesh(const std::filesystem::path& path, const ReadOptions& options) {
  const std::string bytes = read_bytes(path);
  MeshFormat format;
  if (!format_from_extension(path, format) && !format_from_content(bytes, format))
    io::fail_at_line(path.string(), -1, io::kUnknownFormat,
                     "unknown mesh format (expected .obj, .off, .ply or .stl)");
  return read_mesh_from_memory(bytes, format, path.string(), options);
}

}  // namespace isoquad
