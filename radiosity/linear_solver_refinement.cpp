#include "radiosity/linear_solver.hpp"

// LinearSolver's refinement: the shooter oracle (paper §4.2) with the error
// of the shooter's own values, the receiver oracle (paper §4.1) with its
// object-space tests, and the seeding of the vertices a split makes.

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <tuple>

#include "radiosity/form_factor.hpp"
#include "radiosity/interruptible.hpp"
#include "radiosity/receiver_oracle.hpp"

namespace lhr {

namespace {

// eps_vertex and the facet-edge test compare with at least this fraction of
// the adaptation luminance, so that nodes in the dark do not refine without
// bound (the relative norm floors its errors at 1 % of the mean alike).
constexpr double kRelativeErrorFloor = 0.01;
// The receiver oracle's power test (LinearOptions::eps_power) against the
// power the receiver surface reflects instead of the emitted power: a few
// edges along a part's concave junctions must not add up to the 3 % a
// surface's mean may be off by (docs/accuracy.md, "A surface's own power").
constexpr double kSurfacePowerTolerance = 3e-3;
// A graph leaf whose receiver node another graph has split already is split
// here too when, along one of its edges, what this graph's shooter sends per
// unit of unoccluded form factor changes by more than this fraction of the
// larger end (refine_receivers; docs/accuracy.md, "Interpolated visibility").
constexpr double kDoubtfulInterpolation = 0.25;
// Shooter-oracle passes per iteration: each pass opens links one level deeper.
constexpr int kMaxShooterPasses = 24;
// A vertex's links to all the children of one shooter element are merged
// into one link to it when the shooter oracle would keep that link with
// this margin below each of its thresholds, so that the next iteration's
// small drift does not open it again (docs/design.md, "Coarsening links").
constexpr double kCoarsenMargin = 0.5;

std::uint64_t element_key(int graph, NodeId element) {
  return (static_cast<std::uint64_t>(graph) << 32) | static_cast<std::uint32_t>(element);
}

// A link's coefficients as the shooter oracle reads them: scaled to its
// judged fraction (GraphLink::judged_fraction).
TransportCoefficients judged_coefficients(const GraphLink& link) {
  assert(link.judged_fraction >= 0.0f);
  TransportCoefficients out = link.coefficients;
  // Without an exact form factor there is nothing to scale: its own draw.
  if (!(out.unoccluded > 0.0f)) return out;
  const double drawn = out.visible(), judged = static_cast<double>(link.judged_fraction) * out.unoccluded;
  if (drawn > 0.0) {
    for (float& f : out.f) f = static_cast<float>(f * (judged / drawn));
  } else if (is_cluster_element(link.shooter)) {
    out.f = {static_cast<float>(judged), 0.0f, 0.0f};
  } else {
    out.f.fill(static_cast<float>(judged / 3.0));
  }
  return out;
}

}  // namespace

double LinearSolver::representation_error(int s, const GraphLink& link, const Rgb& rho) const {
  // docs/design.md §4, shooter oracle: the paper's test weighs what a link carries,
  // not how wrong its shooter's values may be for this receiver; the link's
  // transfer is off by at most its form factor times the element's spread
  // (a whole floor's mean for a block face that sees only the floor's dark
  // front; a coarse triangle's corners across a shadow inside it).
  const SurfaceState& st = surfaces_[s];
  const bool cluster = is_cluster_element(link.shooter);
  const std::vector<Rgb>& spreads = cluster ? st.clusters.spread : st.shooter.spread;
  const std::size_t index = cluster ? static_cast<std::size_t>(cluster_index(link.shooter))
                                    : static_cast<std::size_t>(link.shooter);
  if (index >= spreads.size()) return 0.0;
  Rgb error = static_cast<double>(judged_coefficients(link).visible()) * spreads[index];
  for (int c = 0; c < 3; ++c) error[c] *= rho[c];
  return luminance(error);
}

std::unordered_map<std::uint64_t, double> LinearSolver::shared_representation_error(
    const std::vector<PendingLink>& links) const {
  // An element's representation error is not a receiver's own: every node
  // linked to it in a graph inherits it (receiver splits seed new nodes with
  // their neighbours' links), so a whole floor's mean shown on a whole wall
  // is one error over all the wall's pixels, though each node alone covers
  // too few to matter. Its image cost is the sum over those nodes.
  std::unordered_map<std::uint64_t, double> shared;
  for (const PendingLink& p : links) {
    const InteractionGraph& g = graphs_[p.graph];
    const GraphLink& link = g.links(p.vertex)[p.slot];
    double& sum = shared[element_key(p.graph, link.shooter)];
    if (static_cast<std::size_t>(p.graph) >= graph_importance_.size() ||
        static_cast<std::size_t>(p.vertex) >= graph_importance_[p.graph].size()) {
      continue;
    }
    const Rgb& rho = model_.material(g.receiver_surface()).reflectance;
    sum += representation_error(g.shooter_surface(), link, rho) * graph_importance_[p.graph][p.vertex];
  }
  return shared;
}

void LinearSolver::seed_vertices(int gi, const std::vector<InteractionGraph::NewVertex>& created,
                                 std::vector<PendingLink>& pending) {
  InteractionGraph& g = graphs_[gi];
  for (const auto& nv : created) {
    // A new node sees the shooter through the same elements as the end point
    // of its edge (one cut of S's hierarchy); the shooter oracle refines it
    // from there. Its coefficients are new; its neighbours' are kept (paper
    // §3: 9 new coefficients per receiver split, not 36).
    std::vector<GraphLink> links;
    // Judged by the seed's draw of the same element, not by its own.
    for (const GraphLink& l : g.links(nv.seed)) links.push_back({l.shooter, {}, l.drawn_fraction()});
    // A seed that saw none of S kept no first link (link_new_shooters).
    if (links.empty()) links.push_back({kWholeSurface, {}, kJudgedByPilot});
    for (std::size_t t = 0; t < links.size(); ++t) pending.push_back({gi, nv.index, t});
    links_now_ += links.size();
    g.set_links(nv.index, links);
  }
  if (!created.empty()) shooter_watch_[gi].drift = std::numeric_limits<float>::infinity();
}

NodeId LinearSolver::parent_element(int s, NodeId e) const {
  const SurfaceClusters& clusters = surfaces_[s].clusters;
  if (is_cluster_element(e)) {
    const std::int32_t parent = clusters.tree[cluster_index(e)].parent;
    return parent >= 0 ? cluster_element(parent) : kNoNode;
  }
  const NodeId parent = model_.hierarchy(s).parent(e);
  if (parent != kNoNode) return parent;
  const std::int32_t leaf = static_cast<std::size_t>(e) < clusters.leaf_of_root.size() ? clusters.leaf_of_root[e] : -1;
  return leaf >= 0 ? cluster_element(leaf) : kNoNode;
}

namespace {

// A merged link is judged as its children were: by the draw they were split
// from, the unoccluded-weighted mean where they came from different ones.
float merged_judged_fraction(std::span<const GraphLink> links, std::span<const std::size_t> slots) {
  double weighted = 0.0, weight = 0.0;
  for (std::size_t t : slots) {
    const GraphLink& child = links[t];
    weighted += child.judged_fraction * child.coefficients.unoccluded;
    weight += child.coefficients.unoccluded;
  }
  return weight > 0.0 ? static_cast<float>(weighted / weight) : 1.0f;
}

}  // namespace

std::optional<GraphLink> LinearSolver::merged_link(int s, NodeId parent, std::span<const GraphLink> links,
                                                   std::span<const std::size_t> slots) const {
  GraphLink out{parent, {}};
  double unoccluded = 0.0;
  if (!is_cluster_element(parent)) {
    if (slots.size() != 4) return std::nullopt;
    const SurfaceHierarchy& h = model_.hierarchy(s);
    std::array<TransportCoefficients, 4> children;
    for (std::size_t t : slots) children[h.child_index(links[t].shooter)] = links[t].coefficients;
    out.coefficients = merge_child_coefficients(children);
    out.judged_fraction = merged_judged_fraction(links, slots);
    return out;
  }
  // A constant-basis parent (a cluster) carries its children's transfer:
  // each child's form factor weighed by what it shoots over what the parent
  // shoots, as the shape factor weighs a cluster's triangles (transport.hpp).
  // The plain sum of their form factors, the parent's mean shown to every
  // receiver, lost 0.8 % of the lamp's power in a bright closed room
  // (EnergyBalance.ABrightClosedRoomSeenInPartAbsorbsWhatItsLampEmits): a
  // receiver sees the bright part near it with the larger form factor.
  const SurfaceState& st = surfaces_[s];
  const RootCluster& cluster = st.clusters.tree[cluster_index(parent)];
  const std::size_t expected = cluster.first_child >= 0 ? 2 : cluster.roots.size();
  if (slots.size() != expected) return std::nullopt;
  // Child clusters' factors stand on the shaped luminances ("A shape factor
  // that ages"), and so does the parent's; roots shoot their corners now,
  // within kShapeDrift of those.
  const std::size_t top = cluster_index(parent);
  const bool shaped = cluster.first_child >= 0;
  const double carried = shaped ? st.shaped_cluster_luminance[top] : luminance(st.clusters.radiance[top]);
  double visible = 0.0, transfer = 0.0;
  for (std::size_t t : slots) {
    const GraphLink& child = links[t];
    for (int l = 0; l < 3; ++l) {
      visible += child.coefficients.f[l];
      const double value = shaped ? (l == 0 ? st.shaped_cluster_luminance[cluster_index(child.shooter)] : 0.0)
                                  : luminance(shooter_value(s, child.shooter, l));
      transfer += child.coefficients.f[l] * value;
    }
    unoccluded += child.coefficients.unoccluded;
  }
  out.coefficients.f[0] = static_cast<float>(carried > 0.0 ? transfer / carried : visible);
  out.coefficients.unoccluded = static_cast<float>(unoccluded);
  out.judged_fraction = merged_judged_fraction(links, slots);
  return out;
}

LinearSolver::Coarsening LinearSolver::coarsen_links(int gi) {
  // docs/design.md, "Coarsening links": a vertex's cut of S was opened for
  // what it carried and for its own importance when it was opened (or its
  // neighbour's, which it was seeded from). Where the oracle would now keep
  // the coarser link, the children merge back into it.
  Coarsening out;
  if (!options_.coarsen_links || static_cast<std::size_t>(gi) >= graph_importance_.size()) return out;
  InteractionGraph& g = graphs_[gi];
  const int s = g.shooter_surface();
  const int vertices = static_cast<int>(std::min(g.num_vertices(), graph_importance_[gi].size()));
  struct Merge {
    int vertex;
    std::array<std::size_t, 4> slots;
    std::size_t count;
    GraphLink link;
    double shared;  // its representation error times the vertex's importance
  };
  std::vector<Merge> merges;
  std::vector<std::pair<NodeId, std::size_t>> by_parent;
  for (int i = 0; i < vertices; ++i) {
    const std::span<const GraphLink> links = g.links(i);
    if (links.size() < 2) continue;
    by_parent.clear();
    for (std::size_t t = 0; t < links.size(); ++t) {
      const NodeId parent = parent_element(s, links[t].shooter);
      if (parent != kNoNode) by_parent.emplace_back(parent, t);
    }
    std::sort(by_parent.begin(), by_parent.end());
    for (std::size_t a = 0; a < by_parent.size();) {
      std::size_t b = a;
      while (b < by_parent.size() && by_parent[b].first == by_parent[a].first) ++b;
      const std::size_t count = b - a;
      if (count <= 4) {
        Merge m{i, {}, count, {}, 0.0};
        for (std::size_t k = 0; k < count; ++k) m.slots[k] = by_parent[a + k].second;
        if (const auto link = merged_link(s, by_parent[a].first, links, {m.slots.data(), count})) {
          m.link = *link;
          const LinkJudgement j = judge_link(gi, i, m.link);
          const bool keeps = j.seen <= kCoarsenMargin * options_.eps_link &&
                             (!(options_.eps_vertex > 0) || j.own_error <= kCoarsenMargin * j.own_allowed);
          if (keeps) {
            m.shared = j.own_error * graph_importance_[gi][i];
            merges.push_back(m);
          }
        }
      }
      a = b;
    }
  }
  if (merges.empty()) return out;
  // The error an element's values carry is one over every node linked to
  // it (shared_representation_error): with the links it has already, the
  // merges onto one element must keep that sum under the margin too. They
  // are taken smallest first (then by vertex, so the outcome does not
  // depend on the order of anything else) while it does.
  std::unordered_map<NodeId, double> shared;
  for (const Merge& m : merges) shared.emplace(m.link.shooter, 0.0);
  const Rgb& rho = model_.material(g.receiver_surface()).reflectance;
  for (int i = 0; i < vertices; ++i) {
    for (const GraphLink& link : g.links(i)) {
      if (const auto it = shared.find(link.shooter); it != shared.end()) {
        it->second += representation_error(s, link, rho) * graph_importance_[gi][i];
      }
    }
  }
  std::vector<std::size_t> order(merges.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::tie(merges[a].shared, merges[a].vertex, merges[a].link.shooter) <
           std::tie(merges[b].shared, merges[b].vertex, merges[b].link.shooter);
  });
  const double limit = kCoarsenMargin * options_.eps_link * adaptation_;
  std::vector<std::uint8_t> accepted(merges.size(), 0);
  for (std::size_t k : order) {
    double& sum = shared.at(merges[k].link.shooter);
    if (sum + merges[k].shared > limit) continue;
    sum += merges[k].shared;
    accepted[k] = 1;
  }
  std::vector<GraphLink> kept;
  std::vector<std::uint8_t> gone;
  for (std::size_t a = 0; a < merges.size();) {
    const int i = merges[a].vertex;
    std::size_t b = a;
    while (b < merges.size() && merges[b].vertex == i) ++b;
    const std::span<const GraphLink> links = g.links(i);
    gone.assign(links.size(), 0);
    std::vector<GraphLink> parents;
    for (std::size_t k = a; k < b; ++k) {
      const Merge& m = merges[k];
      if (!accepted[k]) continue;
      for (std::size_t c = 0; c < m.count; ++c) gone[m.slots[c]] = 1;
      parents.push_back(m.link);
      out.links_removed += m.count - 1;
      ++out.merges;
    }
    if (!parents.empty()) {
      kept.clear();
      for (std::size_t t = 0; t < links.size(); ++t) {
        if (!gone[t]) kept.push_back(links[t]);
      }
      kept.insert(kept.end(), parents.begin(), parents.end());
      g.replace_links(i, kept);
    }
    a = b;
  }
  if (out.merges > 0) g.pack_links();
  return out;
}

