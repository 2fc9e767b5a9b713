#pragma once
// Where one surface touches or passes through a planar surface: the lines
// across which the planar surface's radiance jumps (a box standing on a
// floor is dark beneath and lit beside). The initial mesh keeps them as
// edges, so that no element straddles one; see docs/accuracy.md, "Contact
// lines".

#include <array>
#include <vector>

#include "mesh/scene.hpp"
#include "mesh/types.hpp"

namespace lhr {

using Segment3 = std::array<Vec3, 2>;

// Distance from a plane below which a point counts as lying on it: a
// fraction of the scene's size, above the offset that puts a light drawn on
// its ceiling in front of it (mesh/surfaces.hpp), so that the light's
// outline is found on the ceiling.
double contact_tolerance(const std::vector<Surface>& surfaces);

// For each surface, the segments (endpoints within `tolerance` of its plane,
// not yet clipped to its region) where another surface meets its front:
// edges of the other surface lying on the plane where that surface leaves
// the plane towards the front, or where it lies flat on the plane facing
// the same way (its outline); and the lines where the other surface crosses
// the plane. Empty
// for curved surfaces.
std::vector<std::vector<Segment3>> find_contact_lines(const std::vector<Surface>& surfaces, double tolerance);

}  // namespace lhr
