// Corpus meshes for the benchmarks: read and prepared once per process, outside the timing.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

#include "io/read_mesh.hpp"
#include "prep/prepare.hpp"

namespace isoquad::bench {

inline std::filesystem::path corpus_path(const char* name) {
  const char* dir = std::getenv("ISOQUAD_CORPUS_DIR");
  return std::filesystem::path(dir ? dir : ISOQUAD_SOURCE_DIR "/corpus") / name;
}

// The first component of a prepared corpus mesh; nullptr when the corpus is missing.
inline const PreparedComponent* corpus_component(const char* name) {
  static std::map<std::string, PreparedMesh> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    const auto path = corpus_path(name);
    if (!std::filesystem::exists(path)) return nullptr;
    it = cache.emplace(name, prepare(read_mesh(path).mesh)).first;
  }
  return &it->second.components.at(0);
}

inline constexpr const char* kMissing = "corpus missing: run scripts/get-corpus";

}  // namespace isoquad::bench
