// Connected regions of faces: the one flood fill of the code base. Two faces sharing halfedge h
// are connected iff h has a twin and connects(h) holds; faces outside `in` (when given) get
// kInvalid. Regions are numbered 0.. in order of their smallest face. Returns the count.
#pragma once

#include <vector>

#include "core/tri_mesh.hpp"

namespace isoquad {

template <class Connects, class Inside>
uint32_t face_regions(const TriMesh& m, Connects&& connects, Inside&& in,
                      std::vector<uint32_t>& region) {
  region.assign(m.num_faces(), kInvalid);
  uint32_t count = 0;
  std::vector<uint32_t> stack;
  for (uint32_t f0 = 0; f0 < m.num_faces(); ++f0) {
    if (region[f0] != kInvalid || !in(f0)) continue;
    region[f0] = count;
    stack.assign(1, f0);
    while (!stack.empty()) {
      const uint32_t f = stack.back();
      stack.pop_back();
      for (uint32_t i = 0; i < 3; ++i) {
        const uint32_t h = 3 * f + i;
        if (m.twin(h) == kInvalid || !connects(h)) continue;
        const uint32_t g = TriMesh::face_of(m.twin(h));
        if (region[g] == kInvalid && in(g)) {
          region[g] = count;
          stack.push_back(g);
        }
      }
    }
    ++count;
  }
  return count;
}

template <class Connects>
uint32_t face_regions(const TriMesh& m, Connects&& connects, std::vector<uint32_t>& region) {
  return face_regions(
      m, connects, [](uint32_t) { return true; }, region);
}

}  // namespace isoquad
