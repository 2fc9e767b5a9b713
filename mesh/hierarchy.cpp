#include "mesh/hierarchy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "mesh/edge_key.hpp"

namespace lhr {

namespace {

int next3(int k) { return k == 2 ? 0 : k + 1; }
int prev3(int k) { return k == 0 ? 2 : k - 1; }

// Child c (< 3) has its edges c and (c+2)%3 on the parent's edges of the same
// index (see the numbering in hierarchy.hpp); the centre child has none.
bool is_outer_edge(int child_index, int edge) {
  return child_index != 3 && (edge == child_index || edge == prev3(child_index));
}

// Corner c of the centre child is the midpoint of parent edge (c+1)%3, so the
// midpoint of parent edge e is its corner (e+2)%3.
int centre_corner_of_edge_midpoint(int edge) { return prev3(edge); }

}  // namespace

SurfaceHierarchy::SurfaceHierarchy(TriMesh initial) : mesh_(std::move(initial)) {
  if (mesh_.has_vertex_status() || mesh_.has_edge_status() || mesh_.has_halfedge_status() ||
      mesh_.has_face_status()) {
    mesh_.garbage_collection();
  }
  if (mesh_.n_faces() > static_cast<std::size_t>(std::numeric_limits<NodeId>::max() / 4) ||
      mesh_.n_vertices() > static_cast<std::size_t>(std::numeric_limits<VertexId>::max() / 2)) {
    throw std::length_error("surface hierarchy: initial mesh too large (" + std::to_string(mesh_.n_faces()) +
                            " faces, " + std::to_string(mesh_.n_vertices()) + " vertices)");
  }
  num_roots_ = mesh_.n_faces();
  num_leaves_ = num_roots_;
  nodes_.resize(num_roots_);
  vertex_level_.assign(mesh_.n_vertices(), 0);
  t_vertex_.assign(mesh_.n_vertices(), 0);

  for (const auto fh : mesh_.faces()) {
    Node& node = nodes_[fh.idx()];
    node.root_face = fh.idx();
    // Following next() walks the face in its own (counter-clockwise) order.
    auto h = mesh_.halfedge_handle(fh);
    for (int k = 0; k < 3; ++k) {
      if (k > 0 && h == mesh_.halfedge_handle(fh)) {
        throw std::invalid_argument("surface hierarchy: face " + std::to_string(fh.idx()) +
                                    " is not a triangle");
      }
      node.corners[k] = mesh_.from_vertex_handle(h).idx();
      const auto opposite = mesh_.opposite_halfedge_handle(h);
      if (mesh_.is_boundary(opposite)) {
        node.boundary_mask |= static_cast<std::uint8_t>(1U << k);
      } else {
        node.neighbor[k] = mesh_.face_handle(opposite).idx();
      }
      h = mesh_.next_halfedge_handle(h);
    }
    if (h != mesh_.halfedge_handle(fh)) {
      throw std::invalid_argument("surface hierarchy: face " + std::to_string(fh.idx()) +
                                  " is not a triangle");
    }
  }
}

int SurfaceHierarchy::edge_index(NodeId q, VertexId a, VertexId b) const {
  const auto& c = nodes_[q].corners;
  for (int j = 0; j < 3; ++j) {
    const VertexId s = c[j];
    const VertexId t = c[next3(j)];
    if ((s == a && t == b) || (s == b && t == a)) return j;
  }
  return -1;
}

VertexId SurfaceHierarchy::midpoint(VertexId a, VertexId b) const {
  const auto it = midpoints_.find(edge_key(a, b));
  return it == midpoints_.end() ? kNoVertex : it->second;
}

VertexId SurfaceHierarchy::midpoint_or_create(VertexId a, VertexId b, int level) {
  const auto [it, inserted] = midpoints_.try_emplace(edge_key(a, b), kNoVertex);
  if (!inserted) return it->second;
  if (mesh_.n_vertices() >= static_cast<std::size_t>(std::numeric_limits<VertexId>::max())) {
    midpoints_.erase(it);
    throw std::length_error("surface hierarchy: vertex ids exhausted");
  }
  const Vec3 p = 0.5 * (point(a) + point(b));
  const VertexId m = mesh_.add_vertex(p).idx();
  vertex_level_.push_back(level);
  t_vertex_.push_back(0);
  it->second = m;
  return m;
}

NodeId SurfaceHierarchy::coarser_or_equal_leaf_neighbor(NodeId n, int edge) const {
  // An edge without a same-level neighbour that is not on the boundary is an
  // outer edge of its node and lies on the parent's edge of the same index,
  // so climbing keeps the edge index until a neighbour appears.
  NodeId a = n;
  while (nodes_[a].neighbor[edge] == kNoNode) {
    if (is_boundary_edge(a, edge) || nodes_[a].parent == kNoNode) return kNoNode;
    a = nodes_[a].parent;
  }
  const NodeId q = nodes_[a].neighbor[edge];
  return is_leaf(q) ? q : kNoNode;
}

std::vector<NodeId> SurfaceHierarchy::split(NodeId n) {
  if (n < 0 || static_cast<std::size_t>(n) >= nodes_.size()) {
    throw std::out_of_range("surface hierarchy: cannot split node " + std::to_string(n) + ", there are " +
                            std::to_string(nodes_.size()) + " nodes");
  }
  std::vector<NodeId> split_nodes;
  split_recursive(n, split_nodes);
  return split_nodes;
}

void SurfaceHierarchy::split_recursive(NodeId n, std::vector<NodeId>& split_nodes) {
  if (!is_leaf(n)) return;
  if (nodes_[n].level >= kMaxLevel) {
    throw std::length_error("surface hierarchy: cannot split node " + std::to_string(n) + " of level " +
                            std::to_string(kMaxLevel) + " (the deepest level allowed)");
  }
  for (int k = 0; k < 3; ++k) ensure_neighbor(n, k, split_nodes);
  subdivide(n);
  split_nodes.push_back(n);
}

void SurfaceHierarchy::ensure_neighbor(NodeId n, int edge, std::vector<NodeId>& split_nodes) {
  if (nodes_[n].neighbor[edge] != kNoNode || is_boundary_edge(n, edge)) return;
  const NodeId p = nodes_[n].parent;
  if (p == kNoNode) {
    throw std::logic_error("surface hierarchy: root " + std::to_string(n) + " edge " + std::to_string(edge) +
                           " has neither a neighbour nor a boundary");
  }
  // Splitting the coarser leaf q across links its children to p's children,
  // n among them (q is one level coarser than n in a restricted quadtree;
  // splitting q may force still coarser leaves first).
  ensure_neighbor(p, edge, split_nodes);
  split_recursive(nodes_[p].neighbor[edge], split_nodes);
  if (nodes_[n].neighbor[edge] == kNoNode) {
    throw std::logic_error("surface hierarchy: forced split did not give node " + std::to_string(n) +
                           " a neighbour across edge " + std::to_string(edge));
  }
}

void SurfaceHierarchy::subdivide(NodeId n) {
  const int child_level = nodes_[n].level + 1;
  const auto v = nodes_[n].corners;
  std::array<VertexId, 3> m{};
  for (int k = 0; k < 3; ++k) {
    m[k] = midpoint_or_create(v[k], v[next3(k)], child_level);
    // The midpoint sits inside the edge of the neighbour while that stays a
    // leaf; once both sides are split it is a corner on both sides.
    const NodeId q = nodes_[n].neighbor[k];
    t_vertex_[m[k]] = (q != kNoNode && is_leaf(q)) ? 1 : 0;
  }

  const auto first = static_cast<NodeId>(nodes_.size());
  if (nodes_.size() > static_cast<std::size_t>(std::numeric_limits<NodeId>::max() - 4)) {
    throw std::length_error("surface hierarchy: node ids exhausted");
  }
  const std::array<std::array<VertexId, 3>, 4> child_corners = {{
      {v[0], m[0], m[2]},
      {m[0], v[1], m[1]},
      {m[2], m[1], v[2]},
      {m[1], m[2], m[0]},
  }};
  const Node parent = nodes_[n];
  for (int c = 0; c < 4; ++c) {
    Node child;
    child.corners = child_corners[c];
    child.parent = n;
    child.root_face = parent.root_face;
    child.level = static_cast<std::int8_t>(child_level);
    child.child_index = static_cast<std::int8_t>(c);
    for (int k = 0; k < 3; ++k) {
      if (is_outer_edge(c, k) && ((parent.boundary_mask >> k) & 1U)) {
        child.boundary_mask |= static_cast<std::uint8_t>(1U << k);
      }
    }
    nodes_.push_back(child);
  }
  nodes_[n].first_child = first;

  // Inner edges: edge (c+1)%3 of corner child c against the same edge of the centre.
  for (int c = 0; c < 3; ++c) {
    const int k = next3(c);
    nodes_[first + c].neighbor[k] = first + 3;
    nodes_[first + 3].neighbor[k] = first + c;
  }

  // Outer edges: parent edge k is covered by edge k of child k (at v[k]) and
  // of child k+1 (at v[k+1]); pair each with the neighbour's child at the
  // same end of the shared edge.
  for (int k = 0; k < 3; ++k) {
    const NodeId q = parent.neighbor[k];
    if (q == kNoNode || is_leaf(q)) continue;
    const int j = edge_index(q, v[k], v[next3(k)]);
    if (j < 0) throw std::logic_error("surface hierarchy: neighbour links are inconsistent");
    const NodeId q_first = nodes_[q].first_child;
    const bool same_start = nodes_[q].corners[j] == v[k];
    const NodeId q_at_start = q_first + (same_start ? j : next3(j));
    const NodeId q_at_end = q_first + (same_start ? next3(j) : j);
    nodes_[first + k].neighbor[k] = q_at_start;
    nodes_[q_at_start].neighbor[j] = first + k;
    nodes_[first + next3(k)].neighbor[k] = q_at_end;
    nodes_[q_at_end].neighbor[j] = first + next3(k);
  }

  num_leaves_ += 3;
  max_level_ = std::max(max_level_, child_level);
}

std::vector<NodeId> SurfaceHierarchy::leaves() const {
  std::vector<NodeId> out;
  out.reserve(num_leaves_);
  for (NodeId n = 0; n < static_cast<NodeId>(nodes_.size()); ++n) {
    if (is_leaf(n)) out.push_back(n);
  }
  return out;
}

std::vector<NodeId> SurfaceHierarchy::nodes_at_level(int level) const {
  std::vector<NodeId> out;
  for (NodeId n = 0; n < static_cast<NodeId>(nodes_.size()); ++n) {
    if (nodes_[n].level == level) out.push_back(n);
  }
  return out;
}

std::vector<VertexId> SurfaceHierarchy::t_vertices() const {
  std::vector<VertexId> out;
  for (VertexId v = 0; v < static_cast<VertexId>(t_vertex_.size()); ++v) {
    if (t_vertex_[v] != 0) out.push_back(v);
  }
  return out;
}

ConformingMesh SurfaceHierarchy::conforming_mesh() const {
  std::vector<std::array<VertexId, 3>> triangles;
  std::vector<NodeId> triangle_leaf;
  triangles.reserve(num_leaves_ + num_leaves_ / 2);
  for (NodeId n = 0; n < static_cast<NodeId>(nodes_.size()); ++n) {
    if (!is_leaf(n)) continue;
    const auto& v = nodes_[n].corners;
    // A leaf edge has a T-vertex exactly where the same-level neighbour is
    // split; in a restricted quadtree it is that edge's midpoint and nothing
    // finer, so one extra vertex per edge closes every crack.
    std::array<VertexId, 3> m = {kNoVertex, kNoVertex, kNoVertex};
    int count = 0;
    for (int k = 0; k < 3; ++k) {
      const NodeId q = nodes_[n].neighbor[k];
      if (q == kNoNode || is_leaf(q)) continue;
      const int j = edge_index(q, v[k], v[next3(k)]);
      m[k] = nodes_[nodes_[q].first_child + 3].corners[centre_corner_of_edge_midpoint(j)];
      ++count;
    }
    if (count == 0) {
      triangles.push_back(v);
    } else if (count == 3) {
      triangles.push_back({v[0], m[0], m[2]});
      triangles.push_back({m[0], v[1], m[1]});
      triangles.push_back({m[2], m[1], v[2]});
      triangles.push_back({m[1], m[2], m[0]});
    } else if (count == 1) {
      int k = 0;
      while (m[k] == kNoVertex) ++k;
      const VertexId a = v[k], b = v[next3(k)], c = v[prev3(k)];
      triangles.push_back({a, m[k], c});
      triangles.push_back({m[k], b, c});
    } else {
      // Edge k is the one without a T-vertex: cut off the corner opposite it
      // like a child, and split the remaining trapezoid along its shorter
      // diagonal (better-shaped triangles; ties go to the first).
      int k = 0;
      while (m[k] != kNoVertex) ++k;
      const VertexId a = v[k], b = v[next3(k)], c = v[prev3(k)];
      const VertexId mb = m[next3(k)];  // on b-c
      const VertexId mc = m[prev3(k)];  // on c-a
      triangles.push_back({mb, c, mc});
      const double d_a = (point(a) - point(mb)).sqrnorm();
      const double d_b = (point(b) - point(mc)).sqrnorm();
      if (d_a <= d_b) {
        triangles.push_back({a, b, mb});
        triangles.push_back({a, mb, mc});
      } else {
        triangles.push_back({b, mb, mc});
        triangles.push_back({b, mc, a});
      }
    }
    triangle_leaf.resize(triangles.size(), n);
  }

  ConformingMesh out;
  out.leaf = std::move(triangle_leaf);
  std::vector<int> exported(mesh_.n_vertices(), -1);
  for (const auto& t : triangles) {
    for (const VertexId x : t) exported[x] = 0;
  }
  for (VertexId x = 0; x < static_cast<VertexId>(exported.size()); ++x) {
    if (exported[x] < 0) continue;
    exported[x] = out.mesh.add_vertex(point(x)).idx();
    out.source.push_back(x);
  }
  for (const auto& t : triangles) {
    const auto fh = out.mesh.add_face(OpenMesh::VertexHandle(exported[t[0]]), OpenMesh::VertexHandle(exported[t[1]]),
                                      OpenMesh::VertexHandle(exported[t[2]]));
    if (!fh.is_valid()) {
      throw std::runtime_error("surface hierarchy: the conforming mesh is not manifold at triangle (" +
                               std::to_string(t[0]) + "," + std::to_string(t[1]) + "," + std::to_string(t[2]) +
                               ") of hierarchy vertices; the initial mesh has a non-manifold vertex");
    }
  }
  return out;
}

std::size_t SurfaceHierarchy::geometry_bytes() const {
  // OpenMesh stores a point and an outgoing half-edge per vertex, four
  // handles per half-edge (vertex, face, next, prev) and one per face.
  return mesh_.n_vertices() * (sizeof(Vec3) + sizeof(int)) + mesh_.n_halfedges() * 4 * sizeof(int) +
         mesh_.n_faces() * sizeof(int);
}

std::size_t SurfaceHierarchy::hierarchy_bytes() const {
  // Hash nodes of the midpoint table: key, value and a next pointer; one
  // pointer per bucket.
  const std::size_t midpoint_table = midpoints_.size() * (sizeof(std::uint64_t) + sizeof(VertexId) + sizeof(void*)) +
                                     midpoints_.bucket_count() * sizeof(void*);
  return nodes_.capacity() * sizeof(Node) + vertex_level_.capacity() * sizeof(std::int32_t) +
         t_vertex_.capacity() + midpoint_table;
}

}  // namespace lhr
