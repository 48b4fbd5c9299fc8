#include "io/write_mesh.hpp"

#include <fmt/format.h>
#include <unistd.h>
#include <algorithm>
#include <bit>
#include <charconv>
#include <fstream>

#include "isoquad/error.hpp"

namespace isoquad {

namespace {

[[noreturn]] void fail_write(const std::filesystem::path& path, const std::string& what) {
  ErrorContext ctx;
  ctx.file = path.string();
  throw Error(ErrorKind::invalid_input, "E001", what, ctx);
}

// Shortest representation that reads back to the same double.
void put_double(std::string& buf, double v) {
  char tmp[32];
  const auto r = std::to_chars(tmp, tmp + sizeof tmp, v);
  buf.append(tmp, r.ptr);
}

void put_uint(std::string& buf, uint64_t v) {
  char tmp[24];
  const auto r = std::to_chars(tmp, tmp + sizeof tmp, v);
  buf.append(tmp, r.ptr);
}

void put_vertices(std::string& buf, const PolyMesh& m, const char* prefix) {
  for (const Vec3& p : m.positions) {
    buf += prefix;
    put_double(buf, p.x);
    buf += ' ';
    put_double(buf, p.y);
    buf += ' ';
    put_double(buf, p.z);
    buf += '\n';
  }
}

void write_obj(std::ostream& out, const PolyMesh& m) {
  std::string buf = "# written by isoquad\n";
  put_vertices(buf, m, "v ");
  const bool groups = m.face_group.size() == m.num_faces();
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    if (groups && (f == 0 || m.face_group[f] != m.face_group[f - 1]))
      buf += fmt::format("g patch_{}\n", m.face_group[f]);
    buf += 'f';
    for (uint32_t v : m.face(f)) {
      buf += ' ';
      put_uint(buf, uint64_t(v) + 1);
    }
    buf += '\n';
  }
  out << buf;
}

void write_off(std::ostream& out, const PolyMesh& m) {
  std::string buf = fmt::format("OFF\n{} {} 0\n", m.num_vertices(), m.num_faces());
  put_vertices(buf, m, "");
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    put_uint(buf, m.face(f).size());
    for (uint32_t v : m.face(f)) {
      buf += ' ';
      put_uint(buf, v);
    }
    buf += '\n';
  }
  out << buf;
}

template <class T>
void put_le(std::string& buf, T v) {
  static_assert(std::endian::native == std::endian::little, "big-endian hosts are not supported");
  buf.append(reinterpret_cast<const char*>(&v), sizeof v);
}

void write_ply(std::ostream& out, const PolyMesh& m, bool binary) {
  const bool groups = m.face_group.size() == m.num_faces();
  const bool colors = m.face_color.size() == m.num_faces();
  std::size_t max_face = 0;
  for (std::size_t f = 0; f < m.num_faces(); ++f) max_face = std::max(max_face, m.face(f).size());
  const char* count_type = max_face < 256 ? "uchar" : "uint";
  std::string buf = fmt::format(
      "ply\nformat {} 1.0\ncomment written by isoquad\nelement vertex {}\nproperty double x\n"
      "property double y\nproperty double z\nelement face {}\nproperty list {} int "
      "vertex_indices\n",
      binary ? "binary_little_endian" : "ascii", m.num_vertices(), m.num_faces(), count_type);
  if (groups) buf += "property int patch\n";
  if (colors) buf += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  buf += "end_header\n";
  if (!binary) {
    put_vertices(buf, m, "");
    for (std::size_t f = 0; f < m.num_faces(); ++f) {
      put_uint(buf, m.face(f).size());
      for (uint32_t v : m.face(f)) {
        buf += ' ';
        put_uint(buf, v);
      }
      if (groups) buf += fmt::format(" {}", m.face_group[f]);
      if (colors)
        buf += fmt::format(" {} {} {}", m.face_color[f][0], m.face_color[f][1], m.face_color[f][2]);
      buf += '\n';
    }
  } else {
    for (const Vec3& p : m.positions) {
      put_le(buf, p.x);
      put_le(buf, p.y);
      put_le(buf, p.z);
    }
    for (std::size_t f = 0; f < m.num_faces(); ++f) {
      if (max_face < 256)
        put_le(buf, uint8_t(m.face(f).size()));
      else
        put_le(buf, uint32_t(m.face(f).size()));
      for (uint32_t v : m.face(f)) put_le(buf, int32_t(v));
      if (groups) put_le(buf, int32_t(m.face_group[f]));
      if (colors) buf.append(reinterpret_cast<const char*>(m.face_color[f].data()), 3);
    }
  }
  out << buf;
}

MeshFormat output_format(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (ext == ".obj") return MeshFormat::obj;
  if (ext == ".off") return MeshFormat::off;
  if (ext == ".ply") return MeshFormat::ply;
  ErrorContext ctx;
  ctx.file = path.string();
  throw Error(ErrorKind::invalid_input, "E002", "cannot write this format (use .obj, .off or .ply)",
              ctx);
}

}  // namespace

void write_mesh(std::ostream& out, const PolyMesh& mesh, MeshFormat format,
                const WriteOptions& options) {
  switch (format) {
    case MeshFormat::obj:
      write_obj(out, mesh);
      break;
    case MeshFormat::off:
      write_off(out, mesh);
      break;
    case MeshFormat::ply:
      write_ply(out, mesh, options.ply_binary);
      break;
    case MeshFormat::stl:
      throw Error(ErrorKind::invalid_input, "E002", "STL output is not supported");
  }
}

void write_mesh(const std::filesystem::path& path, const PolyMesh& mesh,
                const WriteOptions& options) {
  const MeshFormat format = output_format(path);
  write_file_atomically(
      path, [&](std::ostream& out) { write_mesh(out, mesh, format, options); },
      format == MeshFormat::ply && options.ply_binary);
}

void check_output_path(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) fail_write(path, "is a folder, not a file");
  const std::filesystem::path folder = path.has_parent_path() ? path.parent_path() : ".";
  if (!std::filesystem::is_directory(folder, ec))
    fail_write(path,
               fmt::format("cannot be written: the folder {} does not exist", folder.string()));
  if (::access(folder.c_str(), W_OK) != 0)
    fail_write(path,
               fmt::format("cannot be written: the folder {} is not writable", folder.string()));
}

void check_output_folder(const std::filesystem::path& folder) {
  std::error_code ec;
  std::filesystem::path existing = std::filesystem::absolute(folder, ec);
  while (!std::filesystem::exists(existing, ec) && existing.has_relative_path())
    existing = existing.parent_path();
  if (!std::filesystem::is_directory(existing, ec))
    fail_write(folder, fmt::format("cannot be created: {} is not a folder", existing.string()));
  if (::access(existing.c_str(), W_OK) != 0)
    fail_write(folder, fmt::format("cannot be created: {} is not writable", existing.string()));
}

void check_mesh_output(const std::filesystem::path& path) {
  output_format(path);
  check_output_path(path);
}

void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& fill, bool binary) {
  std::filesystem::path tmp = path;
  tmp += fmt::format(".tmp.{}", ::getpid());
  try {
    {
      std::ofstream out(tmp, binary ? std::ios::binary | std::ios::trunc : std::ios::trunc);
      if (!out) fail_write(path, "cannot be created (does the folder exist and is it writable?)");
      fill(out);
      out.flush();
      if (!out) fail_write(path, "write failed (disk full?)");
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) fail_write(path, "cannot replace the file: " + ec.message());
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw;
  }
}

}  // namespace isoquad