std::vector<std::uint8_t> LinearSolver::coarsen_due_graphs() {
  std::vector<std::uint8_t> due(graphs_.size(), 0);
  for (std::size_t gi = 0; gi < graphs_.size(); ++gi) {
    const InteractionGraph& g = graphs_[gi];
    const auto nodes = static_cast<std::uint32_t>(model_.hierarchy(g.shooter_surface()).num_nodes());
    due[gi] = shooter_watch_[gi].due(graph_drift(g), nodes, options_.oracle_drift) ? 1 : 0;
    stats_.shooter_judgements += due[gi];
  }
  // The judged graphs' vertex importance, for this refinement only.
  graph_importance_.assign(graphs_.size(), {});
  interruptible_parallel_for(graphs_.size(), options_.checkpoint, [&](std::size_t gi) {
    if (due[gi]) vertex_importance(static_cast<int>(gi), graph_importance_[gi]);
  });
  // Coarsening reads only what the last push and importance pass left and
  // writes only its own graph: the graphs are coarsened in parallel.
  std::vector<Coarsening> coarsened(graphs_.size());
  interruptible_parallel_for(graphs_.size(), options_.checkpoint, [&](std::size_t gi) {
    if (due[gi]) coarsened[gi] = coarsen_links(static_cast<int>(gi));
  });
  // A merge keeps what the links carry but for the representation error the
  // margin bounds; what that moves R's radiance by is R's drift at the next
  // push, which the receiver oracle's watch reads.
  for (const Coarsening& c : coarsened) {
    links_now_ -= c.links_removed;
    stats_.shooter_coarsenings += c.merges;
  }
  return due;
}

