#include "radiosity/interaction_graph.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace lhr {

InteractionGraph::Start::Start(const SurfaceHierarchy& receiver) {
  roots.resize(receiver.num_roots());
  for (std::size_t f = 0; f < roots.size(); ++f) roots[f] = receiver.root(static_cast<int>(f));
  VertexId last = -1;
  for (NodeId root : roots) {
    for (VertexId v : receiver.corners(root)) last = std::max(last, v);
  }
  index.assign(static_cast<std::size_t>(last + 1), -1);
  vertices.reserve(index.size());
  for (NodeId root : roots) {
    for (VertexId v : receiver.corners(root)) {
      if (index[v] >= 0) continue;
      index[v] = static_cast<std::int32_t>(vertices.size());
      vertices.push_back(v);
    }
  }
  vertices.shrink_to_fit();
}

std::size_t InteractionGraph::Start::bytes() const {
  return sizeof(*this) + roots.capacity() * sizeof(NodeId) + vertices.capacity() * sizeof(VertexId) +
         index.capacity() * sizeof(std::int32_t);
}

InteractionGraph::InteractionGraph(int shooter_surface, int receiver_surface, std::shared_ptr<const Start> start)
    : shooter_(shooter_surface),
      receiver_(receiver_surface),
      start_(std::move(start)),
      num_start_(static_cast<int>(start_->vertices.size())) {
  // Sized exactly: a scene of many small shooters holds one graph per
  // shooter and receiver, most of which never split, and growth by doubling
  // would leave up to half of each graph's per-vertex tables unused.
  first_.assign(start_->vertices.size() + 1, 0);
}

void InteractionGraph::set_state(NodeId n, NodeState s) {
  const auto k = static_cast<std::size_t>(n);
  std::vector<std::uint8_t>& state = cut_->state;
  if (k >= 4 * state.size()) state.resize(k / 4 + 1, 0);
  if (this->state(n) == NodeState::kLeaf) --cut_->num_leaves;
  if (s == NodeState::kLeaf) ++cut_->num_leaves;
  const unsigned shift = 2 * (k & 3);
  state[k >> 2] = static_cast<std::uint8_t>((state[k >> 2] & ~(3u << shift)) | (static_cast<unsigned>(s) << shift));
}

int InteractionGraph::add_vertex(VertexId v) {
  const int i = static_cast<int>(num_vertices());
  cut_->vertices.push_back(static_cast<std::uint32_t>(v));
  const std::size_t k = static_cast<std::size_t>(v) - start_->index.size();
  cut_->index.grow(k + 1, 0);
  cut_->index.set(k, static_cast<std::uint32_t>(i) + 1);
  first_.push_back(first_.back());
  return i;
}

std::vector<NodeId> InteractionGraph::leaves(const SurfaceHierarchy& receiver) const {
  if (!cut_) return start_->roots;
  std::vector<NodeId> out;
  out.reserve(cut_->num_leaves);
  std::vector<NodeId> stack;
  for (NodeId root : start_->roots) {
    stack.push_back(root);
    while (!stack.empty()) {
      const NodeId n = stack.back();
      stack.pop_back();
      const NodeState s = state(n);
      if (s == NodeState::kLeaf) {
        out.push_back(n);
      } else if (s == NodeState::kInterior) {
        for (int c = 3; c >= 0; --c) stack.push_back(receiver.child(n, c));
      }
    }
  }
  return out;
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
  if (!cut_) {
    // The first split: the cut stops being R's roots.
    const std::vector<NodeId>& roots = start_->roots;
    cut_ = std::make_unique<Cut>();
    cut_->num_leaves = static_cast<std::uint32_t>(roots.size());
    cut_->state.assign((roots.size() + 3) / 4, 0);
    for (NodeId root : roots) {
      const auto k = static_cast<std::size_t>(root);
      cut_->state[k >> 2] |= static_cast<std::uint8_t>(static_cast<unsigned>(NodeState::kLeaf) << (2 * (k & 3)));
    }
  }
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
  if (!links_.empty() || growing_) {
    throw std::logic_error("InteractionGraph::set_every_vertex_link: the graph has links already");
  }
  const std::size_t n = num_vertices();
  if (n > std::numeric_limits<std::uint32_t>::max()) {
    throw std::length_error("InteractionGraph: more than 2^32 links in one graph");
  }
  links_.assign(n, link);
  for (std::size_t i = 0; i < n; ++i) first_.set(i + 1, static_cast<std::uint32_t>(i + 1));
}

