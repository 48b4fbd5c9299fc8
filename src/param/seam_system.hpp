// The linear system of the seamless map (DESIGN.md §7.1-7.3, §7.6): one unknown uv per free
// vertex in its home chart, the weighted-average equations per face in the face's chart, seam
// weights per mesh edge and locked meta-edges whose vertices sit on the straight side. The
// sparsity pattern does not depend on the weights or on which meta-edges are locked (locked rows
// become identity rows with explicit zeros), so the symbolic factorization is done once and
// every later solve is one numeric factorization. Eigen and SuiteSparse stay in the .cpp.
#pragma once

#include <memory>
#include <vector>

#include "param/param.hpp"

namespace isoquad {

class SeamSystem {
 public:
  // `rank`: an elimination rank per vertex (ordering.hpp) that numbers the unknowns, which are
  // then factored in that order; null: the unknowns in vertex order, ordered by CHOLMOD (METIS
  // from 60,000 rows on, else AMD).
  SeamSystem(const TriMesh& mesh, const FaceData<uint32_t>& labels, const MetaMesh& meta,
             const Layout& layout, WeightKind weights, const std::vector<uint32_t>* rank = nullptr);
  ~SeamSystem();
  SeamSystem(const SeamSystem&) = delete;
  SeamSystem& operator=(const SeamSystem&) = delete;

  // Meta-edges that are straight whatever the relaxation: mesh-boundary and feature meta-edges.
  const std::vector<char>& always_locked() const;
  // Meta-edge of each seam mesh edge (an edge on a meta-edge), kInvalid elsewhere.
  const EdgeData<uint32_t>& edge_meta_edge() const;
  uint32_t unknowns() const;

  // Solves with seam weights `stiffness` (per mesh edge; 1 off the seams) and the meta-edges
  // with locked[e] != 0 held straight (chord-length positions on their lattice segment).
  ParamMap solve(const EdgeData<double>& stiffness, const std::vector<char>& locked,
                 ParamReport& report);

  // The same with every meta-edge locked, as a scalar system of its own (the patches decouple).
  // Const: it may run while solve() runs on another thread, with its own report.
  ParamMap solve_locked(ParamReport& report) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace isoquad