bool LinearSolver::refine_shooters(const std::vector<std::uint8_t>& due) {
  // Paper §4.2: a link whose largest basis contribution, reflected and seen by
  // the camera, is significant is replaced by links from the shooter's
  // children, recursively (a pass per level), each pass over every graph in
  // turn. A verdict reads only its own graph's links, so each graph's
  // splits are drawn and packed before the next graph's, and what the next
  // pass judges is kept graph by graph in 8 bytes a link: a list over all
  // graphs, as large as the links it named and uncounted, stood at the top
  // of what --max-memory bounds (docs/robustness.md, "Budgets").
  //
  // A graph's links are judged again only when what their verdicts read has
  // moved (docs/design.md, "One iteration"), as for the receiver oracle: new
  // links (a receiver split seeds them; its new nodes also move R's
  // importance, so this is said twice on purpose), S's hierarchy (its elements' spread
  // and children), or, by oracle_drift in all since they were last judged,
  // R's and S's radiance, R's importance and the tone map's adaptation. A
  // link the last judging kept would be kept again; its children made then
  // were judged in that iteration's later passes.
  if (options_.checkpoint) options_.checkpoint();
  bool changed = false;
  struct LinkAt {
    std::int32_t vertex;
    std::uint32_t slot;
  };
  std::vector<std::vector<LinkAt>> to_judge(graphs_.size());
  std::vector<PendingLink> candidates, created;
  for (int pass = 0; pass < kMaxShooterPasses; ++pass) {
    if (pass > 0 && options_.checkpoint) options_.checkpoint();
    bool split = false;
    for (std::size_t gi = 0; gi < graphs_.size(); ++gi) {
      const int graph = static_cast<int>(gi);
      candidates.clear();
      if (pass == 0) {
        if (!due[gi]) continue;
        const InteractionGraph& g = graphs_[gi];
        for (int i = 0; i < static_cast<int>(g.num_vertices()); ++i) {
          for (std::size_t t = 0; t < g.links(i).size(); ++t) candidates.push_back({graph, i, t});
        }
      } else {
        if (to_judge[gi].empty()) continue;
        for (const LinkAt& l : to_judge[gi]) candidates.push_back({graph, l.vertex, l.slot});
        std::vector<LinkAt>().swap(to_judge[gi]);
      }
      created.clear();
      changed |= split_shooters(candidates, created);
      compute_coefficients(created);
      // Packed graph by graph: a list that grows is copied out until then.
      graphs_[gi].pack_links();
      to_judge[gi].reserve(created.size());
      for (const PendingLink& p : created) to_judge[gi].push_back({p.vertex, static_cast<std::uint32_t>(p.slot)});
      split |= !created.empty();
    }
    if (!split) break;
  }
  return changed;
}

