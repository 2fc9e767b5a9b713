#pragma once
// Splitting a planar polygon into triangles: the path tracer builds its own
// Embree scene from the input polygons (docs/design.md §5 "Reference") and
// hands each one here projected onto its plane. In doubles: the tracer needs
// only a tiling of the polygon, not the exact predicates with which
// mesh/initial_mesh splits the same polygons for the solvers.

#include <array>
#include <optional>
#include <vector>

namespace lhr {

// Triangles (as corner indices into the polygon) tiling a planar polygon that
// is counter-clockwise in q: a fan when every fan triangle is
// counter-clockwise, else ear clipping. Collinear pieces are dropped; an
// empty optional means the polygon is self-intersecting or clockwise.
std::optional<std::vector<std::array<int, 3>>> triangulate_planar_polygon(const std::vector<std::array<double, 2>>& q);

}  // namespace lhr
