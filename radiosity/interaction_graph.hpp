#pragma once
// Interaction graph (paper §5, docs/design.md §4): what one shooter surface S gives one
// receiver surface R. Its leaves are a restricted quadtree cut of R's
// hierarchy (the levels where S contributes); its vertices are the corners of
// those leaves, each with the links from S's elements and S's contribution
// there. The graph owns no geometry: node and vertex ids are R's.

#include <cstdint>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

#include "mesh/hierarchy.hpp"
#include "radiosity/transport.hpp"

namespace lhr {

// Shooter element: a node of S's quadtree (linear basis, three coefficients),
// or ≤ kWholeSurface: root cluster −(shooter+2) of S (constant basis, f[0]).
constexpr NodeId kWholeSurface = -2;
inline bool is_cluster_element(NodeId e) { return e <= kWholeSurface; }
inline int cluster_index(NodeId e) { return -(e + 2); }
inline NodeId cluster_element(int cluster) { return -(cluster + 2); }

struct GraphLink {
  NodeId shooter;
  TransportCoefficients coefficients;
};

class InteractionGraph {
 public:
  enum class NodeState : std::uint8_t { kOutside = 0, kLeaf = 1, kInterior = 2 };

  // The graph starts on R's roots, every initial vertex a graph vertex (the
  // minimum density of paper §4.1).
  InteractionGraph(int shooter_surface, int receiver_surface, const SurfaceHierarchy& receiver);

  int shooter_surface() const { return shooter_; }
  int receiver_surface() const { return receiver_; }

  NodeState state(NodeId n) const {
    return static_cast<std::size_t>(n) < state_.size() ? static_cast<NodeState>(state_[n]) : NodeState::kOutside;
  }
  // Graph leaves, in the order the splits left them (deterministic).
  const std::vector<NodeId>& leaves() const { return leaves_; }
  std::size_t num_leaves() const { return leaves_.size(); }
  // The graph leaf containing R's node n (n or an ancestor), or kNoNode if n
  // is above the cut.
  NodeId leaf_containing(NodeId n, const SurfaceHierarchy& receiver) const;

  std::size_t num_vertices() const { return vertices_.size(); }
  VertexId vertex(int i) const { return vertices_[i]; }
  // Index of R's vertex v in this graph, or -1.
  int index_of(VertexId v) const { return static_cast<std::size_t>(v) < index_.size() ? index_[v] : -1; }
  // Vertex i's links. A view: add_link() and set_links() move them.
  std::span<GraphLink> links(int i) {
    if (!growing_.empty()) {
      if (const auto it = growing_.find(i); it != growing_.end()) return it->second;
    }
    return {links_.data() + first_[i], first_[i + 1] - first_[i]};
  }
  std::span<const GraphLink> links(int i) const {
    if (!growing_.empty()) {
      if (const auto it = growing_.find(i); it != growing_.end()) return it->second;
    }
    return {links_.data() + first_[i], first_[i + 1] - first_[i]};
  }
  // Every vertex's one link, before any other (a new shooter's first links).
  void set_every_vertex_link(const GraphLink& link);
  void add_link(int i, const GraphLink& link);
  // Vertex i's links become `links` (a new vertex, which had none).
  void set_links(int i, std::span<const GraphLink> links);
  // Puts the lists that grew since the last call back into the one array,
  // each vertex's links in their order.
  void pack_links();
  // S's contribution at vertex i before reflection: Σ_links Σ_l F^l B_j^l.
  Rgb& gathered(int i) { return gathered_[i]; }
  const Rgb& gathered(int i) const { return gathered_[i]; }

  // A new vertex and the vertex whose shooter elements it starts from.
  struct NewVertex {
    int index;
    int seed;
  };
  // Splits graph leaf n, and first any coarser graph leaf across its edges so
  // the cut stays restricted; splits R's hierarchy where it is still a leaf.
  // New graph vertices (edge midpoints) are appended to `created`, each
  // seeded by an end point of its edge. Returns false if n is not a graph leaf.
  bool split(NodeId n, SurfaceHierarchy& receiver, std::vector<NewVertex>& created);

  std::size_t num_links() const;
  // Bytes of this graph's own storage: node states, vertex table, links.
  std::size_t bytes() const;
  std::size_t link_bytes() const;

 private:
  void set_state(NodeId n, NodeState s);
  int add_vertex(VertexId v);

  int shooter_;
  int receiver_;
  std::vector<std::uint8_t> state_;  // per R node
  std::vector<NodeId> leaves_;
  std::vector<VertexId> vertices_;
  // Per R vertex: its index here or -1. Dense: 4 bytes per receiver vertex
  // cost less than a hash table's nodes once a graph holds a few per cent of
  // them, and lookups are direct.
  std::vector<std::int32_t> index_;
  // Every vertex's links in one array, vertex i's at [first_[i],
  // first_[i + 1]): a small vector per vertex cost a 24-byte header, an
  // allocation and its spare capacity, for lists of one to a few hundred
  // links. A list that grows during a refinement pass is copied out to
  // growing_ and packed back in afterwards (pack_links).
  std::vector<GraphLink> links_;
  std::vector<std::uint32_t> first_{0};
  std::unordered_map<int, std::vector<GraphLink>> growing_;
  std::vector<Rgb> gathered_;
};

}  // namespace lhr