LinearSolver::LinkJudgement LinearSolver::judge_link(int gi, int i, const GraphLink& link) const {
  const InteractionGraph& g = graphs_[gi];
  const int s = g.shooter_surface();
  const Rgb& rho = model_.material(g.receiver_surface()).reflectance;
  const TransportCoefficients judged = judged_coefficients(link);
  double largest = 0.0;
  for (int l = 0; l < 3; ++l) {
    Rgb transfer = static_cast<double>(judged.f[l]) * shooter_value(s, link.shooter, l);
    for (int c = 0; c < 3; ++c) transfer[c] *= rho[c];
    largest = std::max(largest, luminance(transfer));
  }
  LinkJudgement out;
  out.seen = largest / adaptation_ * graph_importance_[gi][i];
  // A node made in this refinement pass has no value yet: the floor
  // stands for it until the next push.
  const std::vector<Rgb>& values = surfaces_[g.receiver_surface()].radiance;
  const VertexId v = g.vertex(i);
  const double own = static_cast<std::size_t>(v) < values.size() ? luminance(values[v]) : 0.0;
  out.own_error = representation_error(s, link, rho);
  out.own_allowed = options_.eps_vertex * std::max(own, kRelativeErrorFloor * adaptation_);
  return out;
}

bool LinearSolver::split_shooters(const std::vector<PendingLink>& candidates, std::vector<PendingLink>& created) {
  const std::vector<std::vector<BFloat16>>& importance = graph_importance_;
  const auto shared = shared_representation_error(candidates);
  // Each link is judged on what the last push left, which the splits below
  // do not change, so the judging runs in parallel and the splits in order:
  // the same links as judging and splitting one link after another.
  enum Verdict : std::uint8_t { kKeep, kSeen, kOwnError };
  std::vector<std::uint8_t> verdict(candidates.size(), kKeep);
  interruptible_parallel_for(candidates.size(), options_.checkpoint, [&](std::size_t k) {
    const PendingLink& p = candidates[k];
    const InteractionGraph& g = graphs_[p.graph];
    if (static_cast<std::size_t>(p.graph) >= importance.size() ||
        static_cast<std::size_t>(p.vertex) >= importance[p.graph].size()) {
      return;
    }
    const GraphLink& link = g.links(p.vertex)[p.slot];
    if (!splittable(g.shooter_surface(), link.shooter, g.receiver_surface())) return;
    const LinkJudgement j = judge_link(p.graph, p.vertex, link);
    // Or the element's own representation is off, over every node sharing it.
    const double shared_error = shared.at(element_key(p.graph, link.shooter));
    if (j.seen > options_.eps_link || shared_error / adaptation_ > options_.eps_link) {
      verdict[k] = kSeen;
    } else if (options_.eps_vertex > 0 && j.own_error > j.own_allowed) {
      verdict[k] = kOwnError;
    }
  });
  bool changed = false;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    if (verdict[k] == kKeep) continue;
    const PendingLink& p = candidates[k];
    if (budget_.refuses(links_now_, 3, stats_)) continue;
    InteractionGraph& g = graphs_[p.graph];
    const GraphLink& parent = g.links(p.vertex)[p.slot];
    const std::vector<NodeId> kids = children(g.shooter_surface(), parent.shooter);
    // The children are judged by the parent's draw, which their own draws
    // do not depend on (docs/accuracy.md, "Judged by another draw").
    const float fraction = parent.drawn_fraction();
    g.links(p.vertex)[p.slot] = {kids[0], {}, fraction};
    created.push_back(p);
    for (std::size_t c = 1; c < kids.size(); ++c) {
      created.push_back({p.graph, p.vertex, g.links(p.vertex).size()});
      g.add_link(p.vertex, {kids[c], {}, fraction});
    }
    links_now_ += kids.size() - 1;
    oracle_watch_[p.graph].drift = std::numeric_limits<float>::infinity();
    ++stats_.shooter_refinements;
    if (verdict[k] == kOwnError) ++stats_.vertex_error_refinements;
    changed = true;
  }
  return changed;
}

