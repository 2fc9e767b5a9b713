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
// fraction of the scene's size.
double contact_tolerance(const std::vector<Surface>& surfaces);

// For each surface, the segments (endpoints within `tolerance` of its plane,
// not yet clipped to its region) where another surface meets its front:
// edges of the other surface lying on the plane where that surface leaves
// the plane towards the front, and the lines where it crosses the plane. A
// surface lying flat on the plane (a light drawn on its ceiling) adds none. Empty
// for curved surfaces.
std::vector<std::vector<Segment3>> find_contact_lines(const std::vector<Surface>& surfaces, double tolerance);

}  // namespace lhr
