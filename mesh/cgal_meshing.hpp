#pragma once
// The CGAL algorithms the initial meshing runs (docs/design.md §4, "Initial
// meshing"), behind types that do not name CGAL: cgal_meshing.cpp is the
// only translation unit that includes CGAL, which is slow to compile
// (docs/design.md §2, "CGAL stays in mesh/cgal_meshing.cpp"). The planar
// path (mesh/planar_mesh.hpp) and the curved path (mesh/curved_mesh.hpp)
// decide what to mesh and check what comes back.

#include <array>
#include <cstddef>
#include <utility>
#include <vector>

#include "mesh/meshing_checkpoint.hpp"
#include "mesh/point2.hpp"
#include "mesh/point_locator.hpp"
#include "mesh/types.hpp"

namespace lhr {

// Splits one polygon (counter-clockwise in the plane) into triangles,
// appended to `out`, with CGAL's exact orientation test. Throws
// std::runtime_error naming polygon `polygon_index` when it is
// self-intersecting or clockwise.
void triangulate_polygon(const std::vector<int>& poly, const std::vector<Point2>& q, std::size_t polygon_index,
                         std::vector<std::array<int, 3>>& out);

// What a planar surface's constrained Delaunay mesh must keep.
struct ConstrainedRegion {
  std::vector<Point2> points;          // the surface's points, then those contact lines add
  std::size_t num_surface_points = 0;  // how many of `points` are the surface's own
  std::vector<std::pair<int, int>> polygon_edges;  // constraints that bound the region or crease it
  std::vector<std::pair<int, int>> contact_edges;  // constraints inside it
};

struct RegionMesh {
  std::vector<Point2> points;
  // Per point: the surface point it is, or -1 for a point the mesher or a
  // contact line added (its 3D position comes from the input triangles).
  std::vector<int> surface_point;
  std::vector<std::array<int, 3>> triangles;  // counter-clockwise, indices into points
};

// Constrained Delaunay refinement of the part of the plane the constraints
// enclose and `region`'s triangles cover, to triangles whose smallest angle
// has sin² >= shape_bound and whose edges are at most size_bound. Only the
// constraints' ends are inserted. Throws std::runtime_error when the
// constraints cross each other, enclose nothing, or refinement runs away.
RegionMesh refine_region(const ConstrainedRegion& constraints, const PointLocator& region, double shape_bound,
                         double size_bound);

// One pass of a curved surface's remeshing, a coarsening sweep
// (mesh/coarsen.hpp) or, last, CGAL's isotropic remeshing: its target edge
// length and how many triangles it was handed.
struct RemeshPass {
  double target_length = 0.0;
  std::size_t faces = 0;
};

// Isotropic remeshing of a curved surface toward edges of h, then every edge
// longer than h split. The border and the input's bends stay lines of the
// mesh; `fixed` vertices (the ends of seam edges, which another surface
// shares) are neither moved nor removed. A surface far finer than h is
// first coarsened in passes toward halved targets; returns every pass, the
// final one last. Leaves deleted elements for garbage collection.
std::vector<RemeshPass> remesh_isotropic(TriMesh& mesh, double h, const std::vector<TriMesh::VertexHandle>& fixed,
                                         MeshingCheckpoint& checkpoint);

}  // namespace lhr
