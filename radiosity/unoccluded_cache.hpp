#pragma once
// Per interaction graph, the exact unoccluded form factor from its whole
// shooter at the receiver vertices push() interpolates at (docs/design.md §4,
// "Interaction graphs", push): the receiver's vertices that are not graph
// vertices. At a graph vertex it is the sum of the links' unoccluded form
// factors, read from them where needed, so it is not kept; elsewhere it costs
// a form factor from all of S, so it is computed once and kept, in vertex
// order, 16 bits each (UnitFloat16; BENCHMARKS.md, "Tables sized by the
// graph's own cut", "Graph storage under 30 %").

#include <cstddef>
#include <cstdint>
#include <vector>

#include "radiosity/compact_tables.hpp"
#include "radiosity/interaction_graph.hpp"

namespace lhr {

class UnoccludedCache {
 public:
  // Brings the table to the receiver's first `receiver_vertices` vertices and
  // to g as it stands: a vertex g has made its own since the last call drops
  // its value, a receiver vertex new since then gets NaN (not computed yet).
  // Graph vertices and receiver vertices are only ever added.
  void update(const InteractionGraph& g, std::size_t receiver_vertices);
  // Value k belongs to the k-th receiver vertex, in id order, that is not a
  // graph vertex.
  std::vector<UnitFloat16>& values() { return values_; }
  std::size_t bytes() const { return sizeof(*this) + values_.capacity() * sizeof(UnitFloat16); }

 private:
  std::vector<UnitFloat16> values_;
  std::uint32_t receiver_vertices_ = 0;  // as of the last update
  std::uint32_t graph_vertices_ = 0;
};

}  // namespace lhr
