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
//
// A thin part (a chair leg 4 cm wide, a table's apron) holds its own bends
// across its width: the radiance drops into its junctions with the floor or
// a seat within a centimetre, and an element as wide as the part cuts under
// that, whatever its partner (docs/accuracy.md, "Thin parts"). So a
// surface's own elements may also go down to a fraction of its width.

#include <algorithm>
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

  // Smallest area surface s's own width allows its elements.
  double own_min_area(int s) const { return own_min_area_[s]; }

  // A split of a node of surface `self` with this area, in an interaction
  // with `partner`, is allowed: the finer of the two floors holds.
  bool allows_split(double area, int self, int partner) const {
    return area > 4.0 * std::min(min_area_[partner], own_min_area_[self]);
  }

  // A split of a node with this area goes below the floor every surface
  // has (the user's, or h/32): only a small partner or a thin surface of
  // its own allows it.
  bool below_scene_floor(double area) const { return area <= 4.0 * scene_min_area_; }

 private:
  std::vector<double> min_area_;
  std::vector<double> own_min_area_;
  double scene_min_area_ = 0.0;
};

}  // namespace lhr
