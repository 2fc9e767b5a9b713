#pragma once
// Interaction graph (paper §5, docs/design.md §4): what one shooter surface S gives one
// receiver surface R. Its leaves are a restricted quadtree cut of R's
// hierarchy (the levels where S contributes); its vertices are the corners of
// those leaves, each with the links from S's elements. S's contribution
// there is not stored: it is summed from the links where it is read (the
// solver's push and receiver oracle). The graph owns no geometry: node and
// vertex ids are R's.

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

#include "mesh/hierarchy.hpp"
#include "radiosity/compact_tables.hpp"
#include "radiosity/transport.hpp"

namespace lhr {

// Shooter element: a node of S's quadtree (linear basis, three coefficients),
// or ≤ kWholeSurface: root cluster −(shooter+2) of S (constant basis, f[0]).
constexpr NodeId kWholeSurface = -2;
inline bool is_cluster_element(NodeId e) { return e <= kWholeSurface; }
inline int cluster_index(NodeId e) { return -(e + 2); }
inline NodeId cluster_element(int cluster) { return -(cluster + 2); }

// GraphLink::judged_fraction of a link with no draw before it.
constexpr float kJudgedByPilot = -1.0f;

struct GraphLink {
  NodeId shooter;
  TransportCoefficients coefficients;
  // The visible fraction the shooter oracle judges this link by, as a share
  // of its exact unoccluded form factor: the draw of the link it was split
  // or copied from, never its own, so that which links are kept does not
  // depend on what their own rays found (docs/accuracy.md, "Judged by
  // another draw"). A first link has no draw before it: it is made with
  // kJudgedByPilot, and its coefficients' computation judges it by a pilot
  // draw of its own that it then discards.
  float judged_fraction = 1.0f;

  // The visible fraction of its own draw (a cluster's shape factor
  // included); 1 without an exact form factor to divide by.
  float drawn_fraction() const {
    return coefficients.unoccluded > 0.0f ? coefficients.visible() / coefficients.unoccluded : 1.0f;
  }
};

class InteractionGraph {
 public:
  enum class NodeState : std::uint8_t { kOutside = 0, kLeaf = 1, kInterior = 2 };

  // What every graph on one receiver starts from: R's roots, every initial
  // vertex a graph vertex (the minimum density of paper §4.1). One copy is
  // shared by all graphs on R: with many shooters (10 000 lamps over a
  // floor, docs/robustness.md "Budgets") the graphs that never split would
  // otherwise each hold the same root and vertex tables.
  struct Start {
    std::vector<NodeId> roots;       // 0 … num_roots − 1, the first leaves
    std::vector<VertexId> vertices;  // the roots' corners, first seen first
    std::vector<std::int32_t> index;  // per initial vertex id: its place in `vertices`, or −1
    explicit Start(const SurfaceHierarchy& receiver);
    std::size_t bytes() const;
  };

  InteractionGraph(int shooter_surface, int receiver_surface, std::shared_ptr<const Start> start);
  InteractionGraph(int shooter_surface, int receiver_surface, const SurfaceHierarchy& receiver)
      : InteractionGraph(shooter_surface, receiver_surface, std::make_shared<const Start>(receiver)) {}
  const Start& start() const { return *start_; }

  int shooter_surface() const { return shooter_; }
  int receiver_surface() const { return receiver_; }

  NodeState state(NodeId n) const {
    const auto k = static_cast<std::size_t>(n);
    if (!cut_) return k < start_->roots.size() ? NodeState::kLeaf : NodeState::kOutside;
    const std::vector<std::uint8_t>& state = cut_->state;
    return k < 4 * state.size() ? static_cast<NodeState>((state[k >> 2] >> (2 * (k & 3))) & 3u)
                                : NodeState::kOutside;
  }
  // Graph leaves, read off the node states: root by root, each root's
  // leaves depth first, children in order (deterministic).
  std::vector<NodeId> leaves(const SurfaceHierarchy& receiver) const;
  std::size_t num_leaves() const { return cut_ ? cut_->num_leaves : start_->roots.size(); }
  // The graph leaf containing R's node n (n or an ancestor), or kNoNode if n
  // is above the cut.
  NodeId leaf_containing(NodeId n, const SurfaceHierarchy& receiver) const;

