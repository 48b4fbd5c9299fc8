// PLY (ascii, binary_little_endian, binary_big_endian). Vertex x, y, z of any numeric type; the
// face list `vertex_indices` (or `vertex_index`); every other element and property is skipped
// with its exact size, so unknown properties never shift the data.
#include <fmt/format.h>
#include <bit>
#include <cstring>

#include "io/parse_util.hpp"

namespace isoquad::io {

namespace {

enum class Scalar { i8, u8, i16, u16, i32, u32, f32, f64 };

bool parse_scalar(std::string_view s, Scalar& out) {
  static const std::pair<std::string_view, Scalar> kNames[] = {
      {"char", Scalar::i8},    {"int8", Scalar::i8},     {"uchar", Scalar::u8},
      {"uint8", Scalar::u8},   {"short", Scalar::i16},   {"int16", Scalar::i16},
      {"ushort", Scalar::u16}, {"uint16", Scalar::u16},  {"int", Scalar::i32},
      {"int32", Scalar::i32},  {"uint", Scalar::u32},    {"uint32", Scalar::u32},
      {"float", Scalar::f32},  {"float32", Scalar::f32}, {"double", Scalar::f64},
      {"float64", Scalar::f64}};
  for (const auto& [name, type] : kNames)
    if (s == name) {
      out = type;
      return true;
    }
  return false;
}

std::size_t scalar_size(Scalar s) {
  switch (s) {
    case Scalar::i8:
    case Scalar::u8:
      return 1;
    case Scalar::i16:
    case Scalar::u16:
      return 2;
    case Scalar::i32:
    case Scalar::u32:
    case Scalar::f32:
      return 4;
    case Scalar::f64:
      return 8;
  }
  return 0;
}

struct Property {
  std::string name;
  Scalar type = Scalar::f32;
  bool is_list = false;
  Scalar count_type = Scalar::u8;
};

struct Element {
  std::string name;
  int64_t count = 0;
  std::vector<Property> properties;
  int64_t header_line = 0;
};

enum class Encoding { ascii, little, big };

// Reads scalars from the binary body with bounds checks and byte-order conversion.
class BinaryCursor {
 public:
  BinaryCursor(std::string_view bytes, std::size_t pos, bool big_endian, const std::string& file)
      : bytes_(bytes),
        pos_(pos),
        swap_(big_endian != (std::endian::native == std::endian::big)),
        file_(file) {}

  double read(Scalar type, std::string_view what) {
    const std::size_t n = scalar_size(type);
    if (pos_ + n > bytes_.size())
      fail_at_byte(file_, int64_t(pos_), kTruncated,
                   fmt::format("the file ends inside {} ({} of {} bytes present)", what,
                               bytes_.size() - pos_, n));
    unsigned char raw[8];
    std::memcpy(raw, bytes_.data() + pos_, n);
    if (swap_)
      for (std::size_t i = 0; i < n / 2; ++i) std::swap(raw[i], raw[n - 1 - i]);
    pos_ += n;
    switch (type) {
      case Scalar::i8: {
        int8_t v;
        std::memcpy(&v, raw, 1);
        return v;
      }
      case Scalar::u8:
        return raw[0];
      case Scalar::i16: {
        int16_t v;
        std::memcpy(&v, raw, 2);
        return v;
      }
      case Scalar::u16: {
        uint16_t v;
        std::memcpy(&v, raw, 2);
        return v;
      }
      case Scalar::i32: {
        int32_t v;
        std::memcpy(&v, raw, 4);
        return v;
      }
      case Scalar::u32: {
        uint32_t v;
        std::memcpy(&v, raw, 4);
        return v;
      }
      case Scalar::f32: {
        float v;
        std::memcpy(&v, raw, 4);
        return v;
      }
      case Scalar::f64: {
        double v;
        std::memcpy(&v, raw, 8);
        return v;
      }
    }
    return 0;
  }
  std::size_t pos() const { return pos_; }

