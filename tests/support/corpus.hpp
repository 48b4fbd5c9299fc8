// Access to the real-mesh corpus (scripts/get-corpus). Tests that need a corpus mesh skip when
// the corpus is absent, and fail instead when ISOQUAD_REQUIRE_CORPUS is set (as in CI), so a
// missing corpus can never make CI pass quietly.
#pragma once

#include <gtest/gtest.h>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace isoquad::test {

inline std::filesystem::path corpus_dir() {
  if (const char* d = std::getenv("ISOQUAD_CORPUS_DIR")) return d;
  return std::filesystem::path(ISOQUAD_SOURCE_DIR) / "corpus";
}

// The corpus (bench/corpus.txt), for tests parameterized over every mesh.
inline constexpr const char* kCorpusMeshes[] = {"sphere.off",
                                                "cactus.off",
                                                "hand.off",
                                                "cow.off",
                                                "fandisk.off",
                                                "bunny00.off",
                                                "armadillo.off",
                                                "double-torus-example.off",
                                                "eight.off",
                                                "knot1.off",
                                                "rotor.off",
                                                "elephant.off",
                                                "anchor.off",
                                                "mesh_with_border.off",
                                                "nefertiti.off",
                                                "mushroom.off",
                                                "mech-holes-shark.off",
                                                "three_peaks.off",
                                                "cylinder.off"};

// A test name from a corpus file name and a patch count (0: automatic).
inline std::string corpus_case_name(const std::string& file, uint32_t patches) {
  std::string n = file.substr(0, file.find('.'));
  for (char& ch : n)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return n + (patches ? "_K" + std::to_string(patches) : std::string("_Kauto"));
}

inline std::filesystem::path data_dir() {
  return std::filesystem::path(ISOQUAD_SOURCE_DIR) / "data";
}

// Path of a corpus mesh; empty (after recording a skip or a failure) when it is missing.
inline std::filesystem::path corpus_mesh(const std::string& name) {
  const auto p = corpus_dir() / name;
  if (std::filesystem::exists(p)) return p;
  return {};
}

#define ISOQUAD_CORPUS_MESH(var, name)                                                      \
  const std::filesystem::path var = ::isoquad::test::corpus_mesh(name);                     \
  if (var.empty()) {                                                                        \
    if (std::getenv("ISOQUAD_REQUIRE_CORPUS")) FAIL() << "corpus mesh missing: " << (name); \
    GTEST_SKIP() << "corpus mesh missing (run scripts/get-corpus): " << (name);             \
  }

}  // namespace isoquad::test
