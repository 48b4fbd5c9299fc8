#include "param/ordering.hpp"

#include <fmt/format.h>

#include <cholmod.h>
#include <algorithm>
#include <numeric>

#include "isoquad/error.hpp"

namespace isoquad {

std::vector<uint32_t> nested_dissection_ranks(const TriMesh& mesh) {
  const uint32_t nv = mesh.num_vertices();
  std::vector<uint32_t> rank(nv);
  if (nv < 2) {
    std::iota(rank.begin(), rank.end(), 0u);
    return rank;
  }
  // The lower triangle of the adjacency pattern, column by column (rows sorted).
  std::vector<std::vector<int>> below(nv);
  for (uint32_t e = 0; e < mesh.num_edges(); ++e) {
    const uint32_t h = mesh.edge_halfedge(e);
    const uint32_t a = std::min(mesh.from(h), mesh.to(h)), b = std::max(mesh.from(h), mesh.to(h));
    below[a].push_back(int(b));
  }
  cholmod_common c;
  cholmod_start(&c);
  c.print = 0;
  cholmod_sparse* A =
      cholmod_allocate_sparse(nv, nv, 2 * std::size_t(mesh.num_edges()) + nv,
                              /*sorted=*/1, /*packed=*/1, /*stype=*/-1, CHOLMOD_PATTERN, &c);
  std::vector<int> perm(nv);
  bool ok = A != nullptr;
  if (ok) {
    int* col = static_cast<int*>(A->p);
    int* row = static_cast<int*>(A->i);
    int k = 0;
    for (uint32_t v = 0; v < nv; ++v) {
      col[v] = k;
      auto& rows = below[v];
      std::sort(rows.begin(), rows.end());
      row[k++] = int(v);  // the diagonal
      for (const int r : rows) row[k++] = r;
    }
    col[nv] = k;
    ok = cholmod_metis(A, nullptr, 0, /*postorder=*/1, perm.data(), &c) != 0;
    cholmod_free_sparse(&A, &c);
  }
  cholmod_finish(&c);
  if (!ok)
    throw Error(ErrorKind::solver, "E551",
                fmt::format("the nested dissection of the {}-vertex graph failed", nv));
  for (uint32_t k = 0; k < nv; ++k) rank[uint32_t(perm[k])] = k;
  return rank;
}

std::vector<uint32_t> extend_ranks(const TriMesh& refined,
                                   const std::vector<uint32_t>& base_ranks) {
  const uint32_t nv = refined.num_vertices(), nb = uint32_t(base_ranks.size());
  // A sort key per vertex: twice the base rank, and one more for a new vertex placed after the
  // neighbour it takes its rank from; new vertices next to new vertices only are settled in
  // rounds, from those nearest the base vertices.
  std::vector<uint64_t> key(nv, UINT64_MAX);
  for (uint32_t v = 0; v < std::min(nv, nb); ++v) key[v] = 2 * uint64_t(base_ranks[v]);
  for (bool changed = true; changed;) {
    changed = false;
    for (uint32_t v = nb; v < nv; ++v) {
      if (key[v] != UINT64_MAX) continue;
      uint64_t best = 0;
      bool any = false;
      refined.for_each_outgoing(v, [&](uint32_t h) {
        const uint32_t w = refined.to(h);
        if (key[w] != UINT64_MAX) best = std::max(best, key[w] | 1), any = true;
      });
      if (any) key[v] = best, changed = true;
    }
  }
  std::vector<uint32_t> order(nv);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return key[a] < key[b]; });
  std::vector<uint32_t> rank(nv);
  for (uint32_t k = 0; k < nv; ++k) rank[order[k]] = k;
  return rank;
}

}  // namespace isoquad
