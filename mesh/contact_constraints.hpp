#pragma once
// Contact lines (mesh/contact_lines.hpp) turned into constraints of one
// planar surface's initial mesh, in the surface's (u, v) frame
// (mesh/planar_mesh.hpp; docs/accuracy.md, "Contact lines").

#include <array>
#include <utility>
#include <vector>

#include "mesh/point2.hpp"

namespace lhr {

// The contact lines clipped to the surface's region, their ends snapped
// (within the contact tolerance) onto polygon vertices, onto polygon edges
// (which are split there) and onto each other, and pieces lying along a
// polygon edge dropped. Without the snapping, an end a rounding error away
// from an edge would leave a sliver that Delaunay refinement fills with ever
// smaller triangles.
struct ContactConstraints {
  std::vector<Point2> points;                      // new points, numbered from the surface's point count on
  std::vector<std::pair<int, int>> polygon_edges;  // the polygon constraints, split at contact ends
  std::vector<std::pair<int, int>> contact_edges;
};

// q: the surface's points; triangles: its region (indices into q);
// polygon_edges: the constraints the polygons give; contacts: the contact
// segments in the same frame.
ContactConstraints plan_contacts(const std::vector<Point2>& q, const std::vector<std::array<int, 3>>& triangles,
                                 const std::vector<std::pair<int, int>>& polygon_edges,
                                 const std::vector<std::pair<Point2, Point2>>& contacts, double tolerance);

}  // namespace lhr
