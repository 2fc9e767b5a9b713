#pragma once
// The receiver oracle of paper §4.1, per interaction-graph edge (docs/design.md §4):
// between triangles left and right with edge vertices 1,2 and opposite
// vertices 3,4, how much would the displayed image change if S's
// contribution were refined across that edge?

#include <array>

#include "radiosity/tone_map.hpp"

namespace lhr {

// Luminances at vertices 1,2 (the edge), 3 (left's opposite), 4 (right's).
struct EdgeValues {
  std::array<double, 4> own{};    // B_l: shooter S's reflected contribution
  std::array<double, 4> total{};  // radiance with every shooter, S included
  double visibility_1 = 1.0;      // fraction of S visible from vertex 1
  double visibility_2 = 1.0;      // ... and from vertex 2
};

class ReceiverOracle {
 public:
  ReceiverOracle(const ToneMap& tone, double vis_threshold) : tone_(tone), vis_threshold_(vis_threshold) {}

  // ΔE in display units. B_min is the smallest radiance of the four vertices
  // without S. Same visibility along the edge: half the second difference of
  // S's displayed contribution across it,
  //   ½|M(B1+Bmin) + M(B2+Bmin) − M(B3+Bmin) − M(B4+Bmin)|
  // (the paper prints "+M(B4)"; a second difference needs "−"). A
  // visibility change: the conservative max_l − min_l of M(Bmin+B_l).
  double display_error(const EdgeValues& edge) const;

  // Split left and right (and link S to the new nodes) when this holds;
  // pixels = I_left + I_right.
  static bool refines(double display_error, double pixels, double eps_pixel) {
    return display_error * pixels >= eps_pixel;
  }

 private:
  const ToneMap& tone_;
  double vis_threshold_;
};

}  // namespace lhr
