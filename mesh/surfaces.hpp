#pragma once
// Grouping loaded faces into surfaces (docs/design.md §3).

#include <functional>
#include <utility>
#include <vector>

#include "mesh/scene.hpp"

namespace lhr {

constexpr double kDefaultCreaseAngleDeg = 30.0;

struct SurfaceSplit {
  std::vector<Surface> surfaces;
  int dropped_zero_area_faces = 0;
  int non_manifold_edges = 0;  // edges of more than two faces: surfaces are cut along them
  // Emitters that lay on a coplanar, same-facing surface (a light drawn on
  // its ceiling), each with that surface: moved in front of it by lift_distance.
  std::vector<std::pair<int, int>> lifted_emitters;
  double lift_distance = 0.0;
};

// Connected faces sharing an edge, with equal material and group, whose
// normals differ by at most crease_angle_deg, form one surface; an edge of
// more than two faces joins none of them. Faces whose
// area is zero (relative to the scene size) are dropped and counted.
// Preconditions (checked by the loaders): indices in range, >= 3 distinct
// vertices per face, finite points.
// An emitting planar surface lying in the plane of another planar surface
// that faces the same way, and overlapping it, is moved off that plane along
// its normal by a small fraction of the scene size, so that it is in front:
// coincident surfaces would otherwise be resolved by rounding, differently
// by each ray.
// checkpoint, when set, is called every few thousand faces: a soup of 10^6
// faces takes a second to split, and a caller may need to stop it.
SurfaceSplit split_into_surfaces(const PolygonSoup& soup, double crease_angle_deg,
                                 const std::function<void()>& checkpoint = {});

}  // namespace lhr
