#pragma once
// How far a shooter element's representation can be from the radiance it
// stands for (docs/design.md §4, shooter oracle). A link carries an element's basis
// values — a cluster's mean, a triangle's projected values — to a receiver that
// may see only part of it (the dark floor in front of a block, not the floor's
// lit middle); what it carries is off by at most the link's form factor times
// this spread, so the oracles refine where that product matters even when the
// element's mean looks harmless.

#include <algorithm>
#include <cmath>
#include <vector>

#include "mesh/hierarchy.hpp"
#include "mesh/types.hpp"

namespace lhr {

// What a linear element shoots with (docs/accuracy.md, "What a coarse triangle
// shoots"): the L2 projection of its leaves' piecewise-linear radiance L onto
// its three hat functions, not L at its corners. A receiver far off sees a
// near-constant kernel over the element, so the element must carry L's
// integral; the corner values of a floor triangle with a lamp's hot spot
// inside it miss the spot and shoot too little. Where the projection would go
// negative it is drawn toward its mean until it is not (a radiance below 0 is
// not light); the mean, and so the power, is kept.
struct LinearShooterValues {
  std::vector<std::array<Rgb, 3>> corners;  // per node, at its corners
  std::vector<Rgb> root_integral;           // per root, ∫ L dA over it
  // Per node, per channel, a bound on |L(x) − P(x)| over the node, P the
  // node's projected linear function; 0 at a leaf (a leaf is its own L).
  std::vector<Rgb> spread;
};

// node_area[n]: node n's area. Children must have larger ids than parents,
// roots come first. Fills `out` in place (it is rebuilt every iteration and
// keeps its capacity).
void project_linear_nodes(const SurfaceHierarchy& h, const std::vector<Rgb>& vertex_radiance,
                          const std::vector<double>& node_area, LinearShooterValues& out);

// Constant elements: per node, per channel, max |L(leaf) − L(node)| over the
// leaves below it. 0 at a leaf.
std::vector<Rgb> constant_node_spread(const SurfaceHierarchy& h, const std::vector<Rgb>& node_radiance);

// Per cluster: a bound on |L(x) − value[c]| over the open part of its roots
// (a root closed off entirely is seen by no receiver), given each root's own
// spread and how far its representative values (`root_values(root)`: its
// corners, or its one constant) are from the cluster's value.
// Cluster: anything with a `roots` list (RootCluster, or a solver's own).
template <typename Cluster, typename RootValues>
std::vector<Rgb> cluster_spread(const std::vector<Cluster>& clusters, const std::vector<Rgb>& value,
                                const std::vector<double>& root_exposure, const std::vector<Rgb>& node_spread,
                                const RootValues& root_values) {
  std::vector<Rgb> out(clusters.size(), Rgb(0, 0, 0));
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    for (NodeId root : clusters[c].roots) {
      if (!(root_exposure[root] > 0)) continue;
      for (const Rgb& v : root_values(root)) {
        for (int k = 0; k < 3; ++k) {
          out[c][k] = std::max(out[c][k], node_spread[root][k] + std::abs(v[k] - value[c][k]));
        }
      }
    }
  }
  return out;
}

}  // namespace lhr
