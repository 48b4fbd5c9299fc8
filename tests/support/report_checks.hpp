// Checks of a report folder (report/report.hpp): every file it lists exists and is what its name
// says: a PNG whose chunks are all there (signature, IHDR with a non-empty size, IEND at the
// end), an SVG document, JSON, and an HTML page that shows the quad count.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

namespace isoquad::test {

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline uint32_t big_endian32(const std::string& s, std::size_t at) {
  return uint32_t(uint8_t(s[at])) << 24 | uint32_t(uint8_t(s[at + 1])) << 16 |
         uint32_t(uint8_t(s[at + 2])) << 8 | uint32_t(uint8_t(s[at + 3]));
}

// Walks the PNG's chunks: each length must stay inside the file, the first is IHDR and the
// last IEND.
inline void expect_valid_png(const std::filesystem::path& p) {
  const std::string s = slurp(p);
  ASSERT_GT(s.size(), 8u + 25u + 12u) << p;
  ASSERT_EQ(s.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << p;
  ASSERT_EQ(s.substr(12, 4), "IHDR") << p;
  EXPECT_GT(big_endian32(s, 16), 0u) << p;  // width
  EXPECT_GT(big_endian32(s, 20), 0u) << p;  // height
  std::size_t at = 8;
  std::string last;
  while (at + 12 <= s.size()) {
    const uint32_t length = big_endian32(s, at);
    last = s.substr(at + 4, 4);
    at += 12 + std::size_t(length);
  }
  EXPECT_EQ(at, s.size()) << p << ": chunks do not end at the end of the file";
  EXPECT_EQ(last, "IEND") << p;
}

inline void expect_valid_svg(const std::filesystem::path& p) {
  const std::string s = slurp(p);
  EXPECT_EQ(s.rfind("<?xml", 0), 0u) << p;
  EXPECT_NE(s.find("<svg"), std::string::npos) << p;
  EXPECT_NE(s.find("</svg>"), std::string::npos) << p;
}

// Checks every file report.json lists; returns report.json.
inline nlohmann::json expect_valid_report(const std::filesystem::path& dir) {
  const nlohmann::json report = nlohmann::json::parse(slurp(dir / "report.json"));
  EXPECT_TRUE(report.contains("quality"));
  EXPECT_TRUE(report.contains("options"));
  for (const char* name : {"input.png", "patches.png", "contours.png", "quads.png", "layout.svg",
                           "weights.png", "report.json", "index.html"}) {
    bool listed = false;
    for (const auto& f : report.at("files")) listed |= f.get<std::string>() == name;
    EXPECT_TRUE(listed) << name;
  }
  for (const auto& f : report.at("files")) {
    const std::string name = f.get<std::string>();
    const std::filesystem::path p = dir / name;
    EXPECT_TRUE(std::filesystem::is_regular_file(p)) << p;
    if (name.ends_with(".png")) expect_valid_png(p);
    if (name.ends_with(".svg")) expect_valid_svg(p);
  }
  const std::string html = slurp(dir / "index.html");
  EXPECT_NE(html.find("<span id=\"quads\">" + report.at("quads").dump() + "</span>"),
            std::string::npos);
  return report;
}

}  // namespace isoquad::test
