#include "core/z_order.hpp"

#include <algorithm>
#include <utility>

namespace isoquad {

std::vector<uint32_t> z_order(const std::vector<Vec3>& points) {
  Box3 box;
  for (const Vec3& p : points) box.add(p);
  const Vec3 extent = box.hi - box.lo;
  const double size = std::max({extent.x, extent.y, extent.z});
  auto spread = [](uint64_t x) {  // 21 bits to every third bit of 63
    x &= 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffffULL;
    x = (x | x << 16) & 0x1f0000ff0000ffULL;
    x = (x | x << 8) & 0x100f00f00f00f00fULL;
    x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
    x = (x | x << 2) & 0x1249249249249249ULL;
    return x;
  };
  auto cell = [&](double v, double lo) {
    return size > 0 ? uint64_t(std::clamp((v - lo) / size, 0.0, 1.0) * 2097151.0) : uint64_t(0);
  };
  std::vector<std::pair<uint64_t, uint32_t>> key(points.size());
  for (uint32_t i = 0; i < points.size(); ++i) {
    const Vec3& p = points[i];
    key[i] = {spread(cell(p.x, box.lo.x)) | spread(cell(p.y, box.lo.y)) << 1 |
                  spread(cell(p.z, box.lo.z)) << 2,
              i};
  }
  std::sort(key.begin(), key.end());
  std::vector<uint32_t> order(points.size());
  for (uint32_t i = 0; i < points.size(); ++i) order[i] = key[i].second;
  return order;
}

}  // namespace isoquad
