#include <gtest/gtest.h>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/read_mesh.hpp"
#include "io/write_mesh.hpp"
#include "isoquad/error.hpp"
#include "shapes.hpp"

using namespace isoquad;

namespace {

// A mesh whose coordinates need all 15-17 significant digits, plus extreme magnitudes.
PolyMesh precise_mesh() {
  PolyMesh m;
  m.positions = {{0.123456789012345, -1.2345678901234567e8, 1e-300},
                 {0.1, 0.2, 0.30000000000000004},
                 {-7.000000000000001, 3.141592653589793, 2.718281828459045},
                 {1e300, -4.9406564584124654e-324, 123456.78901234567}};
  m.add_face({0, 1, 2});
  m.add_face({0, 2, 3, 1});
  return m;
}

PolyMesh round_trip(const PolyMesh& m, MeshFormat format, bool binary) {
  std::ostringstream out;
  write_mesh(out, m, format, {.ply_binary = binary});
  return read_mesh_from_memory(out.str(), format, "memory").mesh;
}

void expect_identical(const PolyMesh& a, const PolyMesh& b) {
  ASSERT_EQ(a.num_vertices(), b.num_vertices());
  for (std::size_t i = 0; i < a.num_vertices(); ++i)
    for (int k = 0; k < 3; ++k) {  // bit-exact, not approximately equal
      const double x = a.positions[i][k], y = b.positions[i][k];
      EXPECT_EQ(std::memcmp(&x, &y, 8), 0)
          << "vertex " << i << " coordinate " << k << ": " << x << " vs " << y;
    }
  EXPECT_EQ(a.face_offsets, b.face_offsets);
  EXPECT_EQ(a.face_vertices, b.face_vertices);
}

std::string code_of(std::string_view bytes, MeshFormat format, ReadOptions options = {}) {
  try {
    read_mesh_from_memory(bytes, format, "bad", options);
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::invalid_input);
    return e.code();
  }
  return "no error";
}

std::string message_of(std::string_view bytes, MeshFormat format) {
  try {
    read_mesh_from_memory(bytes, format, "bad.mesh");
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

template <class T>
void put(std::string& s, T v, bool big = false) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof v);
  if (big) std::reverse(b, b + sizeof v);
  s.append(b, sizeof v);
}

std::string binary_stl(const std::vector<std::array<float, 9>>& tris, int declared = -1) {
  std::string s(80, ' ');
  put<uint32_t>(s, declared < 0 ? uint32_t(tris.size()) : uint32_t(declared));
  for (const auto& t : tris) {
    for (int k = 0; k < 3; ++k) put<float>(s, 0.f);
    for (float f : t) put<float>(s, f);
    put<uint16_t>(s, 0);
  }
  return s;
}

}  // namespace

TEST(IO, RoundTripIsBitExactInEveryFormat) {
  const PolyMesh m = precise_mesh();
  expect_identical(m, round_trip(m, MeshFormat::obj, false));
  expect_identical(m, round_trip(m, MeshFormat::off, false));
  expect_identical(m, round_trip(m, MeshFormat::ply, false));
  expect_identical(m, round_trip(m, MeshFormat::ply, true));
}

