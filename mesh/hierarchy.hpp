#pragma once
// The restricted triangle quadtree of one surface (paper §3, figs. 2-4; docs/design.md §4
// "Hierarchy").
//
// OpenMesh owns the connectivity of the initial triangulation (each face roots
// a quadtree) and the positions of the vertices of every level; the quadtree
// nodes live in one dense array indexed by NodeId, with no per-node heap
// storage. Values a solver keeps per node or per vertex hang on these ids in
// arrays of its own (see CornerValues).
//
// Neighbour finding: every node stores its same-level neighbour across each
// edge. Roots take them from the OpenMesh half-edge connectivity; a split links
// its children to each other and, where the same-level neighbour is already
// split, to that neighbour's children along the shared edge (the classic
// pointer scheme for quadtrees), so neighbour queries and forced splits cost
// O(1) per step with no hashing. Edge midpoints are kept in a hash map keyed
// by the undirected vertex pair so that both sides of an edge share one
// midpoint vertex and midpoint(a, b) can be answered for any edge.

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
  std::vector<NodeId> leaf;          // per exported face: the leaf it covers part of
};

class SurfaceHierarchy {
 public:
  // Deepest level a node may reach; splitting a node at this level throws
  // std::length_error (the geometry is far below double precision long before).
  static constexpr int kMaxLevel = 100;

  // Every face of `initial` becomes a level-0 root, NodeId == face index, its
  // corners in the face's counter-clockwise (half-edge) order. The mesh must
  // be a manifold triangle mesh (as the initial mesher produces); deleted
  // elements are garbage-collected first, which renumbers faces.
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
  // Consequences used throughout: child c (c < 3) has its edges c and
  // (c+2)%3 on the parent's edges of the same index; its edge (c+1)%3 is
  // shared with edge (c+1)%3 of the centre child.
  const std::array<VertexId, 3>& corners(NodeId n) const { return nodes_[n].corners; }
  int level(NodeId n) const { return nodes_[n].level; }
  NodeId parent(NodeId n) const { return nodes_[n].parent; }
  bool is_leaf(NodeId n) const { return nodes_[n].first_child == kNoNode; }
  // Valid only for a node that is not a leaf; children are consecutive ids.
  NodeId child(NodeId n, int i) const { return nodes_[n].first_child + i; }
  // Which child of its parent a node is (0..3), -1 for a root.
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
  NodeId neighbor(NodeId n, int edge) const { return nodes_[n].neighbor[edge]; }
  // Whether edge k of node n lies on the boundary of the surface.
  bool is_boundary_edge(NodeId n, int edge) const { return (nodes_[n].boundary_mask >> edge) & 1U; }
  // The leaf across edge k that contains the edge's midpoint region: same
  // level or coarser if it is a leaf; if the same-level neighbour is split,
  // kNoNode (use neighbor() and walk its children). kNoNode on the boundary.
  NodeId coarser_or_equal_leaf_neighbor(NodeId n, int edge) const;

  // Splits leaf n into four children. To keep the quadtree restricted
  // (leaves sharing an edge differ by at most one level), coarser neighbours
  // are split first, recursively. Returns every node split, forced ones
  // first, n last. Splitting a node that is not a leaf is a no-op returning {}.
  // Throws std::out_of_range for an id that is not a node and
  // std::length_error when n (or a forced split) is at kMaxLevel.
  std::vector<NodeId> split(NodeId n);

  // Both in increasing NodeId order.
  std::vector<NodeId> leaves() const;
  // Nodes of one level (0 = roots).
  std::vector<NodeId> nodes_at_level(int level) const;
  int max_level() const { return max_level_; }

  // A T-vertex lies strictly inside an edge of some leaf (the coarse side of
  // a split whose same-level neighbour is split). O(1).
  bool is_t_vertex(VertexId v) const { return t_vertex_[v] != 0; }
  // In increasing VertexId order.
  std::vector<VertexId> t_vertices() const;

  // Leaves as a conforming mesh: a leaf with T-vertices on k of its edges is
  // split through them for output only (k = 1: 2 triangles, 2: 3, 3: the 4
  // children-shaped triangles), so the result is crack-free and manifold.
  // Faces follow leaf order; vertices are the used hierarchy vertices in
  // increasing id order. An unsplit hierarchy exports the initial faces.
  ConformingMesh conforming_mesh() const;

  // Memory held, in bytes: vertex positions and the OpenMesh connectivity of
  // the initial triangulation; the quadtree nodes and per-vertex bookkeeping.
  std::size_t geometry_bytes() const;
  std::size_t hierarchy_bytes() const;

 private:
  struct Node {
    std::array<VertexId, 3> corners;
    std::array<NodeId, 3> neighbor = {kNoNode, kNoNode, kNoNode};  // same level, across edge k
    NodeId parent = kNoNode;
    NodeId first_child = kNoNode;  // the four children are consecutive
    std::int32_t root_face = 0;
    std::int8_t level = 0;
    std::int8_t child_index = -1;
    std::uint8_t boundary_mask = 0;  // bit k: edge k is on the surface boundary
  };
  // Index j of the edge of node q joining a and b (either direction), or -1.
  int edge_index(NodeId q, VertexId a, VertexId b) const;
  VertexId midpoint_or_create(VertexId a, VertexId b, int level);
  void split_recursive(NodeId n, std::vector<NodeId>& split_nodes);
  // Makes sure edge k of leaf n has a same-level neighbour or is boundary,
  // splitting coarser leaves across it as needed.
  void ensure_neighbor(NodeId n, int edge, std::vector<NodeId>& split_nodes);
  void subdivide(NodeId n);

  TriMesh mesh_;
  std::vector<Node> nodes_;
  std::vector<std::int32_t> vertex_level_;
  std::vector<std::uint8_t> t_vertex_;
  std::unordered_map<std::uint64_t, VertexId> midpoints_;
  std::size_t num_roots_ = 0;
  std::size_t num_leaves_ = 0;
  int max_level_ = 0;
};

// Per-node-corner storage for a solver (e.g. one shooter's coefficients at
// every level, paper §3): grows with the hierarchy, indexed by (node, corner).
// One contiguous array, three values per node.
template <class T>
class CornerValues {
 public:
  // Grows the storage to cover node n; new values are value-initialised.
  T& at(NodeId n, int corner) {
    ensure(n);
    return data_[3 * static_cast<std::size_t>(n) + corner];
  }
  // Throws std::out_of_range for a node never stored.
  const T& at(NodeId n, int corner) const { return data_.at(3 * static_cast<std::size_t>(n) + corner); }
  void ensure(NodeId n) {
    if (data_.size() < 3 * static_cast<std::size_t>(n + 1)) data_.resize(3 * static_cast<std::size_t>(n + 1));
  }
  // Covers every node of a hierarchy with num_nodes nodes in one allocation.
  void reserve_nodes(std::size_t num_nodes) { data_.reserve(3 * num_nodes); }
  bool has(NodeId n) const { return n >= 0 && 3 * static_cast<std::size_t>(n) < data_.size(); }
  std::size_t size_nodes() const { return data_.size() / 3; }

 private:
  std::vector<T> data_;
};

}  // namespace lhr
