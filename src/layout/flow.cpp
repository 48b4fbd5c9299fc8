#include "layout/flow.hpp"

#include <lemon/network_simplex.h>
#include <lemon/smart_graph.h>
#include <chrono>
#include <cmath>

namespace isoquad {

namespace {
struct Entry {
  uint32_t row;
  int sign;
};
std::vector<std::vector<Entry>> columns(uint32_t n, const std::vector<SideRow>& rows) {
  std::vector<std::vector<Entry>> cols(n);
  for (uint32_t r = 0; r < rows.size(); ++r)
    for (const auto& [e, s] : rows[r]) cols[e].push_back({r, s});
  return cols;
}
}  // namespace

std::optional<std::vector<int>> network_signs(uint32_t n, const std::vector<SideRow>& rows) {
  const auto cols = columns(n, rows);
  // Column e in rows r1, r2 with coefficients a1, a2 needs sigma_r1 a1 = -sigma_r2 a2.
  std::vector<std::vector<std::pair<uint32_t, int>>> adj(rows.size());
  for (const auto& c : cols) {
    if (c.size() > 2) return std::nullopt;
    if (c.size() == 2) {
      const int product = -c[0].sign * c[1].sign;  // required sigma_r1 * sigma_r2
      adj[c[0].row].push_back({c[1].row, product});
      adj[c[1].row].push_back({c[0].row, product});
    }
  }
  std::vector<int> sigma(rows.size(), 0);
  std::vector<uint32_t> stack;
  for (uint32_t r0 = 0; r0 < rows.size(); ++r0) {
    if (sigma[r0]) continue;
    sigma[r0] = 1;
    stack.assign(1, r0);
    while (!stack.empty()) {
      const uint32_t r = stack.back();
      stack.pop_back();
      for (const auto& [s, product] : adj[r]) {
        if (!sigma[s]) {
          sigma[s] = sigma[r] * product;
          stack.push_back(s);
        } else if (sigma[s] != sigma[r] * product) {
          return std::nullopt;  // an odd cycle: not a network matrix
        }
      }
    }
  }
  return sigma;
}

std::optional<Lengths> solve_lengths_flow(const std::vector<double>& c,
                                          const std::vector<SideRow>& rows) {
  const auto t0 = std::chrono::steady_clock::now();
  const uint32_t n = uint32_t(c.size());
  const auto sigma = network_signs(n, rows);
  if (!sigma) return std::nullopt;
  const auto cols = columns(n, rows);
  using Graph = lemon::SmartDigraph;
  Graph g;
  std::vector<Graph::Node> node;
  for (uint32_t r = 0; r < rows.size(); ++r) node.push_back(g.addNode());
  const Graph::Node boundary = g.addNode();  // the other end of meta-edges on one side only
  Graph::ArcMap<int64_t> lower(g), upper(g), cost(g);
  // Costs in integers (LEMON's simplex wants them exact): weights scaled by 1e6.
  constexpr double kScale = 1e6;
  constexpr int64_t kInfinite = int64_t(1) << 40;
  std::vector<std::vector<Graph::Arc>> arcs(n);
  for (uint32_t e = 0; e < n; ++e) {
    Graph::Node tail = boundary, head = boundary;
    for (const Entry& en : cols[e]) (sigma->at(en.row) * en.sign > 0 ? head : tail) = node[en.row];
    if (cols[e].empty()) continue;  // on no side (cannot happen in a layout): stays 1
    // The convex piecewise-linear cost d(x, c) (quantize.hpp) in units: a mandatory first unit,
    // then one arc per stretch of integers where d is linear, and the stretching slope above.
    auto add = [&](int64_t lo, int64_t hi, double unit_cost) {
      const Graph::Arc a = g.addArc(tail, head);
      lower[a] = lo, upper[a] = hi, cost[a] = std::llround(unit_cost * kScale);
      arcs[e].push_back(a);
    };
    add(1, 1, 0);
    std::vector<int64_t> knots = {1};
    double at = c[e];
    for (const CostSegment& s : shrink_segments(c[e]))
      knots.push_back(int64_t(std::llround(at -= s.length)));
    knots.push_back(int64_t(std::ceil(c[e])));
    std::sort(knots.begin(), knots.end());
    knots.erase(std::unique(knots.begin(), knots.end()), knots.end());
    for (std::size_t k = 0; k + 1 < knots.size(); ++k) {
      const double a = double(knots[k]), b = double(knots[k + 1]);
      add(0, knots[k + 1] - knots[k], (length_cost(b, c[e]) - length_cost(a, c[e])) / (b - a));
    }
    add(0, kInfinite, stretch_slope(c[e]));
  }
  lemon::NetworkSimplex<Graph, int64_t, int64_t> simplex(g);
  simplex.lowerMap(lower).upperMap(upper).costMap(cost);
  if (simplex.run() != lemon::NetworkSimplex<Graph, int64_t, int64_t>::OPTIMAL) return std::nullopt;
  Lengths out;
  out.solver = "flow";
  out.optimal = true;
  out.x.assign(n, 1);
  for (uint32_t e = 0; e < n; ++e) {
    if (arcs[e].empty()) continue;
    int64_t x = 0;
    for (const auto& a : arcs[e]) x += simplex.flow(a);
    out.x[e] = x;
    out.objective += length_cost(double(x), c[e]);
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace isoquad
