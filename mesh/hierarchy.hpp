#pragma once
// The restricted triangle quadtree of one surface (paper §3, fig. 2; DESIGN §4
// "Hierarchy").
//
// OpenMesh owns the connectivity of the initial triangulation (each face roots
// a quadtree) and the positions of the vertices of every level; the quadtree
// nodes live in a dense array indexed by NodeId. Values a solver keeps per node
// or per vertex hang on these ids in arrays of its own (see CornerValues).

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "mesh/types.hpp"

namespace lhr {

using NodeId = std::int32_t;
using VertexId = std::int32_t;  // == the OpenMesh vertex index in SurfaceHierarchy::mesh()
constexpr NodeId kNoNode = -1;
constexpr VertexId kNoVertex = -1;

// Exported, conforming triangulation of the leaves, T-vertices closed.
struct ConformingMesh {
  TriMesh mesh;                      // leaf triangles, T-vertices closed, counter-clockwise
  std::vector<VertexId> source;      // per exported vertex: the hierarchy vertex it is
};

class SurfaceHierarchy {
 public:
  // Every face of `initial` becomes a level-0 root. The mesh must be a
  // manifold triangle mesh (as the initial mesher produces).
  explicit SurfaceHierarchy(TriMesh initial);

  const TriMesh& mesh() const { return mesh_; }

  std::size_t num_nodes() const { return nodes_.size(); }
  std::size_t num_roots() const { return num_roots_; }
  std::size_t num_vertices() const { return mesh_.n_vertices(); }
  std::size_t num_leaves() const { return num_leaves_; }

  // Root of initial face f (OpenMesh face index): NodeId f.
  NodeId root(int face_index) const { return face_index; }

  // Corners in counter-clockwise order. Children of a node with corners
  // (v0,v1,v2) and edge midpoints m01,m12,m20:
  //   child 0 = (v0,m01,m20), child 1 = (m01,v1,m12), child 2 = (m20,m12,v2),
  //   child 3 = (m12,m20,m01) (centre; its corner k is opposite corner k of the parent).
  const std::array<VertexId, 3>& corners(NodeId n) const { return nodes_[n].corners; }
  int level(NodeId n) const { return nodes_[n].level; }
  NodeId parent(NodeId n) const { return nodes_[n].parent; }
  bool is_leaf(NodeId n) const { return nodes_[n].first_child == kNoNode; }
  NodeId child(NodeId n, int i) const { return nodes_[n].first_child + i; }
  int child_index(NodeId n) const { return nodes_[n].child_index; }
  // Initial face this node descends from.
  int root_face(NodeId n) const { return nodes_[n].root_face; }

  Vec3 point(VertexId v) const { return mesh_.point(OpenMesh::VertexHandle(v)); }
  // Level at which the vertex appeared (0 for initial vertices).
  int vertex_level(VertexId v) const { return vertex_level_[v]; }
  // Vertex at the midpoint of edge (a,b), or kNoVertex if neither side is split.
  VertexId midpoint(VertexId a, VertexId b) const;

  // Edge k of a node runs from corner k to corner k+1 (mod 3).
  // The node of the same level across that edge, or kNoNode where there is
  // none (surface boundary, or the neighbour is coarser).
  NodeId neighbor(NodeId n, int edge) const;
  // The leaf across edge k that contains the edge's midpoint region: same
  // level or coarser if it is a leaf; if the same-level neighbour is split,
  // kNoNode (use neighbor() and walk its children). kNoNode on the boundary.
  NodeId coarser_or_equal_leaf_neighbor(NodeId n, int edge) const;

  // Splits leaf n into four children. To keep the quadtree restricted
  // (leaves sharing an edge differ by at most one level), coarser neighbours
  // are split first, recursively. Returns every node split, forced ones
  // first, n last. Splitting a node that is not a leaf is a no-op returning {}.
  std::vector<NodeId> split(NodeId n);

  std::vector<NodeId> leaves() const;
  // Nodes of one level (0 = roots).
  std::vector<NodeId> nodes_at_level(int level) const;
  int max_level() const { return max_level_; }

  // A T-vertex lies inside an edge of some leaf (the coarse side of a split).
  bool is_t_vertex(VertexId v) const;
  std::vector<VertexId> t_vertices() const;

  // Leaves as a conforming mesh: a leaf with T-vertices on its edges is
  // split through them for output only, so the result is crack-free.
  ConformingMesh conforming_mesh() const;

 private:
  struct Node {
    std::array<VertexId, 3> corners;
    NodeId parent = kNoNode;
    NodeId first_child = kNoNode;  // the four children are consecutive
    std::int32_t root_face = 0;
    std::int8_t level = 0;
    std::int8_t child_index = -1;
  };
  static std::uint64_t edge_key(VertexId a, VertexId b);
  VertexId midpoint_or_create(VertexId a, VertexId b, int level);

  TriMesh mesh_;
  std::vector<Node> nodes_;
  std::vector<int> vertex_level_;
  // Undirected edge (a,b) at any level -> the up to two nodes having it as an edge.
  std::unordered_map<std::uint64_t, std::array<NodeId, 2>> edge_nodes_;
  std::unordered_map<std::uint64_t, VertexId> midpoints_;
  std::size_t num_roots_ = 0;
  std::size_t num_leaves_ = 0;
  int max_level_ = 0;
};

// Per-node-corner storage for a solver (e.g. one shooter's coefficients at
// every level, paper §3): grows with the hierarchy, indexed by (node, corner).
template <class T>
class CornerValues {
 public:
  T& at(NodeId n, int corner) {
    ensure(n);
    return data_[3 * static_cast<std::size_t>(n) + corner];
  }
  const T& at(NodeId n, int corner) const { return data_.at(3 * static_cast<std::size_t>(n) + corner); }
  void ensure(NodeId n) {
    if (data_.size() < 3 * static_cast<std::size_t>(n + 1)) data_.resize(3 * static_cast<std::size_t>(n + 1));
  }
  std::size_t size_nodes() const { return data_.size() / 3; }

 private:
  std::vector<T> data_;
};

}  // namespace lhr
