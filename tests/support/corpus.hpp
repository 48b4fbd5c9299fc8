// Access to the real-mesh corpus (scripts/get-corpus). Tests that need a corpus mesh skip when
// the corpus is absent, and fail instead when ISOQUAD_REQUIRE_CORPUS is set (as in CI), so a
// missing corpus can never make CI pass quietly.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <gtest/gtest.h>
#include <string>

namespace isoquad::test {

inline std::filesystem::path corpus_dir() {
  if (const char* d = std::getenv("ISOQUAD_CORPUS_DIR")) return d;
  return std::filesystem::path(ISOQUAD_SOURCE_DIR) / "corpus";
}

inline std::filesystem::path data_dir() { return std::filesystem::path(ISOQUAD_SOURCE_DIR) / "data"; }

// Path of a corpus mesh; empty (after recording a skip or a failure) when it is missing.
inline std::filesystem::path corpus_mesh(const std::string& name) {
  const auto p = corpus_dir() / name;
  if (std::filesystem::exists(p)) return p;
  return {};
}

#define ISOQUAD_CORPUS_MESH(var, name)                                                          \
  const std::filesystem::path var = ::isoquad::test::corpus_mesh(name);                       \
  if (var.empty()) {                                                                          \
    if (std::getenv("ISOQUAD_REQUIRE_CORPUS")) FAIL() << "corpus mesh missing: " << (name);  \
    GTEST_SKIP() << "corpus mesh missing (run scripts/get-corpus): " << (name);               \
  }

}  // namespace isoquad::test
