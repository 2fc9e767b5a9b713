#pragma once
// The smallest elements refinement may make (docs/design.md §4 "Limits the user
// controls"), per interaction.
//
// A floor fixed for the whole scene (h/32 by default) cannot resolve what a
// surface much smaller than it does to its neighbours: a light of side a at
// height d ≪ h over a wall puts all its power into a spot of size about a + d
// (docs/design.md §5, small lights), and an element larger than that spot either misses it
// (a constant element valued at its centre) or spreads one vertex's value
// over its whole hat function (point collocation, linear basis). So the
// default floor shrinks to a fraction of the partner surface's size in the
// interactions with a small surface; every interaction between surfaces
// larger than the scene floor keeps that floor.

#include <vector>

#include "radiosity/meshed_scene.hpp"

namespace lhr {

class ElementFloor {
 public:
  // min_edge > 0: the user's floor, the same for every interaction.
  // 0: h/32, or less toward small surfaces.
  ElementFloor(const MeshedScene& model, double min_edge);

  // Smallest area an element may be split to in an interaction with surface
  // `partner` (its shooter when it receives, its receiver when it shoots):
  // elements of up to 4 times this area are not split.
  double min_area(int partner) const { return min_area_[partner]; }

  // A split of a node of this area in an interaction with `partner` is allowed.
  bool allows_split(double area, int partner) const { return area > 4.0 * min_area_[partner]; }

 private:
  std::vector<double> min_area_;
};

}  // namespace lhr