// The tests refine_receivers() makes on the leaves and edges of one graph.
class LinearSolver::ReceiverTests {
 public:
  ReceiverTests(LinearSolver& solver, int graph, const ToneMap& tone)
      : solver_(solver),
        model_(solver.model_),
        graph_(graph),
        g_(solver.graphs_[graph]),
        r_(g_.receiver_surface()),
        s_(g_.shooter_surface()),
        h_(model_.hierarchy(r_)),
        st_(solver.surfaces_[r_]),
        rho_(model_.material(r_).reflectance),
        oracle_(tone, solver.options_.vis_threshold) {
    prepare_small_shooter();
    prepare_facet_spread();
    prepare_receiver_power();
    // S's contribution at every graph vertex, gathered once for all the
    // tests from the links as they stand (the shooter oracle has refined
    // some since the push) and the shooter's values of the last pull.
    gathered_.resize(g_.num_vertices());
    tbb::parallel_for(0, static_cast<int>(gathered_.size()), [&](int i) { gathered_[i] = solver_.gathered(g_, i); });
  }

  // S's reflected contribution at graph vertex i.
  double own(int i) const {
    Rgb c = gathered_[i];
    for (int k = 0; k < 3; ++k) c[k] *= rho_[k];
    return luminance(c);
  }

  // The fraction of S that graph vertex i sees.
  double visibility(int i) const {
    double visible = 0.0, unoccluded = 0.0;
    for (const GraphLink& l : g_.links(i)) {
      visible += l.coefficients.visible();
      unoccluded += l.coefficients.unoccluded;
    }
    return unoccluded > 0 ? visible / unoccluded : 0.0;
  }

