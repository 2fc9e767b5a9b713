#pragma once
// Point–triangle geometry shared by the refinement oracles and the path tracer.

#include <array>

#include "mesh/types.hpp"

namespace lhr {

// The point of triangle t (its interior, edges or corners) nearest to p.
Vec3 closest_point(const Vec3& p, const std::array<Vec3, 3>& t);

}  // namespace lhr
