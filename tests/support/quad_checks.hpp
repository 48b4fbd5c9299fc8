// What every output must be, whatever else a test asks of it: pure quads, edge- and
// vertex-manifold, consistently oriented, of the input's topology (the report's reference).
#pragma once

#include <gtest/gtest.h>

#include "metrics/quality.hpp"

namespace isoquad::test {

inline void expect_valid_quad_mesh(const QualityReport& q) {
  EXPECT_TRUE(q.pure_quad);
  EXPECT_TRUE(q.edge_manifold);
  EXPECT_TRUE(q.vertex_manifold);
  EXPECT_TRUE(q.oriented);
  EXPECT_TRUE(q.same_topology) << "chi " << q.topology.euler << ", " << q.topology.boundary_loops
                               << " boundary loops, " << q.topology.components << " components";
}

}  // namespace isoquad::test