  // A shooter smaller than a receiver leaf can light a spot inside it that
  // none of its vertices sees (a small light close to R, between
  // vertices): S's contribution is then zero at all of them, and so is
  // every difference the edge tests look at. What S sends into the leaf,
  // taken as from a point source at S's centre, must then agree with the
  // interpolant's power to eps_power of the emitted power. (A curved S
  // has no one normal to shoot along: left to the edge tests.)
  bool misses_small_shooter(NodeId leaf) const {
    const double area = model_.area(r_, leaf);
    if (!model_.scene().surfaces[s_].planar || !(area > shooter_area_) || !(shooter_power_ > 0)) return false;
    const Vec3& shooter_normal = model_.scene().surfaces[s_].normal;
    const double sent =
        shooter_power_ * point_triangle_form_factor(shooter_centre_, shooter_normal, model_.triangle(r_, leaf));
    double interpolated = 0.0;
    for (VertexId v : h_.corners(leaf)) interpolated += area / 3.0 * own(g_.index_of(v));
    return M_PI * std::abs(sent - interpolated) >= solver_.options_.eps_power * solver_.total_emitted_power_;
  }

  // A vertex another graph has made is a vertex of the exported mesh, and
  // this graph's share there is interpolated: the contribution over the
  // exact unoccluded form factor, taken as linear between the edge's ends
  // (push). Next to an occluder it is not: along an 8 cm table apron below
  // the top's overhang, or across a window pane beside its reveals, the
  // part of the room in view grows fast, then levels off, and the
  // interpolant fell 5-12 % short of it. Where the ends of an edge
  // disagree that much and the leaf matters to the image, the split costs
  // no new receiver nodes and makes those vertices exact here as well.
  bool interpolation_doubtful(NodeId leaf) const {
    if (h_.is_leaf(leaf) || !(solver_.node_importance(r_, leaf) > 0.0)) return false;
    const auto& c = h_.corners(leaf);
    for (int k = 0; k < 3; ++k) {
      const double a = sent_per_form_factor(c[k]), b = sent_per_form_factor(c[(k + 1) % 3]);
      if (std::abs(a - b) > kDoubtfulInterpolation * std::max(a, b)) return true;
    }
    return false;
  }

  // docs/accuracy.md, "Facet edges": on a curved R the faces through a
  // node on a facet edge see S differently (the light can be above one
  // facet's plane and below the next one's), so the radiance S gives
  // jumps there, while the node holds the mean of the one-sided limits.
  // Every leaf touching the node then carries a ramp off by up to half the
  // jump, and it is linear, so no second difference sees it. No split
  // makes that error smaller at the node, only the ramp narrower, so it is
  // weighed by the leaf's pixels, and in the terms the image is judged in:
  // the half jump relative to the node's radiance (floored, as the
  // relative norm is, at a hundredth of the adaptation luminance). On the
  // display, a few per cent on a dim facet fell under ε_pixel.
  bool facet_jump_shows(NodeId leaf) {
    const double pixels = solver_.node_importance(r_, leaf);
    const double eps_pixel = solver_.options_.eps_pixel;
    if (facet_spread_ == nullptr || pixels < eps_pixel) return false;
    for (VertexId v : h_.corners(leaf)) {
      const int i = g_.index_of(v);
      if (i < 0) continue;
      const double b = own(i);
      if (!(b > 0.0)) continue;
      float& spread = (*facet_spread_)[v];
      if (std::isnan(spread)) spread = static_cast<float>(solver_.facet_spread(r_, v, s_));
      const double half_jump = 0.5 * b * spread;
      const double total = luminance(st_.radiance[v]);
      const double error = std::min(1.0, half_jump / std::max(total, kRelativeErrorFloor * solver_.adaptation_));
      if (ReceiverOracle::refines(error, pixels, eps_pixel)) return true;
    }
    return false;
  }

  // What every graph together misplaces across the edge, against what R
  // reflects: beside a concave junction each shooter bends the same way,
  // and no one graph's part reaches kSurfacePowerTolerance while the sum
  // does (docs/accuracy.md, "The sum of the graphs"). The sum's second
  // difference is the reflected radiance's at the edge's four vertices. This
  // graph splits when it bends at least as much as the sum does, relative
  // to what each carries there; at least one graph does.
  bool bends_with_the_sum(const std::array<double, 4>& w, const std::array<int, 4>& idx, double second_difference,
                          double area) const {
    double total_second = 0.0, total = 0.0, own_sum = 0.0;
    for (int i = 0; i < 4; ++i) {
      const double reflected = luminance(st_.radiance[g_.vertex(idx[i])]) - emitted_;
      total_second += w[i] * reflected;
      total += reflected;
      own_sum += own(idx[i]);
    }
    const double total_misplaced = 0.5 * std::abs(total_second) * area;
    if (M_PI * total_misplaced < kSurfacePowerTolerance * receiver_power_ || !(own_sum > 0.0) || !(total > 0.0)) {
      return false;
    }
    const double same_sign = total_second > 0.0 ? second_difference : -second_difference;
    return same_sign * total >= std::abs(total_second) * own_sum;
  }

