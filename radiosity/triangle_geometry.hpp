#pragma once
// Point–triangle geometry the refinement oracles need.

#include <array>

#include "mesh/types.hpp"

namespace lhr {

// The point of triangle t (its interior, edges or corners) nearest to p.
Vec3 closest_point(const Vec3& p, const std::array<Vec3, 3>& t);

}  // namespace lhr
