// Points on the base surface found by walking over it: the closest surface point to a nearby
// position, by descent from a known face. A global closest-point search could jump to another
// sheet in thin parts (fingers, ears, the knot's close strands); a walk from the vertex's own
// face cannot.
#pragma once

#include <array>
#include <cstdint>

#include "core/refined_mesh.hpp"
#include "core/tri_mesh.hpp"
#include "core/vec.hpp"

namespace isoquad {

// Barycentric coordinates of q (in the plane of a, b, c), clamped to be nonnegative.
std::array<double, 3> barycentric(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c);

// The closest point to p on the faces reached by descent over vertex-adjacent faces from
// `start` (ties broken by the smaller face id, so the result is deterministic).
SurfacePoint project_locally(const TriMesh& base, uint32_t start, const Vec3& p);

Vec3 position_of(const TriMesh& base, const SurfacePoint& s);

// Unit normal of a base face.
Vec3 face_normal(const TriMesh& base, uint32_t f);

}  // namespace isoquad
