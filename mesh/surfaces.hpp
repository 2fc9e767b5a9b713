#pragma once
// Grouping loaded faces into surfaces (DESIGN §3).

#include "mesh/scene.hpp"

namespace lhr {

constexpr double kDefaultCreaseAngleDeg = 30.0;

struct SurfaceSplit {
  std::vector<Surface> surfaces;
  int dropped_zero_area_faces = 0;
  int non_manifold_edges = 0;  // edges of more than two faces: surfaces are cut along them
};

// Connected faces sharing an edge, with equal material and group, whose
// normals differ by at most crease_angle_deg, form one surface; an edge of
// more than two faces joins none of them. Faces whose
// area is zero (relative to the scene size) are dropped and counted.
// Preconditions (checked by the loaders): indices in range, >= 3 distinct
// vertices per face, finite points.
SurfaceSplit split_into_surfaces(const PolygonSoup& soup, double crease_angle_deg);

}  // namespace lhr