 private:
  std::string_view bytes_;
  std::size_t pos_;
  bool swap_;
  const std::string& file_;
};

struct Header {
  Encoding encoding = Encoding::ascii;
  std::vector<Element> elements;
  std::size_t body_offset = 0;
  int64_t body_line = 0;
};

Header parse_header(std::string_view bytes, const std::string& file) {
  Header h;
  TextCursor cur(bytes, file);
  if (!cur.next_line(false)) fail_at_line(file, 1, kEmpty, "empty file");
  std::string_view tok;
  cur.next_token(tok);
  if (tok != "ply") cur.fail(kSyntax, fmt::format("expected 'ply' but found '{}'", tok));
  bool have_format = false;
  while (true) {
    if (!cur.next_line(false)) cur.fail(kTruncated, "the header has no 'end_header' line");
    cur.next_token(tok);
    if (tok == "end_header") break;
    if (tok == "comment" || tok == "obj_info") continue;
    if (tok == "format") {
      const std::string_view enc = cur.expect_token("the encoding");
      if (enc == "ascii")
        h.encoding = Encoding::ascii;
      else if (enc == "binary_little_endian")
        h.encoding = Encoding::little;
      else if (enc == "binary_big_endian")
        h.encoding = Encoding::big;
      else
        cur.fail(kUnknownFormat, fmt::format("unknown PLY format '{}'", enc));
      have_format = true;
    } else if (tok == "element") {
      Element e;
      e.name = std::string(cur.expect_token("the element name"));
      e.count = cur.parse_int(cur.expect_token("the element count"), "element count");
      if (e.count < 0) cur.fail(kSyntax, "negative element count");
      e.header_line = cur.line_number();
      h.elements.push_back(std::move(e));
    } else if (tok == "property") {
      if (h.elements.empty()) cur.fail(kSyntax, "property before any element");
      Property p;
      std::string_view type = cur.expect_token("the property type");
      if (type == "list") {
        p.is_list = true;
        if (!parse_scalar(cur.expect_token("the list count type"), p.count_type))
          cur.fail(kSyntax, "unknown list count type");
        type = cur.expect_token("the list item type");
      }
      if (!parse_scalar(type, p.type))
        cur.fail(kSyntax, fmt::format("unknown property type '{}'", type));
      p.name = std::string(cur.expect_token("the property name"));
      h.elements.back().properties.push_back(std::move(p));
    } else {
      cur.fail(kSyntax, fmt::format("unknown header keyword '{}'", tok));
    }
  }
  if (!have_format) cur.fail(kSyntax, "the header has no 'format' line");
  h.body_offset = cur.offset();
  h.body_line = cur.line_number();
  return h;
}

// Reads element instances from either encoding through one interface.
class BodyReader {
 public:
  BodyReader(std::string_view bytes, const Header& h, const std::string& file)
      : ascii_(h.encoding == Encoding::ascii),
        text_(bytes.substr(h.body_offset), file),
        bin_(bytes, h.body_offset, h.encoding == Encoding::big, file),
        file_(file),
        body_line_(h.body_line) {}

  void begin_instance(const Element& e, int64_t i) {
    if (!ascii_) return;
    if (!text_.next_line(false))
      fail_at_line(file_, body_line_ + text_.line_number(), kCountMismatch,
                   fmt::format("the header declares {} '{}' elements but the file ends after {}",
                               e.count, e.name, i));
  }
  double value(Scalar type, std::string_view what) {
    if (!ascii_) return bin_.read(type, what);
    std::string_view tok;
    if (!text_.next_token(tok))
      fail_at_line(file_, line(), kSyntax, fmt::format("the line ends before {}", what));
    std::string_view t = tok;
    double v = 0;
    const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec != std::errc() || ptr != t.data() + t.size())
      fail_at_line(file_, line(), kSyntax, fmt::format("{} '{}' is not a number", what, tok));
    return v;
  }
  bool ascii() const { return ascii_; }
  int64_t line() const { return body_line_ + text_.line_number(); }
  std::size_t byte() const { return bin_.pos(); }
  bool trailing_data() { return ascii_ ? text_.next_line(false) : false; }

 private:
  bool ascii_;
  TextCursor text_;
  BinaryCursor bin_;
  const std::string& file_;
  int64_t body_line_;
};

// The fewest bytes one binary instance of `e` takes: its scalars and list counts (a list may
// be empty).
std::size_t min_binary_bytes(const Element& e) {
  std::size_t n = 0;
  for (const Property& p : e.properties) n += scalar_size(p.is_list ? p.count_type : p.type);
  return n;
}

// Rejects binary element counts the body cannot hold before anything is read or allocated: a
// corrupt header ("element vertex 4000000000") fails at once, naming the element, instead of
// reserving gigabytes or looping over instances without bytes. (An ascii instance takes a line
// each, so there the count is checked line by line, E015.)
void check_binary_counts(const Header& h, std::size_t body_bytes, const std::string& file) {
  std::size_t left = body_bytes;
  for (const Element& e : h.elements) {
    const std::size_t per = min_binary_bytes(e);
    if (per == 0) continue;  // no properties: instances without bytes
    if (uint64_t(e.count) > left / per)
      fail_at_line(file, e.header_line, kTruncated,
                   fmt::format("the header declares {} '{}' elements of {} bytes or more, but "
                               "only {} bytes follow the header",
                               e.count, e.name, per, body_bytes));
    left -= std::size_t(e.count) * per;
  }
}

// A list count as an integer; past what the file's bytes can hold (each item takes one at
// least) it is corrupt, and converting it would overflow.
template <class Fail>
int64_t list_count(double n, std::size_t file_bytes, Fail&& where) {
  if (!(n >= 0) || n != std::floor(n)) where(kSyntax, fmt::format("invalid list count {}", n));
  if (n > double(file_bytes))
    where(kCountMismatch,
          fmt::format("list count {} is more than the file's {} bytes can hold", n, file_bytes));
  return int64_t(n);
}

}  // namespace