  // Whether the edge between e's two triangles asks for both to be split.
  bool edge_refines(NodeId leaf, const OracleEdge& e) const {
    const NodeId across = e.right;
    std::array<int, 4> idx{};
    for (int i = 0; i < 4; ++i) idx[i] = g_.index_of(e.vertex[i]);
    const std::array<double, 4> w =
        edge_weights(h_.point(e.vertex[0]), h_.point(e.vertex[1]), h_.point(e.vertex[2]), h_.point(e.vertex[3]));
    // S's reflected power that linear interpolation misplaces across the
    // edge: half the second difference of its contribution, over both
    // triangles. It must be small against the emitted power whatever the
    // camera sees or the tone map shows (docs/design.md §5: the exported mesh is
    // the product). A small light close to R puts a peak narrower than
    // an element on one vertex, and the interpolant spreads that
    // vertex's value over its hat function: up to 2000 times the light's
    // power on a sub-pixel spot that the image-space test never splits
    // (docs/design.md §5, small lights; tests/test_small_lights.cpp).
    // Beside a concave edge the interpolant cuts under a radiance that
    // bends down steeply into the corner: a loss on every element
    // there, too small for either test alone to see on a surface the
    // camera does not, until the tolerance is low enough to bound the
    // sum (docs/accuracy.md, "Concave junctions").
    double second_difference = 0.0;
    for (int i = 0; i < 4; ++i) second_difference += w[i] * own(idx[i]);
    const double area = model_.area(r_, leaf) + model_.area(r_, across);
    const double misplaced = 0.5 * std::abs(second_difference) * area;
    // And small against what R itself reflects: on a small part beside
    // a concave junction (an apron where a leg stands 1 cm proud of it) no
    // edge misplaces enough of the scene's power, but the loss is a few
    // per cent of the part's own (docs/accuracy.md, "A surface's own power").
    const bool by_power = M_PI * misplaced >= solver_.options_.eps_power * solver_.total_emitted_power_ ||
                          M_PI * misplaced >= kSurfacePowerTolerance * receiver_power_ ||
                          bends_with_the_sum(w, idx, second_difference, area);
    // ΔE is a display difference, at most 1: too few pixels cannot reach ε_pixel.
    const double pixels = solver_.node_importance(r_, leaf) + solver_.node_importance(r_, across);
    const double eps_pixel = solver_.options_.eps_pixel;
    if (!by_power && pixels < eps_pixel) return false;
    EdgeValues edge;
    edge.weights = w;
    for (int i = 0; i < 4; ++i) {
      edge.own[i] = own(idx[i]);
      edge.total[i] = luminance(st_.radiance[g_.vertex(idx[i])]);
    }
    edge.visibility_1 = visibility(idx[0]);
    edge.visibility_2 = visibility(idx[1]);
    return by_power || oracle_.edge_refines(edge, pixels, eps_pixel);
  }

 private:
  void prepare_small_shooter() {
    shooter_area_ = model_.surface_area(s_);
    Rgb reflected_exitance = solver_.surfaces_[s_].clusters.radiance[0];
    for (int k = 0; k < 3; ++k) reflected_exitance[k] *= rho_[k];
    shooter_power_ = shooter_area_ * luminance(reflected_exitance);
    shooter_centre_ = solver_.surfaces_[s_].centre;
  }

  // What R reflects, π A L̄ in luminance, with its mean radiance floored as
  // the relative norm floors its errors, so that a surface in the dark is
  // not refined without bound.
  void prepare_receiver_power() {
    Rgb reflected = st_.clusters.radiance[0];
    const Rgb& emission = model_.material(r_).emission;
    for (int k = 0; k < 3; ++k) reflected[k] = std::max(0.0, reflected[k] - emission[k]);
    emitted_ = luminance(emission);
    receiver_power_ = M_PI * model_.surface_area(r_) *
                      std::max(luminance(reflected), kRelativeErrorFloor * solver_.adaptation_);
  }

  void prepare_facet_spread() {
    if (model_.scene().surfaces[r_].planar) return;
    // Sized by refine_receivers before the graphs are judged in parallel.
    std::vector<std::vector<float>>& cache = solver_.facet_spread_at_;
    assert(cache.size() >= solver_.graphs_.size());
    facet_spread_ = &cache[graph_];
    if (facet_spread_->size() < st_.radiance.size()) {
      facet_spread_->resize(st_.radiance.size(), std::numeric_limits<float>::quiet_NaN());
    }
  }

  double sent_per_form_factor(VertexId v) const {
    const int i = g_.index_of(v);
    if (i < 0) return 0.0;
    const double ff = g_.unoccluded(i);
    return ff > 0.0 ? luminance(gathered_[i]) / ff : 0.0;
  }

