#include "radiosity/interaction_graph.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace lhr {

InteractionGraph::InteractionGraph(int shooter_surface, int receiver_surface, const SurfaceHierarchy& receiver)
    : shooter_(shooter_surface), receiver_(receiver_surface) {
  // Sized exactly: a scene of many small shooters holds one graph per
  // shooter and receiver, most of which never split, and growth by doubling
  // would leave up to half of each graph's per-vertex tables unused.
  std::vector<VertexId> initial;
  initial.reserve(3 * receiver.num_roots());
  for (std::size_t f = 0; f < receiver.num_roots(); ++f) {
    for (VertexId v : receiver.corners(receiver.root(static_cast<int>(f)))) initial.push_back(v);
  }
  std::sort(initial.begin(), initial.end());
  initial.erase(std::unique(initial.begin(), initial.end()), initial.end());
  vertices_.reserve(initial.size());
  first_.reserve(initial.size() + 1);
  gathered_.reserve(initial.size());
  if (!initial.empty()) index_.reserve(static_cast<std::size_t>(initial.back()) + 1);
  leaves_.reserve(receiver.num_roots());
  state_.reserve(receiver.num_roots());
  for (std::size_t f = 0; f < receiver.num_roots(); ++f) {
    set_state(receiver.root(static_cast<int>(f)), NodeState::kLeaf);
    for (VertexId v : receiver.corners(receiver.root(static_cast<int>(f)))) {
      if (index_of(v) < 0) add_vertex(v);
    }
  }
}

void InteractionGraph::set_state(NodeId n, NodeState s) {
  if (static_cast<std::size_t>(n) >= state_.size()) state_.resize(static_cast<std::size_t>(n) + 1, 0);
  if (static_cast<NodeState>(state_[n]) == NodeState::kLeaf) {
    // The last leaf takes the removed one's place: O(1) after the search.
    auto it = std::find(leaves_.begin(), leaves_.end(), n);
    *it = leaves_.back();
    leaves_.pop_back();
  }
  if (s == NodeState::kLeaf) leaves_.push_back(n);
  state_[n] = static_cast<std::uint8_t>(s);
}

int InteractionGraph::add_vertex(VertexId v) {
  const int i = static_cast<int>(vertices_.size());
  vertices_.push_back(v);
  if (static_cast<std::size_t>(v) >= index_.size()) index_.resize(static_cast<std::size_t>(v) + 1, -1);
  index_[v] = i;
  first_.push_back(first_.back());
  gathered_.emplace_back(0, 0, 0);
  return i;
}

NodeId InteractionGraph::leaf_containing(NodeId n, const SurfaceHierarchy& receiver) const {
  for (NodeId a = n; a != kNoNode; a = receiver.parent(a)) {
    const NodeState s = state(a);
    if (s == NodeState::kLeaf) return a;
    if (s == NodeState::kInterior) return kNoNode;
  }
  return kNoNode;
}

bool InteractionGraph::split(NodeId n, SurfaceHierarchy& receiver, std::vector<NewVertex>& created) {
  if (state(n) != NodeState::kLeaf) return false;
  if (receiver.is_leaf(n)) receiver.split(n);
  // R is restricted, so n now has a same-level neighbour across every inner
  // edge; a graph leaf coarser than n across an edge would end up two levels
  // above n's children: split it first (the graph cut stays restricted).
  for (int k = 0; k < 3; ++k) {
    const NodeId across = receiver.neighbor(n, k);
    if (across == kNoNode) continue;
    const NodeId coarse = leaf_containing(across, receiver);
    if (coarse != kNoNode && coarse != across) split(coarse, receiver, created);
  }
  set_state(n, NodeState::kInterior);
  for (int c = 0; c < 4; ++c) set_state(receiver.child(n, c), NodeState::kLeaf);
  // The centre child's corner k is the midpoint of n's edge (k+1, k+2).
  const auto& parent = receiver.corners(n);
  const auto& centre = receiver.corners(receiver.child(n, 3));
  for (int k = 0; k < 3; ++k) {
    const VertexId m = centre[k];
    if (index_of(m) >= 0) continue;
    const int seed = index_of(parent[(k + 1) % 3]);
    if (seed < 0) throw std::logic_error("InteractionGraph::split: a graph leaf's corner is not a graph vertex");
    created.push_back({add_vertex(m), seed});
  }
  return true;
}

void InteractionGraph::set_every_vertex_link(const GraphLink& link) {
  if (!links_.empty() || !growing_.empty()) {
    throw std::logic_error("InteractionGraph::set_every_vertex_link: the graph has links already");
  }
  if (vertices_.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw std::length_error("InteractionGraph: more than 2^32 links in one graph");
  }
  links_.assign(vertices_.size(), link);
  for (std::size_t i = 0; i < vertices_.size(); ++i) first_[i + 1] = static_cast<std::uint32_t>(i + 1);
}

void InteractionGraph::add_link(int i, const GraphLink& link) {
  auto [it, added] = growing_.try_emplace(i);
  if (added) {
    const std::span<const GraphLink> packed(links_.data() + first_[i], first_[i + 1] - first_[i]);
    it->second.assign(packed.begin(), packed.end());
  }
  it->second.push_back(link);
}

void InteractionGraph::set_links(int i, std::span<const GraphLink> links) {
  if (!this->links(i).empty()) throw std::logic_error("InteractionGraph::set_links: the vertex has links already");
  growing_[i].assign(links.begin(), links.end());
}

void InteractionGraph::pack_links() {
  if (growing_.empty()) return;
  std::size_t total = links_.size();
  for (const auto& [i, list] : growing_) total += list.size() - (first_[i + 1] - first_[i]);
  if (total > std::numeric_limits<std::uint32_t>::max()) {
    throw std::length_error("InteractionGraph: more than 2^32 links in one graph");
  }
  std::vector<GraphLink> packed;
  packed.reserve(total);
  std::vector<std::uint32_t> first;
  first.reserve(first_.size());
  first.push_back(0);
  for (std::size_t i = 0; i + 1 < first_.size(); ++i) {
    if (const auto it = growing_.find(static_cast<int>(i)); it != growing_.end()) {
      packed.insert(packed.end(), it->second.begin(), it->second.end());
    } else {
      packed.insert(packed.end(), links_.begin() + first_[i], links_.begin() + first_[i + 1]);
    }
    first.push_back(static_cast<std::uint32_t>(packed.size()));
  }
  growing_ = {};
  links_ = std::move(packed);
  first_ = std::move(first);
}

std::size_t InteractionGraph::num_links() const {
  std::size_t n = links_.size();
  for (const auto& [i, list] : growing_) n += list.size() - (first_[i + 1] - first_[i]);
  return n;
}

std::size_t InteractionGraph::link_bytes() const {
  std::size_t bytes = links_.capacity() * sizeof(GraphLink);
  for (const auto& [i, list] : growing_) bytes += list.capacity() * sizeof(GraphLink);
  return bytes;
}

std::size_t InteractionGraph::bytes() const {
  return sizeof(*this) + state_.capacity() + leaves_.capacity() * sizeof(NodeId) +
         vertices_.capacity() * sizeof(VertexId) +
         index_.capacity() * sizeof(std::int32_t) +
         first_.capacity() * sizeof(std::uint32_t) + gathered_.capacity() * sizeof(Rgb) +
         growing_.size() * (sizeof(std::vector<GraphLink>) + 2 * sizeof(void*));
}

}  // namespace lhr