ReadResult read_ply(std::string_view bytes, const std::string& file, const ReadOptions& options) {
  ReadResult result;
  result.format = MeshFormat::ply;
  const Header h = parse_header(bytes, file);
  result.binary = h.encoding != Encoding::ascii;
  if (result.binary) check_binary_counts(h, bytes.size() - h.body_offset, file);
  BodyReader body(bytes, h, file);
  auto where = [&](const char* code, const std::string& msg) {
    if (body.ascii()) fail_at_line(file, body.line(), code, msg);
    fail_at_byte(file, int64_t(body.byte()), code, msg);
  };
  FaceChecker faces{options, result, {}};
  std::vector<int64_t> idx;
  bool have_vertices = false;
  for (const Element& e : h.elements) {
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    int xyz[3] = {-1, -1, -1};
    int list = -1;
    for (int k = 0; k < int(e.properties.size()); ++k) {
      const Property& p = e.properties[k];
      if (is_vertex && !p.is_list && p.name.size() == 1 && p.name[0] >= 'x' && p.name[0] <= 'z')
        xyz[p.name[0] - 'x'] = k;
      if (is_face && p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index"))
        list = k;
    }
    if (is_vertex) {
      if (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0)
        fail_at_line(file, e.header_line, kSyntax,
                     "the vertex element lacks an x, y or z property");
      if (!faces.result.mesh.positions.empty())
        fail_at_line(file, e.header_line, kSyntax, "more than one vertex element");
      have_vertices = true;
      result.mesh.positions.reserve(
          std::size_t(std::min<int64_t>(e.count, int64_t(bytes.size() / 3))));
    }
    if (is_face && list < 0)
      fail_at_line(file, e.header_line, kSyntax, "the face element has no 'vertex_indices' list");
    if (is_face && !have_vertices)
      fail_at_line(file, e.header_line, kSyntax,
                   "the face element comes before the vertex element");
    if (result.binary && min_binary_bytes(e) == 0) continue;  // nothing to read, however many
    for (int64_t i = 0; i < e.count; ++i) {
      body.begin_instance(e, i);
      Vec3 p;
      idx.clear();
      for (int k = 0; k < int(e.properties.size()); ++k) {
        const Property& prop = e.properties[k];
        if (!prop.is_list) {
          const double v = body.value(prop.type, prop.name);
          for (int c = 0; c < 3; ++c)
            if (k == xyz[c]) p[c] = v;
          continue;
        }
        const int64_t n =
            list_count(body.value(prop.count_type, "a list count"), bytes.size(), where);
        for (int64_t j = 0; j < n; ++j) {
          const double v = body.value(prop.type, prop.name);
          if (k == list) {
            if (v != std::floor(v))
              where(kSyntax, fmt::format("vertex index {} is not an integer", v));
            // Beyond 2^53 no count reaches it, and beyond 2^63 the conversion would overflow.
            if (std::fabs(v) > 0x1p53)
              where(kIndexRange,
                    fmt::format("face references vertex {} but the file has {} vertices", v,
                                result.mesh.num_vertices()));
            idx.push_back(int64_t(v));
          }
        }
      }
      if (is_vertex) add_vertex(result.mesh, p, where);
      if (is_face) {
        if (idx.size() < 3)
          where(kDegenerateFace,
                fmt::format("face {} has {} vertices; a face needs at least 3", i, idx.size()));
        faces.add(idx, where);
      }
    }
  }
  if (body.trailing_data())
    fail_at_line(file, body.line(), kCountMismatch, "unexpected data after the declared elements");
  if (!body.ascii() && body.byte() != bytes.size())
    fail_at_byte(file, int64_t(body.byte()), kCountMismatch,
                 fmt::format("{} bytes follow the declared elements", bytes.size() - body.byte()));
  return result;
}

}  // namespace isoquad::io