  LinearSolver& solver_;
  const MeshedScene& model_;
  int graph_;
  const InteractionGraph& g_;
  int r_, s_;
  const SurfaceHierarchy& h_;
  const SurfaceState& st_;
  const Rgb& rho_;
  const ReceiverOracle oracle_;
  double shooter_area_ = 0.0;
  double shooter_power_ = 0.0;
  double receiver_power_ = 0.0;
  double emitted_ = 0.0;  // R's own emitted luminance
  Vec3 shooter_centre_{0, 0, 0};
  std::vector<float>* facet_spread_ = nullptr;  // curved receivers only
  std::vector<Rgb> gathered_;  // per graph vertex
};

std::vector<NodeId> LinearSolver::receiver_leaves_to_split(int graph, const ToneMap& tone) {
  ReceiverTests tests(*this, graph, tone);
  const InteractionGraph& g = graphs_[graph];
  const int r = g.receiver_surface(), s = g.shooter_surface();
  const SurfaceHierarchy& h = model_.hierarchy(r);
  std::vector<NodeId> to_split;
  std::vector<OracleEdge> edges;
  for (NodeId leaf : g.leaves(h)) {
    if (tests.misses_small_shooter(leaf) && splittable(r, leaf, s)) to_split.push_back(leaf);
    if ((tests.interpolation_doubtful(leaf) || tests.facet_jump_shows(leaf)) && splittable(r, leaf, s)) {
      to_split.push_back(leaf);
      continue;
    }
    edges.clear();
    oracle_edges(g, h, leaf, edges);
    for (const OracleEdge& e : edges) {
      if (!tests.edge_refines(leaf, e) || !splittable(r, leaf, s) || !splittable(r, e.right, s)) continue;
      to_split.push_back(leaf);
      to_split.push_back(e.right);
    }
  }
  return to_split;
}

bool LinearSolver::split_receiver_leaves(int graph, const std::vector<NodeId>& to_split,
                                         std::vector<PendingLink>& pending) {
  InteractionGraph& g = graphs_[graph];
  const int r = g.receiver_surface();
  SurfaceHierarchy& h = model_.hierarchy(r);
  bool changed = false;
  std::vector<InteractionGraph::NewVertex> created;
  for (NodeId n : to_split) {
    // A split seeds its new vertices (at most 3 unless the restriction
    // splits neighbours too) with the links of a corner.
    std::size_t seeded = 0;
    for (VertexId v : h.corners(n)) {
      if (const int i = g.index_of(v); i >= 0) seeded = std::max(seeded, g.links(i).size());
    }
    if (budget_.refuses(links_now_, 3 * seeded, stats_)) break;
    const std::size_t before = created.size();
    if (g.split(n, h, created)) {
      ++stats_.receiver_splits;
      changed = true;
      sync_vertices(r);
      seed_vertices(graph, {created.begin() + static_cast<std::ptrdiff_t>(before), created.end()}, pending);
    }
  }
  return changed;
}

bool LinearSolver::refine_receivers(std::vector<PendingLink>& pending, const ToneMap& tone) {
  // Paper §4.1, in two phases (docs/design.md, "One iteration"): every graph
  // is judged first, in parallel, while nothing is split; then the splits
  // are made graph by graph, in order. Judged one graph after
  // another, the oracle was half of a room's solve on one core.
  // A graph is judged again only when what its verdict reads has moved
  // (docs/design.md, "One iteration"): its links (the shooter oracle marks
  // the graphs it refines), R's hierarchy, or, by oracle_drift in all since
  // it was last judged, R's and S's radiance and R's importance relative to
  // themselves and the tone map's adaptation. Unjudged, it would say what
  // it said then: nothing to split, or it would have split since.
  if (facet_spread_at_.size() < graphs_.size()) facet_spread_at_.resize(graphs_.size());
  std::vector<std::uint8_t> judge(graphs_.size(), 0);
  for (std::size_t gi = 0; gi < graphs_.size(); ++gi) {
    const InteractionGraph& g = graphs_[gi];
    const auto nodes = static_cast<std::uint32_t>(model_.hierarchy(g.receiver_surface()).num_nodes());
    if (oracle_watch_[gi].due(graph_drift(g), nodes, options_.oracle_drift)) {
      judge[gi] = 1;
      ++stats_.receiver_judgements;
    }
  }
  std::vector<std::vector<NodeId>> to_split(graphs_.size());
  interruptible_parallel_for(graphs_.size(), options_.checkpoint, [&](std::size_t gi) {
    if (judge[gi]) to_split[gi] = receiver_leaves_to_split(static_cast<int>(gi), tone);
  });
  bool changed = false;
  for (std::size_t gi = 0; gi < graphs_.size(); ++gi) {
    changed |= split_receiver_leaves(static_cast<int>(gi), to_split[gi], pending);
    graphs_[gi].pack_links();
  }
  return changed;
}

}  // namespace lhr
