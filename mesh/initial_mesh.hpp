#pragma once
// Initial meshing to a minimum density (paper §4.1, fig. 6c; docs/design.md §4).

#include <functional>

#include "mesh/contact_lines.hpp"
#include "mesh/scene.hpp"
#include "mesh/types.hpp"

namespace lhr {

struct MeshingOptions {
  double max_edge = 0.0;          // h: no output edge longer than this (plus rounding)
  double min_angle_deg = 20.0;    // lower bound on every angle the input boundary does not force smaller
  // Called often while a surface is meshed (inside CGAL's remeshing of a
  // curved surface too); whatever it throws leaves mesh_surface unchanged,
  // so a signal stops a long meshing within a second (docs/robustness.md).
  std::function<void()> checkpoint;
};

// h when the user gives none: a fraction of the scene's bounding-box diagonal.
double default_max_edge(const Scene& scene);

// Planar surfaces: constrained Delaunay meshing of the surface's region
// (holes kept), boundary vertices and edges preserved. Curved surfaces:
// isotropic remeshing to h with boundary and sharp features preserved.
// Faces are counter-clockwise seen from the surface's front.
// Throws std::runtime_error naming the surface when meshing fails.
// A planar surface's mesh also has edges along its contact lines
// (mesh/contact_lines.hpp), ends within contact_tolerance snapped together.
TriMesh mesh_surface(const Surface& surface, const MeshingOptions& options, const std::vector<Segment3>& contacts = {},
                     double contact_tolerance = 0.0);

}  // namespace lhr