void InteractionGraph::add_link(int i, const GraphLink& link) {
  if (!growing_) growing_ = std::make_unique<std::unordered_map<int, std::vector<GraphLink>>>();
  auto [it, added] = growing_->try_emplace(i);
  if (added) {
    const std::span<const GraphLink> packed(links_.data() + first_[i], first_[i + 1] - first_[i]);
    it->second.assign(packed.begin(), packed.end());
  }
  it->second.push_back(link);
}

void InteractionGraph::set_links(int i, std::span<const GraphLink> links) {
  if (!this->links(i).empty()) throw std::logic_error("InteractionGraph::set_links: the vertex has links already");
  if (!growing_) growing_ = std::make_unique<std::unordered_map<int, std::vector<GraphLink>>>();
  (*growing_)[i].assign(links.begin(), links.end());
}

void InteractionGraph::replace_links(int i, std::span<const GraphLink> links) {
  if (!growing_) growing_ = std::make_unique<std::unordered_map<int, std::vector<GraphLink>>>();
  (*growing_)[i].assign(links.begin(), links.end());
}

void InteractionGraph::pack_links() {
  // Splits grew these by doubling; a graph that splits no more keeps them
  // as they stand.
  if (cut_) {
    cut_->state.shrink_to_fit();
    cut_->vertices.shrink_to_fit();
    cut_->index.shrink_to_fit();
  }
  if (!growing_) {
    first_.shrink_to_fit();
    return;
  }
  std::size_t total = links_.size();
  for (const auto& [i, list] : *growing_) total += list.size() - (first_[i + 1] - first_[i]);
  if (total > std::numeric_limits<std::uint32_t>::max()) {
    throw std::length_error("InteractionGraph: more than 2^32 links in one graph");
  }
  std::vector<GraphLink> packed;
  packed.reserve(total);
  CompactUints first;
  first.reserve(first_.size());
  first.push_back(0);
  for (std::size_t i = 0; i + 1 < first_.size(); ++i) {
    if (const auto it = growing_->find(static_cast<int>(i)); it != growing_->end()) {
      packed.insert(packed.end(), it->second.begin(), it->second.end());
    } else {
      packed.insert(packed.end(), links_.begin() + first_[i], links_.begin() + first_[i + 1]);
    }
    first.push_back(static_cast<std::uint32_t>(packed.size()));
  }
  growing_.reset();
  links_ = std::move(packed);
  first_ = std::move(first);
}

std::size_t InteractionGraph::drop_links(const std::function<bool(const GraphLink&)>& drop) {
  pack_links();
  std::vector<GraphLink> kept;
  CompactUints first;
  first.reserve(first_.size());
  first.push_back(0);
  for (std::size_t i = 0; i + 1 < first_.size(); ++i) {
    for (std::size_t k = first_[i]; k < first_[i + 1]; ++k) {
      if (!drop(links_[k])) kept.push_back(links_[k]);
    }
    first.push_back(static_cast<std::uint32_t>(kept.size()));
  }
  const std::size_t dropped = links_.size() - kept.size();
  if (dropped > 0) {
    kept.shrink_to_fit();
    links_ = std::move(kept);
    first_ = std::move(first);
  }
  return dropped;
}

std::size_t InteractionGraph::num_links() const {
  std::size_t n = links_.size();
  if (!growing_) return n;
  for (const auto& [i, list] : *growing_) n += list.size() - (first_[i + 1] - first_[i]);
  return n;
}

std::size_t InteractionGraph::link_bytes() const {
  std::size_t bytes = links_.capacity() * sizeof(GraphLink);
  if (!growing_) return bytes;
  for (const auto& [i, list] : *growing_) bytes += list.capacity() * sizeof(GraphLink);
  return bytes;
}

std::size_t InteractionGraph::bytes() const {
  std::size_t bytes = sizeof(*this) + first_.bytes();
  if (cut_) {
    bytes += sizeof(Cut) + cut_->state.capacity() + cut_->vertices.bytes() +
             cut_->index.bytes();
  }
  if (growing_) {
    // The map's bucket array and one node (key, vector, next pointer) per list.
    bytes += sizeof(*growing_) + growing_->bucket_count() * sizeof(void*) +
             growing_->size() * (sizeof(std::pair<const int, std::vector<GraphLink>>) + sizeof(void*));
  }
  return bytes;
}

}  // namespace lhr
