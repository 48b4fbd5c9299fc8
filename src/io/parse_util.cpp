#include "io/parse_util.hpp"

#include <fmt/format.h>
#include <algorithm>

namespace isoquad::io {

void fail_at_line(const std::string& file, int64_t line, const char* code,
                  const std::string& message, std::initializer_list<uint32_t> faces) {
  ErrorContext ctx;
  ctx.file = file;
  ctx.line = line;
  ctx.faces = faces;
  throw Error(ErrorKind::invalid_input, code, message, std::move(ctx));
}

void fail_at_byte(const std::string& file, int64_t offset, const char* code,
                  const std::string& message) {
  ErrorContext ctx;
  ctx.file = file;
  ctx.byte_offset = offset;
  throw Error(ErrorKind::invalid_input, code, message, std::move(ctx));
}

bool TextCursor::next_line(bool strip_comments) {
  while (next_ < text_.size()) {
    const std::size_t end = text_.find('\n', next_);
    const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
    line_ = text_.substr(next_, stop - next_);
    next_ = stop + (end == std::string_view::npos ? 0 : 1);
    ++line_no_;
    if (strip_comments) {
      const std::size_t hash = line_.find('#');
      if (hash != std::string_view::npos) line_ = line_.substr(0, hash);
    }
    pos_ = 0;
    if (line_.find_first_not_of(" \t\r\f\v") != std::string_view::npos) return true;
  }
  line_ = {};
  pos_ = 0;
  return false;
}

bool TextCursor::next_token(std::string_view& token) {
  const std::size_t begin = line_.find_first_not_of(" \t\r\f\v", pos_);
  if (begin == std::string_view::npos) {
    pos_ = line_.size();
    return false;
  }
  std::size_t end = line_.find_first_of(" \t\r\f\v", begin);
  if (end == std::string_view::npos) end = line_.size();
  token = line_.substr(begin, end - begin);
  pos_ = end;
  return true;
}

std::string_view TextCursor::expect_token(std::string_view what) {
  std::string_view token;
  if (!next_token(token)) fail(kSyntax, fmt::format("expected {} but the line ends", what));
  return token;
}

double TextCursor::parse_double(std::string_view token, std::string_view what) const {
  std::string_view t = token;
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  double value = 0;
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
  if (ec == std::errc::result_out_of_range)
    fail(kNonFinite, fmt::format("{} '{}' is out of the range of a double", what, token));
  if (ec != std::errc() || ptr != t.data() + t.size())
    fail(kSyntax, fmt::format("{} '{}' is not a number", what, token));
  if (!std::isfinite(value))
    fail(kNonFinite, fmt::format("{} is '{}' (NaN or infinite)", what, token));
  return value;
}

int64_t TextCursor::parse_int(std::string_view token, std::string_view what) const {
  std::string_view t = token;
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  int64_t value = 0;
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
  if (ec != std::errc() || ptr != t.data() + t.size())
    fail(kSyntax, fmt::format("{} '{}' is not an integer", what, token));
  return value;
}

bool FaceChecker::distinct(const std::vector<uint32_t>& v) {
  if (v.size() < 3) return false;
  if (v.size() <= 8) {
    for (std::size_t i = 0; i < v.size(); ++i)
      for (std::size_t j = i + 1; j < v.size(); ++j)
        if (v[i] == v[j]) return false;
    return true;
  }
  std::vector<uint32_t> s(v);
  std::sort(s.begin(), s.end());
  return std::adjacent_find(s.begin(), s.end()) == s.end();
}

}  // namespace isoquad::io
