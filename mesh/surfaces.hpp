#pragma once
// Grouping loaded faces into surfaces (DESIGN §3).

#include "mesh/scene.hpp"

namespace lhr {

constexpr double kDefaultCreaseAngleDeg = 30.0;

struct SurfaceSplit {
  std::vector<Surface> surfaces;
  int dropped_zero_area_faces = 0;
};

// Connected faces sharing an edge, with equal material and group, whose
// normals differ by at most crease_angle_deg, form one surface. Faces whose
// area is zero (relative to the scene size) are dropped and counted.
// Preconditions (checked by the loaders): indices in range, >= 3 distinct
// vertices per face, finite points.
SurfaceSplit split_into_surfaces(const PolygonSoup& soup, double crease_angle_deg);

}  // namespace lhr
