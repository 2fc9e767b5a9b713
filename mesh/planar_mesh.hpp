#pragma once
// A planar surface's initial mesh (paper §4.1; docs/design.md §4, "Initial
// meshing"): constrained Delaunay meshing of the surface's region in its own
// plane, holes kept, boundary vertices and edges preserved, creases of the
// input and contact lines kept as edges.

#include <vector>

#include "mesh/contact_lines.hpp"
#include "mesh/initial_mesh.hpp"
#include "mesh/scene.hpp"
#include "mesh/types.hpp"

namespace lhr {

// Faces counter-clockwise seen from the surface's front. Throws
// std::runtime_error saying what is wrong with the polygons (mesh_surface
// adds the surface's name). `contacts` may be empty.
TriMesh mesh_planar(const Surface& surface, const MeshingOptions& options, const std::vector<Segment3>& contacts,
                    double contact_tolerance);

}  // namespace lhr
