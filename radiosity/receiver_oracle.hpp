#pragma once
// The receiver oracle of paper §4.1, per interaction-graph edge (docs/design.md §4):
// between triangles left and right with edge vertices 1,2 and opposite
// vertices 3,4, how much would the displayed image change if S's
// contribution were refined across that edge?

#include <array>
#include <vector>

#include "mesh/hierarchy.hpp"
#include "radiosity/interaction_graph.hpp"
#include "radiosity/tone_map.hpp"

namespace lhr {

// The four points' affine dependence: weights w with Σ w_i = 0 and
// Σ w_i p_i = 0, so Σ w_i f(p_i) = 0 for every linear f. With q the point
// where line 3-4 meets line 1-2, q = α p1 + (1−α) p2 = β p3 + (1−β) p4, they
// are 2(α, 1−α, −β, −(1−β)): twice the difference between f at q
// interpolated along the edge and across it. For a regular pair (a
// parallelogram, q the midpoint of both diagonals) they are the paper's
// (1, 1, −1, −1); on a coarse–fine pair, or on two irregular root triangles,
// those would see a linear field as curved (docs/design.md §4, "Edge
// weights"). On a curved surface q is the least-squares crossing; where
// lines 1-2 and 3-4 are (nearly) parallel or q falls far outside either
// segment, the paper's weights.
std::array<double, 4> edge_weights(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4);

// A pair of graph leaves the oracle looks at: `left` and the leaf `right`
// across left's edge (vertex[0], vertex[1]); vertex[2] is left's opposite
// corner, vertex[3] the corner of right farthest from the edge's line.
struct OracleEdge {
  NodeId left = kNoNode;
  NodeId right = kNoNode;
  std::array<VertexId, 4> vertex{};
};

// The pairs whose `left` is graph leaf `leaf`. Each pair of the graph is
// listed once over all its leaves: a same-level pair from its smaller id, a
// coarse–fine pair (the graph is restricted: one level apart) from the fine
// side. Boundary edges have no pair.
void oracle_edges(const InteractionGraph& graph, const SurfaceHierarchy& receiver, NodeId leaf,
                  std::vector<OracleEdge>& out);

// Luminances at vertices 1,2 (the edge), 3 (left's opposite), 4 (right's).
struct EdgeValues {
  std::array<double, 4> own{};    // B_l: shooter S's reflected contribution
  std::array<double, 4> total{};  // radiance with every shooter, S included
  std::array<double, 4> weights{1.0, 1.0, -1.0, -1.0};  // edge_weights of the four points
  double visibility_1 = 1.0;      // fraction of S visible from vertex 1
  double visibility_2 = 1.0;      // ... and from vertex 2
};

class ReceiverOracle {
 public:
  ReceiverOracle(const ToneMap& tone, double vis_threshold) : tone_(tone), vis_threshold_(vis_threshold) {}

  // ΔE in display units. B_min is the smallest radiance of the four vertices
  // without S. Same visibility along the edge: half the second difference of
  // S's displayed contribution across it, ½|Σ w_i M(B_i+Bmin)|; for a
  // regular pair
  //   ½|M(B1+Bmin) + M(B2+Bmin) − M(B3+Bmin) − M(B4+Bmin)|
  // (the paper prints "+M(B4)"; a second difference needs "−"). A
  // visibility change: the conservative max_l − min_l of M(Bmin+B_l).
  double display_error(const EdgeValues& edge) const;

  // Split left and right (and link S to the new nodes) when this holds;
  // pixels = I_left + I_right.
  static bool refines(double display_error, double pixels, double eps_pixel) {
    return display_error * pixels >= eps_pixel;
  }

  // refines(display_error(edge), pixels, eps_pixel), decided first from a
  // bound that takes two tone-map evaluations where ΔE takes four: with
  // weights summing to 0 and a display M that never decreases (both tone
  // maps; ToneMap.*NeverInverts*), |Σ w_i M_i| is at most
  // ½ Σ|w_i| (M_max − M_min). A solve asks this of every edge of every
  // graph it judges (44 M times in the two rooms), and the bound settles
  // over 99 % of them.
  bool edge_refines(const EdgeValues& edge, double pixels, double eps_pixel) const;

 private:
  const ToneMap& tone_;
  double vis_threshold_;
};

}  // namespace lhr