TEST(IO, DoublePrecisionCoordinateSurvivesObjFile) {
  const auto path = std::filesystem::temp_directory_path() / "isoquad_precision.obj";
  PolyMesh m;
  m.positions = {{0.123456789012345, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.add_face({0, 1, 2});
  write_mesh(path, m);
  const ReadResult r = read_mesh(path);
  EXPECT_EQ(r.mesh.positions[0].x, 0.123456789012345);
  std::filesystem::remove(path);
}

TEST(IO, RoundTripKeepsFaceGroups) {
  PolyMesh m = test::cube_quads();
  m.face_group = {0, 0, 1, 1, 2, 5};
  for (bool binary : {false, true}) {
    std::ostringstream out;
    write_mesh(out, m, MeshFormat::ply, {.ply_binary = binary});
    EXPECT_NE(out.str().find("property int patch"), std::string::npos);
    expect_identical(m, read_mesh_from_memory(out.str(), MeshFormat::ply, "m").mesh);
  }
  std::ostringstream obj;
  write_mesh(obj, m, MeshFormat::obj);
  EXPECT_NE(obj.str().find("g patch_5"), std::string::npos);
}

TEST(IO, ObjFaceFormsNegativeIndicesAndPolygons) {
  const std::string obj =
      "# comment\nmtllib x.mtl\no thing\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 1.0\nvt 0 0\nvn 0 0 1\n"
      "g a\nusemtl m\ns off\nf 1/1/1 2/1/1 3/1/1\nf 1//1 3//1 4//1\nf -4/1 -2/1 -1/1\nf 1 2 3 4\n";
  const ReadResult r = read_mesh_from_memory(obj, MeshFormat::obj, "t.obj");
  ASSERT_EQ(r.mesh.num_vertices(), 4u);
  ASSERT_EQ(r.mesh.num_faces(), 4u);
  EXPECT_EQ(std::vector<uint32_t>(r.mesh.face(2).begin(), r.mesh.face(2).end()),
            (std::vector<uint32_t>{0, 2, 3}));
  EXPECT_EQ(r.mesh.face(3).size(), 4u);
}

TEST(IO, OffVariants) {
  // Counts on the header line, colours after coordinates and faces, comments, CRLF.
  const std::string off =
      "COFF 4 2 0\r\n# c\r\n0 0 0 255 0 0 255\r\n1 0 0 1 1 1 1\r\n1 1 0 0 0 0 0\r\n0 1 0 0 0 0 "
      "0\r\n"
      "3 0 1 2 255 0 0\r\n3 0 2 3\r\n";
  const ReadResult r = read_mesh_from_memory(off, MeshFormat::off, "t.off");
  EXPECT_EQ(r.mesh.num_vertices(), 4u);
  EXPECT_EQ(r.mesh.num_faces(), 2u);
  EXPECT_EQ(r.mesh.positions[2], (Vec3{1, 1, 0}));
}

TEST(IO, PlySkipsUnknownPropertiesAndElements) {
  const std::string ply =
      "ply\nformat ascii 1.0\ncomment x\nelement vertex 3\nproperty float nx\nproperty double x\n"
      "property double y\nproperty double z\nproperty uchar red\nelement face 1\n"
      "property list uchar float texcoord\nproperty list uchar int vertex_indices\nproperty int "
      "flags\n"
      "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n"
      "9 0 0 0 255\n9 1 0 0 255\n9 0 1 0 255\n2 0.5 0.5 3 0 1 2 7\n0 1\n";
  const ReadResult r = read_mesh_from_memory(ply, MeshFormat::ply, "t.ply");
  ASSERT_EQ(r.mesh.num_vertices(), 3u);
  EXPECT_EQ(r.mesh.positions[1], (Vec3{1, 0, 0}));
  ASSERT_EQ(r.mesh.num_faces(), 1u);
}

TEST(IO, PlyBigEndianBinary) {
  std::string ply =
      "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nproperty short extra\nelement face 1\nproperty list uchar uint "
      "vertex_indices\n"
      "end_header\n";
  const float xyz[3][3] = {{0.5f, 0, 0}, {1, 0, -2}, {0, 1, 0}};
  for (const auto& p : xyz) {
    for (float f : p) put<float>(ply, f, true);
    put<int16_t>(ply, 7, true);
  }
  put<uint8_t>(ply, 3);
  for (uint32_t i : {0u, 1u, 2u}) put<uint32_t>(ply, i, true);
  const ReadResult r = read_mesh_from_memory(ply, MeshFormat::ply, "t.ply");
  EXPECT_TRUE(r.binary);
  EXPECT_EQ(r.mesh.positions[1], (Vec3{1, 0, -2}));
  EXPECT_EQ(r.mesh.face(0)[2], 2u);
}

TEST(IO, StlAsciiAndBinary) {
  const std::string ascii =
      "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\n"
      "endfacet\nendsolid t\n";
  const ReadResult a = read_mesh_from_memory(ascii, MeshFormat::stl, "t.stl");
  EXPECT_TRUE(a.unshared_vertices);
  EXPECT_EQ(a.mesh.num_faces(), 1u);
  std::string bin = binary_stl({{0, 0, 0, 1, 0, 0, 0, 1, 0}, {1, 0, 0, 1, 1, 0, 0, 1, 0}});
  bin.replace(0, 5, "solid");  // exporters do this; the size decides
  const ReadResult b = read_mesh_from_memory(bin, MeshFormat::stl, "t.stl");
  EXPECT_TRUE(b.binary);
  EXPECT_EQ(b.mesh.num_faces(), 2u);
  EXPECT_EQ(b.mesh.num_vertices(), 6u);
}

struct Malformed {
  const char* name;
  MeshFormat format;
  std::string bytes;
  const char* code;
};

void PrintTo(const Malformed& m, std::ostream* os) { *os << m.name; }

class MalformedInput : public testing::TestWithParam<Malformed> {};

TEST_P(MalformedInput, GivesItsErrorCode) {
  EXPECT_EQ(code_of(GetParam().bytes, GetParam().format), GetParam().code);
}

const std::string kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
const std::string kPlyHead =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
    "end_header\n";

INSTANTIATE_TEST_SUITE_P(
    IO, MalformedInput,
    testing::Values(
        Malformed{"EmptyObj", MeshFormat::obj, "", "E016"},
        Malformed{"BlankOff", MeshFormat::off, " \n\n", "E016"},
        Malformed{"ObjNoFaces", MeshFormat::obj, kTriangle, "E016"},
        Malformed{"ObjMissingCoordinate", MeshFormat::obj, "v 1 2\n", "E010"},
        Malformed{"ObjNotANumber", MeshFormat::obj, "v 1 2 x3\n", "E010"},
        Malformed{"ObjNaN", MeshFormat::obj, "v nan 0 0\n", "E013"},
        Malformed{"ObjInfinite", MeshFormat::obj, "v 0 inf 0\n", "E013"},
        Malformed{"ObjOverflow", MeshFormat::obj, "v 0 0 1e999\n", "E013"},
        Malformed{"ObjIndexTooLarge", MeshFormat::obj, kTriangle + "f 1 2 4\n", "E012"},
        Malformed{"ObjIndexZero", MeshFormat::obj, kTriangle + "f 0 1 2\n", "E012"},
        Malformed{"ObjRelativeTooFar", MeshFormat::obj, kTriangle + "f -4 1 2\n", "E012"},
        Malformed{"ObjTwoVertexFace", MeshFormat::obj, kTriangle + "f 1 2\n", "E014"},
        Malformed{"ObjRepeatedVertex", MeshFormat::obj, kTriangle + "f 1 2 2\n", "E014"},
        Malformed{"ObjUnknownStatement", MeshFormat::obj, kTriangle + "fx 1 2 3\n", "E010"},
        Malformed{"OffBadHeader", MeshFormat::off, "OFX\n3 1 0\n", "E010"},
        Malformed{"OffBinary", MeshFormat::off, "OFF BINARY\n", "E002"},
        Malformed{"OffTooFewVertices", MeshFormat::off, "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n",
                  "E015"},
        Malformed{"OffTooFewFaces", MeshFormat::off, "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                  "E015"},
        Malformed{"OffTrailingData", MeshFormat::off,
                  "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n", "E015"},
        Malformed{"OffIndexRange", MeshFormat::off, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
                  "E012"},
        Malformed{"OffNegativeIndex", MeshFormat::off,
                  "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", "E012"},
        Malformed{"OffDegenerateFace", MeshFormat::off,
                  "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 1\n", "E014"},
        Malformed{"OffNaN", MeshFormat::off, "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n",
                  "E013"},
        Malformed{"PlyUnknownFormat", MeshFormat::ply,
                  "ply\nformat binary_middle_endian 1.0\nend_header\n", "E002"},
        Malformed{"PlyNoEndHeader", MeshFormat::ply, "ply\nformat ascii 1.0\nelement vertex 3\n",
                  "E011"},
        Malformed{"PlyNoXYZ", MeshFormat::ply,
                  "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n",
                  "E010"},
        Malformed{"PlyTooFewVertices", MeshFormat::ply, kPlyHead + "0 0 0\n1 0 0\n", "E015"},
        Malformed{"PlyIndexRange", MeshFormat::ply, kPlyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
                  "E012"},
        Malformed{"PlyTruncatedBinary", MeshFormat::ply,
                  "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                  "property float y\nproperty float z\nend_header\n" +
                      std::string(20, '\0'),
                  "E011"},
        // Found by fuzzing (fuzz/fuzz_ply): counts and indices past what the file can hold.
        Malformed{"PlyBinaryCountBeyondFile", MeshFormat::ply,
                  "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
                  "property float x\nproperty float y\nproperty float z\nend_header\n" +
                      std::string(36, '\0'),
                  "E011"},
        Malformed{"PlyHugeListCount", MeshFormat::ply,
                  "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                  "property float z\nelement face 1\nproperty list double int vertex_indices\n"
                  "end_header\n0 0 0\n1 0 0\n0 1 0\n1e300 0 1 2\n",
                  "E015"},
        Malformed{"PlyHugeVertexIndex", MeshFormat::ply,
                  "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                  "property float z\nelement face 1\nproperty list uchar double vertex_indices\n"
                  "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 -1e300\n",
                  "E012"},
        Malformed{"StlTruncatedBinary", MeshFormat::stl,
                  binary_stl({{0, 0, 0, 1, 0, 0, 0, 1, 0}}, 2), "E011"},
        Malformed{"StlShortHeader", MeshFormat::stl, std::string(40, '\1'), "E011"},
        Malformed{"StlAsciiNoEnd", MeshFormat::stl,
                  "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 "
                  "0\nendloop\nendfacet\n",
                  "E011"},
        Malformed{"StlAsciiBadVertex", MeshFormat::stl,
                  "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0\n", "E010"},
        Malformed{"StlBinaryNaN", MeshFormat::stl, binary_stl({{0, 0, 0, NAN, 0, 0, 0, 1, 0}}),
                  "E013"}),
    [](const testing::TestParamInfo<Malformed>& i) { return std::string(i.param.name); });

TEST(IO, MessagesNameFileAndLine) {
  EXPECT_NE(message_of(kTriangle + "f 1 2 4\n", MeshFormat::obj).find("bad.mesh:4:"),
            std::string::npos);
  EXPECT_NE(
      message_of("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", MeshFormat::off).find("bad.mesh:6:"),
      std::string::npos);
  EXPECT_NE(
      message_of(binary_stl({{0, 0, 0, 1, 0, 0, 0, 1, 0}}, 2), MeshFormat::stl).find("(byte 134)"),
      std::string::npos);
}

TEST(IO, PlyCountBeyondFileNamesTheElementBeforeAllocating) {
  const std::string ply =
      "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 4000000000\nproperty list uchar int vertex_indices\n"
      "end_header\n" +
      std::string(36, '\0');
  const std::string message = message_of(ply, MeshFormat::ply);
  EXPECT_NE(message.find("bad.mesh:7:"), std::string::npos) << message;
  EXPECT_NE(message.find("4000000000 'face' elements"), std::string::npos) << message;
}

// A binary element without properties takes no bytes, however many it declares: skipped at
// once (looping over 9e18 instances of nothing was a hang the fuzzer found).
TEST(IO, PlyBinaryElementWithoutPropertiesIsSkipped) {
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement marker 9000000000000000000\n"
      "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) put<float>(ply, f);
  put<uint8_t>(ply, 3);
  for (int32_t i : {0, 1, 2}) put<int32_t>(ply, i);
  EXPECT_EQ(read_mesh_from_memory(ply, MeshFormat::ply, "t.ply").mesh.num_faces(), 1u);
}

TEST(IO, RepairDropsDegenerateFacesWithACount) {
  const ReadResult r = read_mesh_from_memory(kTriangle + "f 1 2 2\nf 1 2 3\n", MeshFormat::obj, "t",
                                             {.drop_degenerate_faces = true});
  EXPECT_EQ(r.dropped_faces, 1u);
  EXPECT_EQ(r.mesh.num_faces(), 1u);
}

TEST(IO, UnknownFormatAndMissingFile) {
  const auto dir = std::filesystem::temp_directory_path();
  EXPECT_EQ(code_of("", MeshFormat::obj), "E016");
  try {
    read_mesh(dir / "isoquad_no_such_file.obj");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), "E001");
  }
  const auto odd = dir / "isoquad_mesh.xyz";
  std::ofstream(odd) << "1 2 3\n";
  try {
    read_mesh(odd);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), "E002");
  }
  std::filesystem::remove(odd);
}

TEST(IO, WritesAtomically) {
  const auto dir = std::filesystem::temp_directory_path() / "isoquad_atomic";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const PolyMesh m = test::cube_quads();
  // Writing into a folder that does not exist fails and leaves nothing behind.
  EXPECT_THROW(write_mesh(dir / "missing" / "out.obj", m), Error);
  // A failure while writing keeps the previous file intact and removes the temporary file.
  write_mesh(dir / "out.obj", m);
  const auto before = std::filesystem::file_size(dir / "out.obj");
  EXPECT_THROW(write_file_atomically(dir / "out.obj",
                                     [](std::ostream& o) {
                                       o << "partial";
                                       throw Error(ErrorKind::internal, "E700", "boom");
                                     }),
               Error);
  EXPECT_EQ(std::filesystem::file_size(dir / "out.obj"), before);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1);
  EXPECT_THROW(write_mesh(dir / "out.stl", m), Error);
  std::filesystem::remove_all(dir);
}
