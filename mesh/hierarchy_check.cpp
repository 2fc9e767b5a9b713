#include "mesh/hierarchy_check.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "mesh/edge_key.hpp"

namespace lhr {

namespace {

std::string node_name(NodeId n) { return "node " + std::to_string(n); }

std::string edge_name(NodeId n, int k) { return "node " + std::to_string(n) + " edge " + std::to_string(k); }

}  // namespace

std::vector<Violation> check_hierarchy(const SurfaceHierarchy& h) {
  std::vector<Violation> out;
  auto report = [&out](std::string kind, std::string where, std::string detail) {
    out.push_back({std::move(kind), std::move(where), std::move(detail)});
  };
  const auto num_nodes = static_cast<NodeId>(h.num_nodes());
  const auto num_vertices = static_cast<VertexId>(h.num_vertices());
  const auto num_roots = static_cast<NodeId>(h.num_roots());
  auto valid_vertex = [&](VertexId v) { return v >= 0 && v < num_vertices; };

  // Parent/child structure, documented child corners, midpoint placement.
  std::size_t leaf_count = 0;
  bool corners_ok = true;
  for (NodeId n = 0; n < num_nodes; ++n) {
    const auto& c = h.corners(n);
    if (!valid_vertex(c[0]) || !valid_vertex(c[1]) || !valid_vertex(c[2]) || c[0] == c[1] || c[1] == c[2] ||
        c[2] == c[0]) {
      report("corners", node_name(n), "corner ids out of range or repeated");
      corners_ok = false;
      continue;
    }
    if (n < num_roots) {
      if (h.level(n) != 0 || h.parent(n) != kNoNode || h.child_index(n) != -1 || h.root_face(n) != n) {
        report("root", node_name(n), "a root must have level 0, no parent, child index -1 and root face == id");
      }
      for (int k = 0; k < 3; ++k) {
        if (h.vertex_level(c[k]) != 0) {
          report("vertex-level", node_name(n), "root corner " + std::to_string(c[k]) + " is not a level-0 vertex");
        }
      }
    } else {
      const NodeId p = h.parent(n);
      const int ci = h.child_index(n);
      if (p < 0 || p >= n || ci < 0 || ci > 3 || h.is_leaf(p) || h.child(p, ci) != n) {
        report("parent", node_name(n), "parent " + std::to_string(p) + " / child index " + std::to_string(ci) +
                                           " do not lead back to this node");
      } else if (h.level(n) != h.level(p) + 1 || h.root_face(n) != h.root_face(p)) {
        report("level", node_name(n), "level or root face differs from parent's");
      }
    }
    if (h.is_leaf(n)) {
      ++leaf_count;
      continue;
    }
    const NodeId first = h.child(n, 0);
    if (first <= n || first > num_nodes - 4) {
      report("children", node_name(n), "first child " + std::to_string(first) + " out of range");
      continue;
    }
    std::array<VertexId, 3> m{};
    bool have_midpoints = true;
    for (int k = 0; k < 3; ++k) {
      const VertexId a = c[k];
      const VertexId b = c[(k + 1) % 3];
      m[k] = h.midpoint(a, b);
      if (m[k] == kNoVertex || m[k] != h.midpoint(b, a) || !valid_vertex(m[k])) {
        report("midpoint", edge_name(n, k), "split node has no shared midpoint for its edge");
        have_midpoints = false;
        continue;
      }
      const Vec3 pa = h.point(a), pb = h.point(b), pm = h.point(m[k]);
      const double scale = std::max({pa.norm(), pb.norm(), (pa - pb).norm(), 1e-300});
      if (!((pm - 0.5 * (pa + pb)).norm() <= 1e-12 * scale)) {
        report("midpoint", "vertex " + std::to_string(m[k]),
               "not at the midpoint of edge (" + std::to_string(a) + "," + std::to_string(b) + ")");
      }
      if (h.vertex_level(m[k]) != h.level(n) + 1) {
        report("vertex-level", "vertex " + std::to_string(m[k]),
               "level " + std::to_string(h.vertex_level(m[k])) + ", expected " + std::to_string(h.level(n) + 1));
      }
    }
    if (!have_midpoints) continue;
    const std::array<std::array<VertexId, 3>, 4> expected = {{
        {c[0], m[0], m[2]},
        {m[0], c[1], m[1]},
        {m[2], m[1], c[2]},
        {m[1], m[2], m[0]},
    }};
    for (int i = 0; i < 4; ++i) {
      const NodeId ch = first + i;
      if (h.corners(ch) != expected[i]) {
        report("children", node_name(ch), "corners are not child " + std::to_string(i) + " of " + node_name(n));
      }
      if (h.parent(ch) != n || h.child_index(ch) != i) {
        report("children", node_name(ch), "parent pointer or child index does not match " + node_name(n));
      }
    }
  }
  if (leaf_count != h.num_leaves()) {
    report("num-leaves", "hierarchy",
           "num_leaves() = " + std::to_string(h.num_leaves()) + ", counted " + std::to_string(leaf_count));
  }
  if (!corners_ok) return out;

  // Every undirected edge of every node -> the nodes having it (at most two).
  std::unordered_map<std::uint64_t, std::array<NodeId, 2>> edge_nodes;
  edge_nodes.reserve(3 * static_cast<std::size_t>(num_nodes));
  for (NodeId n = 0; n < num_nodes; ++n) {
    const auto& c = h.corners(n);
    for (int k = 0; k < 3; ++k) {
      auto [it, inserted] = edge_nodes.try_emplace(edge_key(c[k], c[(k + 1) % 3]), std::array{n, kNoNode});
      if (inserted) continue;
      if (it->second[1] == kNoNode) {
        it->second[1] = n;
      } else {
        report("non-manifold-edge", edge_name(n, k), "more than two nodes share this edge");
      }
    }
  }
  auto other_node = [&](NodeId n, VertexId a, VertexId b) {
    const auto it = edge_nodes.find(edge_key(a, b));
    if (it == edge_nodes.end()) return kNoNode;
    return it->second[0] == n ? it->second[1] : it->second[0];
  };

  // Neighbour links and boundary flags agree with the shared edges.
  for (NodeId n = 0; n < num_nodes; ++n) {
    const auto& c = h.corners(n);
    for (int k = 0; k < 3; ++k) {
      const NodeId q = other_node(n, c[k], c[(k + 1) % 3]);
      if (h.neighbor(n, k) != q) {
        report("neighbor", edge_name(n, k),
               "neighbor() = " + std::to_string(h.neighbor(n, k)) + ", the node sharing the edge is " +
                   std::to_string(q));
      }
      if (q != kNoNode && h.level(q) != h.level(n)) {
        report("neighbor", edge_name(n, k), "the node sharing this edge has another level");
      }
      bool boundary = false;
      if (n < num_roots) {
        boundary = q == kNoNode;
      } else {
        const int ci = h.child_index(n);
        boundary = ci != 3 && (k == ci || k == (ci + 2) % 3) && h.is_boundary_edge(h.parent(n), k);
      }
      if (h.is_boundary_edge(n, k) != boundary || (boundary && q != kNoNode)) {
        report("boundary", edge_name(n, k), "boundary flag disagrees with the edges of the hierarchy");
      }
    }
  }

  // Restricted property, checked from the coarse side of every leaf edge:
  // if the node across is split, the leaves along the shared edge must be
  // its children, one level finer. (A leaf with a coarser neighbour is the
  // fine side of that neighbour's check.)
  for (NodeId n = 0; n < num_nodes; ++n) {
    if (!h.is_leaf(n)) continue;
    const auto& c = h.corners(n);
    for (int k = 0; k < 3; ++k) {
      const VertexId a = c[k], b = c[(k + 1) % 3];
      const NodeId q = other_node(n, a, b);
      const VertexId m = h.midpoint(a, b);
      if (q == kNoNode || h.is_leaf(q)) {
        if (m != kNoVertex) report("midpoint", edge_name(n, k), "midpoint exists but no node across is split");
        continue;
      }
      if (m == kNoVertex) continue;  // reported above for q
      for (const auto& [s, t] : {std::pair{a, m}, std::pair{m, b}}) {
        const NodeId fine = other_node(kNoNode, s, t);
        if (fine == kNoNode || !h.is_leaf(fine)) {
          report("restricted", edge_name(n, k),
                 "leaf of level " + std::to_string(h.level(n)) +
                     " is adjacent to leaves more than one level finer across edge (" + std::to_string(a) + "," +
                     std::to_string(b) + ")");
          break;
        }
      }
    }
  }

  // T-vertices recounted: every vertex strictly inside a leaf edge, found by
  // recursive midpoints of the edge.
  std::vector<std::uint8_t> expected_t(static_cast<std::size_t>(num_vertices), 0);
  auto mark_inside = [&](auto&& self, VertexId a, VertexId b, int depth) -> void {
    const VertexId m = h.midpoint(a, b);
    if (m == kNoVertex || depth > SurfaceHierarchy::kMaxLevel) return;
    expected_t[m] = 1;
    self(self, a, m, depth + 1);
    self(self, m, b, depth + 1);
  };
  for (NodeId n = 0; n < num_nodes; ++n) {
    if (!h.is_leaf(n)) continue;
    const auto& c = h.corners(n);
    for (int k = 0; k < 3; ++k) mark_inside(mark_inside, c[k], c[(k + 1) % 3], 0);
  }
  for (VertexId v = 0; v < num_vertices; ++v) {
    if ((expected_t[v] != 0) != h.is_t_vertex(v)) {
      report("t-vertex", "vertex " + std::to_string(v),
             std::string("is_t_vertex() = ") + (h.is_t_vertex(v) ? "true" : "false") + ", recount says " +
                 (expected_t[v] != 0 ? "true" : "false"));
    }
  }
  return out;
}

}  // namespace lhr
