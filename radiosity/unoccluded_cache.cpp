#include "radiosity/unoccluded_cache.hpp"

#include <limits>

namespace lhr {

void UnoccludedCache::update(const InteractionGraph& g, std::size_t receiver_vertices) {
  const std::size_t old_receiver = receiver_vertices_;
  const int old_graph = static_cast<int>(graph_vertices_);
  // The kept values stay in vertex order: a vertex that became a graph
  // vertex leaves a gap that the later values close, in place, and the
  // receiver's new vertices come after all the old ones.
  std::size_t read = 0, write = 0, added = 0;
  for (std::size_t v = 0; v < receiver_vertices; ++v) {
    const int i = g.index_of(static_cast<VertexId>(v));
    if (v >= old_receiver) {
      added += i < 0;
      continue;
    }
    if (i >= 0 && i < old_graph) continue;  // a graph vertex then and now
    const UnitFloat16 value = values_[read++];
    if (i < 0) values_[write++] = value;
  }
  // Sized exactly: every graph keeps one, and doubling would leave up to
  // half of each unused.
  values_.resize(write);
  if (write + added > values_.capacity()) {
    std::vector<UnitFloat16> grown;
    grown.reserve(write + added);
    grown.assign(values_.begin(), values_.end());
    values_ = std::move(grown);
  }
  values_.resize(write + added, UnitFloat16(std::numeric_limits<float>::quiet_NaN()));
  if (values_.capacity() > values_.size()) values_.shrink_to_fit();
  receiver_vertices_ = static_cast<std::uint32_t>(receiver_vertices);
  graph_vertices_ = static_cast<std::uint32_t>(g.num_vertices());
}

}  // namespace lhr