  std::size_t num_vertices() const { return first_.size() - 1; }
  VertexId vertex(int i) const {
    return i < num_start_ ? start_->vertices[i] : static_cast<VertexId>(cut_->vertices[i - num_start_]);
  }
  // Index of R's vertex v in this graph, or -1.
  int index_of(VertexId v) const {
    const auto k = static_cast<std::size_t>(v);
    const std::size_t base = start_->index.size();
    if (k < base) return start_->index[k];
    return cut_ && k - base < cut_->index.size() ? static_cast<int>(cut_->index[k - base]) - 1 : -1;
  }
  // Vertex i's links. A view: add_link() and set_links() move them.
  std::span<GraphLink> links(int i) {
    if (growing_) {
      if (const auto it = growing_->find(i); it != growing_->end()) return it->second;
    }
    return {links_.data() + first_[i], first_[i + 1] - first_[i]};
  }
  std::span<const GraphLink> links(int i) const {
    if (growing_) {
      if (const auto it = growing_->find(i); it != growing_->end()) return it->second;
    }
    return {links_.data() + first_[i], first_[i + 1] - first_[i]};
  }
  // Every vertex's one link, before any other (a new shooter's first links).
  void set_every_vertex_link(const GraphLink& link);
  void add_link(int i, const GraphLink& link);
  // Vertex i's links become `links` (a new vertex, which had none).
  void set_links(int i, std::span<const GraphLink> links);
  // Vertex i's links become `links`, whatever it held (coarsened links).
  void replace_links(int i, std::span<const GraphLink> links);
  // Drops every link `drop` holds true for, in one pass over the packed
  // links; returns how many went. A vertex may be left with none.
  std::size_t drop_links(const std::function<bool(const GraphLink&)>& drop);
  // Puts the lists that grew since the last call back into the one array,
  // each vertex's links in their order, and gives back the room the tables
  // grew into during the pass.
  void pack_links();
  // S's unoccluded form factor at vertex i: Σ_links of theirs, summed in
  // double and kept in float, as they are.
  float unoccluded(int i) const {
    double sum = 0.0;
    for (const GraphLink& link : links(i)) sum += link.coefficients.unoccluded;
    return static_cast<float>(sum);
  }

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
  // Bytes of this graph's own storage: node states, vertex tables, link
  // offsets (links: link_bytes()). The shared Start is its owner's to count.
  std::size_t bytes() const;
  std::size_t link_bytes() const;

 private:
  void set_state(NodeId n, NodeState s);
  int add_vertex(VertexId v);

  int shooter_;
  int receiver_;
  std::shared_ptr<const Start> start_;
  int num_start_;  // start_->vertices.size(): graph vertices 0 … num_start_ − 1
  // What a graph holds once it splits; null until then (the cut is R's
  // roots), so a graph that never splits (most of a scene of many small
  // shooters) carries one pointer for it, not three vectors' headers.
  struct Cut {
    // Two bits per R node up to the last one the cut has reached (4 per
    // byte). The leaves are read off them (leaves()), not listed: a list
    // cost 4 bytes a leaf, about 8 a graph vertex (BENCHMARKS.md, "Tables
    // sized by the graph's own cut").
    std::vector<std::uint8_t> state;
    std::uint32_t num_leaves = 0;
    // The graph vertices after the start's, and per R vertex id from
    // start_->index.size() on, its index here plus one, or 0: dense, 2 bytes
    // (4 in a graph past 65 535 vertices) per vertex R made since the start
    // up to the last this graph holds, since lookups are on every oracle's
    // path and direct.
    CompactUints vertices;  // R's vertex ids, 16 bits each below 65 536
    CompactUints index;
  };
  std::unique_ptr<Cut> cut_;
  // Every vertex's links in one array, vertex i's at [first_[i],
  // first_[i + 1]): a small vector per vertex cost a 24-byte header, an
  // allocation and its spare capacity, for lists of one to a few hundred
  // links. A list that grows during a refinement pass is copied out to
  // growing_ and packed back in afterwards (pack_links); the map itself is
  // held only while some list grows. The offsets take 2 bytes a vertex in a
  // graph of fewer than 65 536 links (CompactUints).
  std::vector<GraphLink> links_;
  CompactUints first_;
  std::unique_ptr<std::unordered_map<int, std::vector<GraphLink>>> growing_;
};

}  // namespace lhr
