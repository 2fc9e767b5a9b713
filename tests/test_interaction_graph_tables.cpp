// An interaction graph's own tables (paper §5 reports graphs ≈ 30 % over what
// they organise; BENCHMARKS.md, "Interaction graphs"): the graphs on one
// receiver share its roots and initial vertices, a graph that never splits
// holds only per-vertex values, and one that splits answers every lookup as
// the cut it holds says, checked against the hierarchy itself.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <set>
#include <vector>

#include "mesh/hierarchy.hpp"
#include "radiosity/compact_tables.hpp"
#include "radiosity/interaction_graph.hpp"
#include "radiosity/unoccluded_cache.hpp"
#include "scene_fixtures.hpp"

namespace lhr {
namespace {

// Per vertex the links' offset, in 16 bits below 65 536 links, and nothing
// else: no gathered value (the solver sums it from the links where it reads
// it), no table per root, per node or per receiver vertex.
std::size_t unsplit_bound(std::size_t vertices) {
  return sizeof(InteractionGraph) + (vertices + 1) * sizeof(std::uint16_t);
}

// CompactUints against a plain vector through every way it is written: the
// values read back are the ones written, 16 bits each until one needs more,
// 32 from then on.
TEST(InteractionGraphTables, CompactUintsReadBackWhatWasWrittenAndWidenOnlyWhenAValueNeedsIt) {
  std::mt19937 random(11);
  std::uniform_int_distribution<std::uint32_t> narrow(0, CompactUints::kNarrowMax);
  CompactUints compact;
  std::vector<std::uint32_t> plain;
  for (int i = 0; i < 1000; ++i) {
    const std::uint32_t v = narrow(random);
    compact.push_back(v);
    plain.push_back(v);
  }
  compact.grow(1200, 7);
  plain.resize(1200, 7);
  for (int i = 0; i < 300; ++i) {
    const std::size_t k = random() % plain.size();
    const std::uint32_t v = narrow(random);
    compact.set(k, v);
    plain[k] = v;
  }
  compact.shrink_to_fit();
  ASSERT_FALSE(compact.wide());
  EXPECT_EQ(compact.bytes(), plain.size() * sizeof(std::uint16_t));
  // One value past 16 bits widens the table and keeps every other value.
  compact.set(500, 0x12345u);
  plain[500] = 0x12345u;
  ASSERT_TRUE(compact.wide());
  compact.push_back(0xFFFFFFFFu);
  plain.push_back(0xFFFFFFFFu);
  compact.grow(1300, 0x10000u);
  plain.resize(1300, 0x10000u);
  compact.set(3, 65535);
  plain[3] = 65535;
  ASSERT_EQ(compact.size(), plain.size());
  for (std::size_t k = 0; k < plain.size(); ++k) ASSERT_EQ(compact[k], plain[k]) << k;
  EXPECT_EQ(compact.back(), plain.back());
  // Assigning values that fit makes it narrow again.
  compact.assign(10, 65535);
  EXPECT_FALSE(compact.wide());
  EXPECT_EQ(compact.size(), 10u);
  EXPECT_EQ(compact[9], 65535u);
  // A table that starts wide.
  const CompactUints wide(4, 70000);
  EXPECT_TRUE(wide.wide());
  EXPECT_EQ(wide[3], 70000u);
}

// Values base^x for x uniform in [lowest, highest], sorted: each is kept
// within 2^bits of itself, and a larger value is never kept smaller.
template <typename Stored>
void expect_kept_within_and_in_order(double base, double lowest, double highest, int bits, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> exponent(lowest, highest);
  std::vector<double> values;
  for (int i = 0; i < 20000; ++i) values.push_back(std::pow(base, exponent(random)));
  std::sort(values.begin(), values.end());
  double previous_in = 0.0;
  float previous_out = 0.0f;
  for (const double v : values) {
    const float stored = Stored(v);
    ASSERT_LE(std::abs(stored - v), std::ldexp(v, bits) * (1.0 + 1e-6)) << v;
    if (v > previous_in) {
      ASSERT_GE(stored, previous_out) << v;
    }
    previous_in = v;
    previous_out = stored;
  }
}

// BFloat16 keeps the importance's range with 8 significant bits: within
// 2^-8 of the value, exact on small integers (pixel counts), order kept.
TEST(InteractionGraphTables, BFloat16KeepsAValueWithinTwoToTheMinusEight) {
  EXPECT_EQ(static_cast<float>(BFloat16(0.0f)), 0.0f);
  for (int n = 0; n <= 256; ++n) EXPECT_EQ(static_cast<float>(BFloat16(static_cast<float>(n))), static_cast<float>(n));
  // 10^-30 … 10^30.
  expect_kept_within_and_in_order<BFloat16>(10.0, -30.0, 30.0, -8, 3);
  EXPECT_TRUE(std::isnan(static_cast<float>(BFloat16(std::nanf("")))));
}

// UnitFloat16 keeps a form factor in [2^-31, 2) within 2^-12 of itself,
// order kept; zero below, its largest value from 2 on, NaN as NaN.
TEST(InteractionGraphTables, UnitFloat16KeepsAFormFactorWithinTwoToTheMinusTwelve) {
  EXPECT_EQ(static_cast<float>(UnitFloat16(0.0f)), 0.0f);
  EXPECT_EQ(static_cast<float>(UnitFloat16(-0.5f)), 0.0f);
  EXPECT_EQ(static_cast<float>(UnitFloat16(1.0f)), 1.0f);
  EXPECT_EQ(static_cast<float>(UnitFloat16(0.5f)), 0.5f);
  EXPECT_EQ(static_cast<float>(UnitFloat16(std::ldexp(1.0f, -30))), std::ldexp(1.0f, -30));
  EXPECT_EQ(static_cast<float>(UnitFloat16(std::ldexp(1.0f, -32))), 0.0f);
  EXPECT_NEAR(static_cast<float>(UnitFloat16(5.0f)), 2.0f, 1e-3);
  EXPECT_LT(static_cast<float>(UnitFloat16(5.0f)), 2.0f);
  EXPECT_TRUE(UnitFloat16(std::nanf("")).is_nan());
  EXPECT_TRUE(std::isnan(static_cast<float>(UnitFloat16(std::nanf("")))));
  EXPECT_FALSE(UnitFloat16(1.9f).is_nan());
  // 2^-30 … 2^0.3.
  expect_kept_within_and_in_order<UnitFloat16>(2.0, -30.0, 0.3, -12, 7);
}

TEST(InteractionGraphTables, GraphsOnOneReceiverShareItsStartAndHoldOnlyPerVertexValues) {
  SurfaceHierarchy receiver = test::grid_hierarchy(21);  // 441 vertices, 800 roots
  // Other graphs have refined the receiver already.
  for (int f = 0; f < 50; ++f) receiver.split(receiver.root(f));
  const auto start = std::make_shared<const InteractionGraph::Start>(receiver);
  std::vector<InteractionGraph> graphs;
  for (int s = 0; s < 100; ++s) graphs.emplace_back(s, 0, start);
  const std::size_t vertices = 21 * 21;
  ASSERT_EQ(start->vertices.size(), vertices);
  ASSERT_EQ(start->roots.size(), receiver.num_roots());
  // The graph object itself: its shooter, receiver, start, links and their
  // offsets, and one pointer each for the tables of a cut and of lists
  // that grow, which a graph that never splits does not hold.
  EXPECT_LE(sizeof(InteractionGraph), 2 * sizeof(std::vector<GraphLink>) + 8 * sizeof(void*));
  for (const InteractionGraph& g : graphs) {
    EXPECT_EQ(&g.start(), start.get());
    ASSERT_EQ(g.num_vertices(), vertices);
    ASSERT_EQ(g.num_leaves(), receiver.num_roots());
    EXPECT_LE(g.bytes(), unsplit_bound(vertices));
  }
  // The roots are the leaves and every initial vertex is a graph vertex,
  // first seen first; nothing the other graphs made is in this one.
  const InteractionGraph& g = graphs.front();
  std::vector<int> seen(receiver.num_vertices(), -1);
  int next = 0;
  for (std::size_t f = 0; f < receiver.num_roots(); ++f) {
    const NodeId root = receiver.root(static_cast<int>(f));
    EXPECT_EQ(g.leaves(receiver)[f], root);
    EXPECT_EQ(g.state(root), InteractionGraph::NodeState::kLeaf);
    for (VertexId v : receiver.corners(root)) {
      if (seen[v] < 0) seen[v] = next++;
    }
  }
  for (VertexId v = 0; v < static_cast<VertexId>(receiver.num_vertices()); ++v) {
    EXPECT_EQ(g.index_of(v), seen[v]) << v;
    if (seen[v] >= 0) {
      EXPECT_EQ(g.vertex(seen[v]), v);
    }
  }
  for (NodeId n = static_cast<NodeId>(receiver.num_roots()); n < static_cast<NodeId>(receiver.num_nodes()); ++n) {
    EXPECT_EQ(g.state(n), InteractionGraph::NodeState::kOutside) << n;
  }
}

// What the cut of a graph says about every node and vertex of R, from the
// hierarchy alone: the leaves are disjoint and cover the roots, a node above
// a leaf is interior, one below or beside the cut is outside, and the graph
// vertices are the corners of its leaves, each at its own index.
void expect_lookups_match_the_cut(const InteractionGraph& g, const SurfaceHierarchy& r) {
  std::vector<InteractionGraph::NodeState> want(r.num_nodes(), InteractionGraph::NodeState::kOutside);
  std::set<VertexId> corners;
  const std::vector<NodeId> leaves = g.leaves(r);
  EXPECT_EQ(leaves.size(), g.num_leaves());
  for (NodeId leaf : leaves) {
    ASSERT_EQ(want[leaf], InteractionGraph::NodeState::kOutside) << "leaf twice: " << leaf;
    want[leaf] = InteractionGraph::NodeState::kLeaf;
    for (NodeId a = r.parent(leaf); a != kNoNode; a = r.parent(a)) {
      ASSERT_NE(want[a], InteractionGraph::NodeState::kLeaf) << "a leaf above a leaf: " << a;
      want[a] = InteractionGraph::NodeState::kInterior;
    }
    for (VertexId v : r.corners(leaf)) corners.insert(v);
  }
  for (NodeId n = 0; n < static_cast<NodeId>(r.num_nodes()); ++n) EXPECT_EQ(g.state(n), want[n]) << n;
  for (NodeId n = static_cast<NodeId>(r.num_nodes()); n < static_cast<NodeId>(r.num_nodes()) + 10; ++n) {
    EXPECT_EQ(g.state(n), InteractionGraph::NodeState::kOutside) << n;
  }
  EXPECT_EQ(g.state(kNoNode), InteractionGraph::NodeState::kOutside);
  ASSERT_EQ(g.num_vertices(), corners.size());
  for (int i = 0; i < static_cast<int>(g.num_vertices()); ++i) EXPECT_EQ(g.index_of(g.vertex(i)), i) << i;
  for (VertexId v = 0; v < static_cast<VertexId>(r.num_vertices()) + 10; ++v) {
    EXPECT_EQ(g.index_of(v) >= 0, corners.count(v) == 1) << v;
  }
  EXPECT_EQ(g.index_of(kNoVertex), -1);
}

TEST(InteractionGraphTables, LookupsFollowTheCutOverARandomSplitSequence) {
  SurfaceHierarchy receiver = test::grid_hierarchy(9);
  const auto start = std::make_shared<const InteractionGraph::Start>(receiver);
  // Two graphs on one receiver split it in turn, each where it likes, so
  // each holds nodes and vertices the other made and skips others.
  InteractionGraph a(0, 0, start), b(1, 0, start);
  std::mt19937 random(11);
  std::vector<InteractionGraph::NewVertex> created;
  for (int step = 0; step < 300; ++step) {
    InteractionGraph& g = step % 3 == 0 ? b : a;
    const std::vector<NodeId> leaves = g.leaves(receiver);
    const NodeId n = leaves[std::uniform_int_distribution<std::size_t>(0, leaves.size() - 1)(random)];
    if (receiver.level(n) >= 4) continue;
    const std::size_t before = g.num_vertices();
    created.clear();
    ASSERT_TRUE(g.split(n, receiver, created));
    // Each new vertex is new to the graph, at the next index, and seeded by
    // a vertex the graph held.
    for (std::size_t k = 0; k < created.size(); ++k) {
      EXPECT_EQ(created[k].index, static_cast<int>(before + k));
      EXPECT_LT(created[k].seed, static_cast<int>(before));
    }
    if (step % 50 == 49) {
      g.pack_links();
      expect_lookups_match_the_cut(a, receiver);
      expect_lookups_match_the_cut(b, receiver);
    }
  }
  // Both cuts went deep, and apart.
  EXPECT_GT(a.num_leaves(), 2 * receiver.num_roots());
  EXPECT_GT(b.num_leaves(), receiver.num_roots());
  EXPECT_NE(a.num_vertices(), b.num_vertices());
  EXPECT_FALSE(a.split(kNoNode, receiver, created));
  expect_lookups_match_the_cut(a, receiver);
  expect_lookups_match_the_cut(b, receiver);
}

TEST(InteractionGraphTables, TheFirstSplitKeepsTheRootsOrderAndPackingLeavesNoSpareRoom) {
  SurfaceHierarchy receiver = test::grid_hierarchy(5);  // 25 vertices, 32 roots
  InteractionGraph g(0, 0, receiver);
  g.set_every_vertex_link({kWholeSurface, {}});
  const std::size_t unsplit = g.bytes();
  EXPECT_LE(unsplit, unsplit_bound(25));
  // After splitting root 5 the leaves are the roots in their order with
  // root 5's four children, in order, in its place.
  std::vector<InteractionGraph::NewVertex> created;
  ASSERT_TRUE(g.split(receiver.root(5), receiver, created));
  std::vector<NodeId> want;
  for (std::size_t f = 0; f < receiver.num_roots(); ++f) {
    if (f != 5) want.push_back(receiver.root(static_cast<int>(f)));
    for (int c = 0; c < 4 && f == 5; ++c) want.push_back(receiver.child(receiver.root(5), c));
  }
  EXPECT_EQ(g.leaves(receiver), want);
  EXPECT_EQ(g.num_leaves(), want.size());
  for (const auto& nv : created) g.set_links(nv.index, std::vector<GraphLink>{{kWholeSurface, {}}});
  g.pack_links();
  // Packed: no list of leaves, per node two bits (R's nodes up to the last
  // child), per new vertex its id (16 bits in a receiver of fewer than
  // 65 536 vertices) and index entry (R's vertices from the start's on), per
  // vertex the links' offset; once, the headers of those three tables and a
  // leaf count, held only by a graph that splits.
  const std::size_t vertices = g.num_vertices();
  const std::size_t extra = vertices - 25;
  const std::size_t split_header =
      sizeof(std::vector<std::uint8_t>) + 2 * sizeof(CompactUints) + 2 * sizeof(std::uint64_t);
  const std::size_t bound = unsplit_bound(vertices) + split_header + (receiver.num_nodes() + 3) / 4 +
                            extra * sizeof(std::uint16_t) +
                            (receiver.num_vertices() - 25) * sizeof(std::uint16_t);
  EXPECT_LE(g.bytes(), bound);
  EXPECT_GT(g.bytes(), unsplit);
}

// A graph past 65 535 links (the light's graph on a Cornell floor at the
// default settings has more) takes 32-bit offsets, and every vertex keeps
// its own links through the widening.
TEST(InteractionGraphTables, AGraphPastSixteenBitsOfLinksKeepsEveryVertexsLinks) {
  SurfaceHierarchy receiver = test::grid_hierarchy(9);  // 81 vertices
  InteractionGraph g(0, 0, receiver);
  g.set_every_vertex_link({kWholeSurface, {}});
  const std::size_t narrow = g.bytes();
  const auto shooter_of = [](int vertex, int k) { return static_cast<NodeId>(vertex * 100000 + k); };
  const std::vector<int> counts{70000, 1, 3, 0, 1000};
  for (int i = 0; i < static_cast<int>(counts.size()); ++i) {
    for (int k = 0; k < counts[i]; ++k) g.add_link(10 * i, {shooter_of(i, k), {}});
  }
  g.pack_links();
  EXPECT_EQ(g.num_links(), 81u + 70000u + 1u + 3u + 1000u);
  for (int v = 0; v < static_cast<int>(g.num_vertices()); ++v) {
    const int i = v % 10 == 0 && v / 10 < static_cast<int>(counts.size()) ? v / 10 : -1;
    const auto links = g.links(v);
    ASSERT_EQ(links.size(), 1u + (i >= 0 ? static_cast<std::size_t>(counts[i]) : 0u)) << v;
    EXPECT_EQ(links[0].shooter, kWholeSurface);
    for (std::size_t k = 1; k < links.size(); ++k) ASSERT_EQ(links[k].shooter, shooter_of(i, static_cast<int>(k) - 1));
  }
  // The offsets went from 2 to 4 bytes a vertex.
  EXPECT_EQ(g.bytes() - narrow, (g.num_vertices() + 1) * sizeof(std::uint16_t));
}

// The solver's unoccluded form factor cache (radiosity/unoccluded_cache.hpp)
// holds one value per receiver vertex that is not a graph vertex, in vertex
// order. While two graphs split the receiver in turn, each value must stay
// with its vertex, be dropped when the graph takes that vertex, and a vertex
// new to the receiver must start uncomputed (NaN).
TEST(InteractionGraphTables, TheUnoccludedCacheKeepsEachValueWithItsVertex) {
  SurfaceHierarchy receiver = test::grid_hierarchy(9);
  const auto start = std::make_shared<const InteractionGraph::Start>(receiver);
  InteractionGraph a(0, 0, start), b(1, 0, start);
  UnoccludedCache cache;  // a's
  // Distinct for every vertex, and as the cache keeps them.
  const auto value_of = [](VertexId v) { return static_cast<float>(UnitFloat16(1.0 / (1.0 + v))); };
  std::mt19937 random(5);
  std::vector<InteractionGraph::NewVertex> created;
  std::size_t computed_before = 0;  // the receiver's vertices when the values were last set
  for (int round = 0; round < 40; ++round) {
    cache.update(a, receiver.num_vertices());
    std::vector<UnitFloat16>& values = cache.values();
    std::size_t k = 0;
    for (VertexId v = 0; v < static_cast<VertexId>(receiver.num_vertices()); ++v) {
      if (a.index_of(v) >= 0) continue;
      ASSERT_LT(k, values.size());
      if (static_cast<std::size_t>(v) < computed_before) {
        EXPECT_EQ(static_cast<float>(values[k]), value_of(v)) << "round " << round << ", vertex " << v;
      } else {
        EXPECT_TRUE(values[k].is_nan()) << "round " << round << ", vertex " << v;
      }
      values[k++] = UnitFloat16(value_of(v));  // what push() computes for the missing ones
    }
    EXPECT_EQ(k, values.size());
    EXPECT_EQ(cache.bytes(), sizeof(cache) + values.size() * sizeof(std::uint16_t));
    computed_before = receiver.num_vertices();
    // b makes receiver vertices a does not hold; a takes some of them.
    for (int step = 0; step < 6; ++step) {
      InteractionGraph& g = step % 2 == 0 ? b : a;
      const std::vector<NodeId> leaves = g.leaves(receiver);
      const NodeId n = leaves[std::uniform_int_distribution<std::size_t>(0, leaves.size() - 1)(random)];
      if (receiver.level(n) >= 4) continue;
      created.clear();
      ASSERT_TRUE(g.split(n, receiver, created));
    }
  }
  EXPECT_GT(b.num_vertices(), start->vertices.size());
  EXPECT_LT(a.num_vertices(), receiver.num_vertices());
}

}  // namespace
}  // namespace lhr
