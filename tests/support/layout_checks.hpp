// Independent checks of a layout: facing sides equal, every length >= 1, transitions map both
// ends of every meta-edge, quarter turns as the corners say.
#pragma once

#include <gtest/gtest.h>

#include "layout/corners.hpp"
#include "layout/layout.hpp"

namespace isoquad::test {

inline void expect_valid_layout(const MetaMesh& meta, const Layout& layout) {
  ASSERT_EQ(layout.charts.size(), meta.faces.size());
  for (uint32_t p = 0; p < meta.faces.size(); ++p) {
    const Chart& c = layout.charts[p];
    int64_t side[4] = {0, 0, 0, 0};
    for (uint32_t i = 0; i < meta.faces[p].cycle.size(); ++i)
      side[c.item_side[i]] += layout.length[meta.faces[p].cycle[i].edge];
    EXPECT_EQ(side[0], side[2]) << "patch " << p;
    EXPECT_EQ(side[1], side[3]) << "patch " << p;
    EXPECT_EQ(c.width, side[0]);
    EXPECT_EQ(c.height, side[1]);
  }
  std::vector<std::array<uint32_t, 4>> corners;
  for (const Chart& c : layout.charts) corners.push_back(c.corners);
  std::vector<std::array<uint32_t, 4>> sorted = corners;
  for (auto& s : sorted) std::sort(s.begin(), s.end());
  EXPECT_EQ(quarter_turns(meta, sorted), layout.quarter_turns);
  for (uint32_t e = 0; e < meta.edges.size(); ++e) {
    EXPECT_GE(layout.length[e], 1);
    const MetaEdge& me = meta.edges[e];
    if (me.right == kInvalid) continue;
    auto ends = [&](uint32_t p) {
      const MetaFace& f = meta.faces[p];
      for (uint32_t i = 0; i < f.cycle.size(); ++i)
        if (f.cycle[i].edge == e) {
          const Lattice a = layout.charts[p].item_position[i],
                        b = layout.charts[p].item_position[(i + 1) % f.cycle.size()];
          return f.cycle[i].forward ? std::pair{a, b} : std::pair{b, a};
        }
      return std::pair{Lattice{}, Lattice{}};
    };
    const auto [a0, a1] = ends(me.left);
    const auto [b0, b1] = ends(me.right);
    EXPECT_EQ(layout.transition[e].apply(a0), b0) << "meta-edge " << e;
    EXPECT_EQ(layout.transition[e].apply(a1), b1) << "meta-edge " << e;
  }
}

}  // namespace isoquad::test
