#pragma once
// Shooters above the quadtree roots (docs/design.md §4 "Progressive linking"): a
// binary tree of clusters of a surface's initial triangles whose top is the
// whole surface, so a shooter starts as one element and opens up only as far
// as the shooter oracle asks.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "radiosity/meshed_scene.hpp"

namespace lhr {

struct RootCluster {
  std::vector<NodeId> roots;
  std::int32_t first_child = -1;  // two consecutive child clusters, or -1: children are the roots
  std::int32_t parent = -1;       // -1 for the whole surface
  double area = 0.0;
  double exposed_area = 0.0;  // Σ area × exposed fraction of its roots
  Vec3 centroid{0, 0, 0};
  Vec3 normal{0, 0, 0};  // unit mean normal
};

// Cluster 0 is the whole surface. Median splits of the root centroids along
// the longest extent: a balanced tree of spatially compact clusters, so a far
// cluster is a fair stand-in for its triangles. Clusters of at most
// `leaf_roots` roots open directly onto their roots.
std::vector<RootCluster> build_root_clusters(const MeshedScene& model, int surface,
                                            const std::vector<double>& root_exposure, std::size_t leaf_roots = 4);

// Per root of a surface: its edges, corner k to corner k+1, as
// shared_edge_form_factors names them (2·edge, + 1 against the edge's own
// half-edge direction in the initial mesh), so a cluster link integrates
// each inner edge once.
std::vector<std::array<std::int32_t, 3>> root_corner_edges(const SurfaceHierarchy& h);

// Each cluster's outline: the edges of its roots that no other root of it
// shares, as initial-mesh vertex pairs in their root's counter-clockwise
// direction. On a planar surface the contour integral over it is the form
// factor of the whole cluster (outline_form_factor), so a far cluster's
// form factor costs its outline, not its roots. Clusters of fewer than
// `min_roots` roots, where that saves little, keep an empty one.
struct ClusterOutlines {
  std::vector<std::uint32_t> start;  // per cluster, then one past the last
  std::vector<std::array<VertexId, 2>> edges;
  std::span<const std::array<VertexId, 2>> of(std::size_t cluster) const {
    return std::span<const std::array<VertexId, 2>>(edges).subspan(start[cluster], start[cluster + 1] - start[cluster]);
  }
  std::size_t bytes() const { return start.capacity() * sizeof(start[0]) + edges.capacity() * sizeof(edges[0]); }
};

// From root_corner_edges' codes: an outline is the symmetric difference of
// its children's, so the tree costs the sum of its outlines' lengths.
ClusterOutlines cluster_outlines(const SurfaceHierarchy& h, const std::vector<RootCluster>& clusters,
                                 const std::vector<std::array<std::int32_t, 3>>& corner_edges,
                                 std::size_t min_roots = 16);

// Per root of a surface: the fraction of it that is open to the scene. A
// point is closed off when every one of a few cosine-distributed rays from it
// ends on the back of a surface (the floor under a block). A whole-surface
// shooter stands for its open part only: averaging the closed, unlit part
// into its value would lose energy.
std::vector<double> root_exposure(const MeshedScene& model, int surface);

}  // namespace lhr
