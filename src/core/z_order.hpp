#pragma once

#include <cstdint>
#include <vector>

#include "core/vec.hpp"

namespace isoquad {

// The points' indices in Z-curve (Morton) order of a 2^21-cell grid over their bounding box,
// ties by index. Work that visits neighbouring points one after another in this order touches
// the same memory: input files often list faces in no spatial order.
std::vector<uint32_t> z_order(const std::vector<Vec3>& points);

}  // namespace isoquad
