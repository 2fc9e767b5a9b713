#include "radiosity/linear_solver.hpp"

// The solver's frame: state per surface, linking, gather, push and the
// iteration. Its transport, importance and refinement live beside it
// (linear_solver_transport.cpp, linear_solver_importance.cpp,
// linear_solver_refinement.cpp).

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "radiosity/shooter_spread.hpp"

namespace lhr {

namespace {

// First links computed and trimmed at a time (link_new_shooters): enough
// for every core, few beside a scene's data.
constexpr std::size_t kFirstLinkBatch = std::size_t{1} << 20;

}  // namespace

int LinearSolver::initial_ancestors(const std::vector<std::array<VertexId, 2>>& parents, VertexId v,
                                    std::array<VertexId, 3>& ancestors) {
  int found = 0;
  std::vector<VertexId> stack{v};
  while (!stack.empty()) {
    const VertexId u = stack.back();
    stack.pop_back();
    if (parents[u][0] != kNoVertex) {
      stack.push_back(parents[u][0]);
      stack.push_back(parents[u][1]);
    } else if (std::find(ancestors.begin(), ancestors.begin() + found, u) == ancestors.begin() + found) {
      if (found == 3) throw std::logic_error("a node descends from more than one initial face");
      ancestors[found++] = u;
    }
  }
  return found;
}

LinearSolver::LinearSolver(MeshedScene& model, LinearOptions options)
    : model_(model),
      options_(std::move(options)),
      floor_(model, options_.min_edge),
      budget_(options_.max_links, options_.max_bytes) {
  if (!options_.tone_map) {
    options_.tone_map = [](double adaptation, double) {
      ToneMapSettings tone;
      tone.world_adaptation = adaptation;
      return std::make_unique<TumblinRushmeierToneMap>(tone);
    };
  }
  surfaces_.resize(model_.num_surfaces());
  for (int s = 0; s < model_.num_surfaces(); ++s) {
    const Material& m = model_.material(s);
    max_emitted_ = std::max(max_emitted_, luminance(m.emission));
    total_emitted_power_ += M_PI * model_.surface_area(s) * luminance(m.emission);
    SurfaceState& st = surfaces_[s];
    st.clusters = SurfaceClusters(model_, s);
    st.root_edges = root_corner_edges(model_.hierarchy(s));
    std::vector<std::array<Vec3, 3>> corners(model_.hierarchy(s).num_roots());
    for (std::size_t root = 0; root < corners.size(); ++root) corners[root] = model_.triangle(s, static_cast<NodeId>(root));
    st.root_triangles = ShooterTriangleTable(corners);
    if (model_.surface_area(s) > 0) {
      for (std::size_t f = 0; f < corners.size(); ++f) {
        st.centre += model_.area(s, static_cast<NodeId>(f)) * model_.centroid(s, static_cast<NodeId>(f));
      }
      st.centre /= model_.surface_area(s);
    }
    // A curved surface's outlines serve where every root is seen plainly:
    // its whole-surface form factor (unoccluded_form_factor) and its cluster
    // links' (transport_to).
    st.outlines = cluster_outlines(model_.hierarchy(s), st.clusters.tree, st.root_edges);
    // An emitter's first links see it uniform, as it starts.
    st.shaped_root_luminance.assign(corners.size(), luminance(m.emission));
    st.shaped_cluster_luminance.resize(st.clusters.radiance.size());
    for (std::size_t c = 0; c < st.clusters.radiance.size(); ++c) {
      st.shaped_cluster_luminance[c] = luminance(st.clusters.radiance[c]);
    }
    sync_vertices(s);
  }
}

void LinearSolver::sync_vertices(int s) {
  SurfaceState& st = surfaces_[s];
  const SurfaceHierarchy& h = model_.hierarchy(s);
  const std::size_t old_vertices = st.radiance.size();
  const std::size_t nv = h.num_vertices();
  st.parents.resize(nv, {kNoVertex, kNoVertex});
  st.approach.resize(nv, Vec3(0, 0, 0));
  st.hidden.resize(nv, 0);
  st.radiance.resize(nv, model_.material(s).emission);
  // A node at a surface's boundary or crease has no value of its own on a
  // shooter's plane: it takes the limit from inside the first element that
  // made it (docs/design.md §4, corners). Roots first, then each split's centre child,
  // whose corners are the split's edge midpoints.
  // A node on a contact line (the foot of a box on a floor; mesh/contact_lines.hpp)
  // lies between an open element and a hidden one: it takes the limit from
  // the open side, the one a viewer sees (docs/accuracy.md, "Contact lines").
  const Surface& surface = model_.scene().surfaces[s];
  const RayCaster& rays = model_.rays();
  const auto enclosed = [&](VertexId v, const Vec3& d) {
    const Vec3 origin = rays.lift(h.point(v) + 8.0 * rays.epsilon() * d, surface.normal);
    return model_.enclosed_fraction(origin, surface.normal);
  };
  // Contact lines are edges of the initial mesh, so only a node on an
  // initial vertex or edge inside the surface (not on its outline, where
  // the other side is off the surface) can lie on one.
  const TriMesh& roots = h.mesh();
  const auto may_straddle = [&](VertexId v) {
    std::array<VertexId, 3> ancestors{kNoVertex, kNoVertex, kNoVertex};
    const int found = initial_ancestors(st.parents, v, ancestors);
    if (found == 1) return !roots.is_boundary(OpenMesh::VertexHandle(ancestors[0]));
    if (found == 2) {
      const auto he = roots.find_halfedge(OpenMesh::VertexHandle(ancestors[0]), OpenMesh::VertexHandle(ancestors[1]));
      return he.is_valid() && !roots.is_boundary(roots.edge_handle(he));
    }
    return false;
  };
  const auto set_approach = [&](VertexId v, NodeId from) {
    if (st.approach[v].sqrnorm() > 0) return;
    Vec3 d = model_.centroid(s, from) - h.point(v);
    d = d.norm() > 0 ? d / d.norm() : Vec3(0, 0, 0);
    if (surface.planar && d.sqrnorm() > 0) {
      // The same rule as the vertex reference (render/vertex_reference.cpp):
      // the other side when it is clearly more open.
      constexpr double kClearlyMoreOpen = 0.125;
      const double here = enclosed(v, d);
      if (here > 0.0) {
        // An initial vertex inside the surface may be where contact lines
        // meet (an apron's and a leg's footprints on a table top): the open
        // side can lie off the line through it, so every root around it is
        // a candidate, as every face is for the vertex reference.
        double best = here, lowest = here;
        if (may_straddle(v)) {
          std::vector<Vec3> sides{-d};
          std::array<VertexId, 3> ancestors{kNoVertex, kNoVertex, kNoVertex};
          if (initial_ancestors(st.parents, v, ancestors) == 1) {
            for (const auto f : roots.vf_range(OpenMesh::VertexHandle(ancestors[0]))) {
              const Vec3 e = model_.centroid(s, static_cast<NodeId>(f.idx())) - h.point(v);
              if (e.norm() > 0 && (e / e.norm() - d).norm() > 1e-9) sides.push_back(e / e.norm());
            }
          }
          for (const Vec3& e : sides) {
            const double there = enclosed(v, e);
            lowest = std::min(lowest, there);
            if (there < best - kClearlyMoreOpen) {
              best = there;
              d = e;
            }
          }
        } else {
          lowest = 1.0;
        }
        st.hidden[v] = std::min(here, lowest) >= 0.5;
      }
    }
    st.approach[v] = d;
  };
  for (NodeId n = static_cast<NodeId>(st.synced_nodes); n < static_cast<NodeId>(h.num_nodes()); ++n) {
    const NodeId parent = h.parent(n);
    if (parent == kNoNode) {
      for (VertexId v : h.corners(n)) set_approach(v, n);
    } else if (h.child_index(n) == 3) {
      const auto& p = h.corners(parent);
      const auto& c = h.corners(n);
      for (int k = 0; k < 3; ++k) {
        if (st.parents[c[k]][0] == kNoVertex) st.parents[c[k]] = {p[(k + 1) % 3], p[(k + 2) % 3]};
        set_approach(c[k], n);
      }
    }
  }
  st.synced_nodes = h.num_nodes();
  // A new vertex starts at the linear interpolant of its edge until the next
  // push gives it its own value.
  for (std::size_t v = old_vertices; v < nv; ++v) {
    const auto& [a, b] = st.parents[v];
    if (a != kNoVertex) st.radiance[v] = 0.5 * (st.radiance[a] + st.radiance[b]);
  }
}

bool LinearSolver::splittable(int s, NodeId e, int partner) const {
  if (is_cluster_element(e)) return true;
  return model_.hierarchy(s).level(e) < SurfaceHierarchy::kMaxLevel && floor_.allows_split(model_.area(s, e), s, partner);
}

std::vector<NodeId> LinearSolver::children(int s, NodeId e) {
  std::vector<NodeId> out;
  if (is_cluster_element(e)) {
    const RootCluster& c = surfaces_[s].clusters.tree[cluster_index(e)];
    if (c.first_child >= 0) {
      out = {cluster_element(c.first_child), cluster_element(c.first_child + 1)};
    } else {
      out = c.roots;
    }
    return out;
  }
  SurfaceHierarchy& h = model_.hierarchy(s);
  if (h.is_leaf(e)) {
    h.split(e);
    sync_vertices(s);
  }
  for (int c = 0; c < 4; ++c) out.push_back(h.child(e, c));
  return out;
}

Rgb LinearSolver::shooter_value(int s, NodeId e, int l) const {
  const SurfaceState& st = surfaces_[s];
  if (is_cluster_element(e)) return l == 0 ? st.clusters.radiance[cluster_index(e)] : Rgb(0, 0, 0);
  // A node made since the last pull is a leaf: its corner values are its own.
  if (static_cast<std::size_t>(e) < st.shooter.corners.size()) return st.shooter.corners[e][l];
  return st.radiance[model_.hierarchy(s).corners(e)[l]];
}

void LinearSolver::pull(int s) {
  // docs/accuracy.md, "What a coarse triangle shoots": every element shoots
  // with the projection of the leaves' radiance below it, which carries
  // their integral; a cluster with the mean of its roots' integrals, each
  // weighted by how open the root is (a floor shoots with what its lit part
  // gives, not the part under a block).
  SurfaceState& st = surfaces_[s];
  const SurfaceHierarchy& h = model_.hierarchy(s);
  std::vector<double> node_area(h.num_nodes());
  for (std::size_t n = 0; n < node_area.size(); ++n) node_area[n] = model_.area(s, static_cast<NodeId>(n));
  project_linear_nodes(h, st.radiance, node_area, st.shooter);
  for (std::size_t c = 0; c < st.clusters.tree.size(); ++c) {
    const RootCluster& cluster = st.clusters.tree[c];
    const bool open = cluster.exposed_area > 0;
    Rgb weighted(0, 0, 0);
    for (NodeId root : cluster.roots) weighted += (open ? st.clusters.root_exposure[root] : 1.0) * st.shooter.root_integral[root];
    st.clusters.radiance[c] = weighted / std::max(open ? cluster.exposed_area : cluster.area, 1e-300);
  }
  // docs/accuracy.md, "A shape factor that ages": only the radiance's shape
  // enters a shape factor, so each cluster is taken relative to the whole.
  const double was_whole = st.shaped_cluster_luminance[0], now_whole = luminance(st.clusters.radiance[0]);
  if (!options_.rescale_cluster_links) {
    take_shaped_luminance(s);
    return;
  }
  if (!(now_whole > 0.0)) return;
  if (!(was_whole > 0.0)) {
    // Its first light: nothing links from a surface without it.
    take_shaped_luminance(s);
    return;
  }
  for (std::size_t c = 0; c < st.clusters.tree.size() && !st.reshape_due; ++c) {
    const double was = st.shaped_cluster_luminance[c], now = luminance(st.clusters.radiance[c]);
    const double moved = was > 0.0 ? std::abs((now * was_whole) / (now_whole * was) - 1.0) : (now > 0.0 ? 1.0 : 0.0);
    st.reshape_due = moved > kShapeDrift;
  }
}

void LinearSolver::take_shaped_luminance(int s) {
  SurfaceState& st = surfaces_[s];
  st.shaped_root_luminance.resize(st.shooter.root_integral.size());
  for (std::size_t root = 0; root < st.shaped_root_luminance.size(); ++root) {
    const double area = model_.area(s, static_cast<NodeId>(root));
    st.shaped_root_luminance[root] = area > 0 ? luminance(st.shooter.root_integral[root]) / area : 0.0;
  }
  st.shaped_cluster_luminance.resize(st.clusters.radiance.size());
  for (std::size_t c = 0; c < st.clusters.radiance.size(); ++c) {
    st.shaped_cluster_luminance[c] = luminance(st.clusters.radiance[c]);
  }
  st.reshape_due = false;
}

void LinearSolver::update_spread() {
  PhaseTimer timer(stats_.seconds_push_pull);
  tbb::parallel_for(0, model_.num_surfaces(), [&](int s) {
    SurfaceState& st = surfaces_[s];
    SurfaceClusters& clusters = st.clusters;
    clusters.spread = cluster_spread(clusters.tree, clusters.radiance, clusters.root_exposure, st.shooter.spread,
                                     [&](NodeId root) { return st.shooter.corners[root]; });
  });
}

bool LinearSolver::first_links_possible(int s, int r, double eps) const {
  // A planar surface does not light itself; a curved one does (the inside
  // of a sphere lights the rest of it). A black receiver reflects nothing.
  const Scene& scene = model_.scene();
  if ((r == s && scene.surfaces[s].planar) || !(max_channel(model_.material(r).reflectance) > 0)) return false;
  return may_exchange_light(scene.surfaces[s], scene.surfaces[r], eps);
}

const InteractionGraph::Start& LinearSolver::start_of(int r) {
  if (starts_.size() < surfaces_.size()) starts_.resize(surfaces_.size());
  if (!starts_[r]) starts_[r] = std::make_shared<const InteractionGraph::Start>(model_.hierarchy(r));
  return *starts_[r];
}

std::size_t LinearSolver::first_link_bytes(int s, double eps) {
  // An upper bound on what link_new_shooters keeps: a first link on every
  // initial vertex of every receiver, but for the vertices behind a planar
  // shooter's plane, which see none of it and keep none. Each link is its
  // own 24 bytes and its vertex's offset; each graph, its object and the
  // per-graph caches and watches beside it.
  constexpr std::size_t kPerLink = sizeof(GraphLink) + sizeof(std::uint32_t);
  constexpr std::size_t kPerGraph = sizeof(InteractionGraph) + sizeof(UnoccludedCache) + 2 * sizeof(OracleWatch) +
                                    2 * sizeof(std::vector<float>) + sizeof(int);
  const Surface& shooter = model_.scene().surfaces[s];
  std::size_t bytes = 0;
  for (int r = 0; r < model_.num_surfaces(); ++r) {
    if (!first_links_possible(s, r, eps)) continue;
    const InteractionGraph::Start& start = start_of(r);
    std::size_t links = start.vertices.size();
    if (shooter.planar) {
      const SurfaceHierarchy& h = model_.hierarchy(r);
      const Vec3& origin = shooter.points.front();
      links = static_cast<std::size_t>(std::count_if(start.vertices.begin(), start.vertices.end(), [&](VertexId v) {
        return OpenMesh::dot(shooter.normal, h.point(v) - origin) > eps;
      }));
    }
    if (links > 0) bytes += kPerGraph + links * kPerLink;
  }
  return bytes;
}

double LinearSolver::leave_out_past_the_budget(const std::vector<std::pair<double, int>>& waiting,
                                               std::vector<bool>& starts) {
  // A shooter's first links used to be made whatever the budget, so that
  // none of its light was dropped; among a thousand boxes that was 522 MiB
  // of them at --max-memory 100M. Now the brightest reflecting shooters
  // start while their first links fit in what the budget has left; the
  // others wait, and their power is reported. A surface that emits starts
  // whatever the budget: its light is the scene's, which no budget may
  // leave out.
  const double eps = 1e-9 * model_.rays().diagonal();
  collect_stats();
  std::size_t room = budget_.room_bytes(stats_.bytes_total());
  double left = 0.0;
  stats_.surfaces_left_out_for_memory = 0;
  for (auto it = waiting.rbegin(); it != waiting.rend(); ++it) {
    const auto [power, s] = *it;
    if (!starts[s]) continue;
    // With no room left, nothing more is worked out: among thousands of
    // surfaces each bound reads every receiver's initial vertices.
    const bool weighed = room > 0 && !surfaces_[s].left_out_for_memory;
    const std::size_t bytes = weighed ? first_link_bytes(s, eps) : 0;
    if ((weighed && bytes <= room) || luminance(model_.material(s).emission) > 0) {
      room -= std::min(room, bytes);
      continue;
    }
    starts[s] = false;
    surfaces_[s].left_out_for_memory = true;
    left += power;
    ++stats_.surfaces_left_out_for_memory;
    stats_.memory_budget_reached = true;
  }
  return left;
}

std::size_t LinearSolver::waiting_first_link_bytes(std::size_t enough) {
  // The surfaces that have power and do not shoot yet start at the next
  // iteration (link_new_shooters): their first links bring light to what
  // does not have it yet, which counts for more than any refinement of the
  // links already made, so refinement leaves room for them (dimmest ones
  // too: the link_power tail is a bound, not a list, and is left in).
  const double eps = 1e-9 * model_.rays().diagonal();
  std::size_t total = 0;
  for (int s = 0; s < model_.num_surfaces() && total < enough; ++s) {
    const SurfaceState& st = surfaces_[s];
    if (st.shooting || st.left_out_for_memory || !(luminance(st.clusters.radiance[0]) > 0)) continue;
    total += first_link_bytes(s, eps);
  }
  return total;
}

bool LinearSolver::link_new_shooters() {
  PhaseTimer timer(stats_.seconds_linking);
  const double eps = 1e-9 * model_.rays().diagonal();
  // Surfaces not yet shooting, dimmest first: those whose powers sum to less
  // than link_power of the emitted power stay out for now. A threshold on
  // each surface alone would drop the light of every small surface of a
  // furnished room (hundreds of chair legs and shelf sides, each below it).
  std::vector<std::pair<double, int>> waiting;
  for (int s = 0; s < model_.num_surfaces(); ++s) {
    const double power = M_PI * model_.surface_area(s) * luminance(surfaces_[s].clusters.radiance[0]);
    if (!surfaces_[s].shooting && power > 0) waiting.emplace_back(power, s);
  }
  std::sort(waiting.begin(), waiting.end());
  const double left_out = options_.link_power * total_emitted_power_;
  double dropped = 0.0;
  std::vector<bool> starts(model_.num_surfaces(), false);
  double kept_out = 0.0;
  for (const auto& [power, s] : waiting) {
    dropped += power;
    if (dropped >= left_out) {
      starts[s] = true;
    } else {
      kept_out = dropped;
    }
  }
  // docs/robustness.md, "First links within the memory budget".
  const double over_budget = budget_.counts_bytes() ? leave_out_past_the_budget(waiting, starts) : 0.0;
  stats_.power_left_out =
      total_emitted_power_ > 0 ? (kept_out + over_budget) / total_emitted_power_ : 0.0;
  stats_.power_left_out_for_memory = total_emitted_power_ > 0 ? over_budget / total_emitted_power_ : 0.0;
  timer.stop();
  // Only pairs that exchange energy keep a graph (paper §5): surfaces facing
  // each other across a wall, say, see nothing of each other.
  const auto exchanges = [](const InteractionGraph& g) {
    for (int i = 0; i < static_cast<int>(g.num_vertices()); ++i) {
      for (const GraphLink& l : g.links(i)) {
        if (l.coefficients.visible() > 0) return true;
      }
    }
    return false;
  };
  // The shooters are linked in batches of about kFirstLinkBatch first
  // links, each batch's graphs judged and trimmed before the next is made:
  // made at once, a thousand boxes' first links with the graphs that
  // exchange nothing were a passing gigabyte over the data they left.
  // Each link's coefficients depend on it alone, so the result is the same.
  std::vector<PendingLink> pending;
  bool linked = false;
  const auto finish_batch = [&](std::size_t first) {
    compute_coefficients(pending);
    linked |= !pending.empty();
    pending.clear();
    // The per-graph form factor cache moves with its graph. Graphs linked in
    // earlier iterations keep their index: the per-graph importance refers to
    // them by it until the next importance pass.
    unoccluded_at_.resize(graphs_.size());
    facet_spread_at_.resize(graphs_.size());
    std::size_t kept = first;
    for (std::size_t g = first; g < graphs_.size(); ++g) {
      if (!exchanges(graphs_[g])) continue;
      if (kept != g) {
        graphs_[kept] = std::move(graphs_[g]);
        unoccluded_at_[kept] = std::move(unoccluded_at_[g]);
        facet_spread_at_[kept] = std::move(facet_spread_at_[g]);
      }
      ++kept;
    }
    graphs_.erase(graphs_.begin() + static_cast<std::ptrdiff_t>(kept), graphs_.end());
    unoccluded_at_.resize(kept);
    facet_spread_at_.resize(kept);
    // A first link whose vertex sees none of S at all, not even unoccluded
    // (the vertex lies behind S's plane, or S below its horizon), carries
    // nothing and never will: the oracles judge it zero and push() reads an
    // unoccluded form factor of zero from it, as from no link. Among many
    // objects most first links are such (a thousand boxes: 8.7 M of 21.2 M),
    // so they are not kept. A split seeds such a vertex's new neighbours
    // with the whole surface again (seed_vertices).
    tbb::parallel_for(first, graphs_.size(), [&](std::size_t g) {
      graphs_[g].drop_links(
          [](const GraphLink& l) { return !(l.coefficients.unoccluded > 0.0f) && !(l.coefficients.visible() > 0.0f); });
    });
  };
  // A batch's transient lists and the links it drops are about 50 bytes a
  // link: a small budget takes smaller batches, so that they stay a few
  // per cent of it.
  const std::size_t batch = budget_.counts_bytes()
                                ? std::clamp<std::size_t>(budget_.max_bytes() / 1024, 4096, kFirstLinkBatch)
                                : kFirstLinkBatch;
  std::size_t batch_first = graphs_.size();
  for (int s = 0; s < model_.num_surfaces(); ++s) {
    SurfaceState& st = surfaces_[s];
    if (!starts[s]) continue;
    st.shooting = true;
    {
      PhaseTimer making(stats_.seconds_linking);
      for (int r = 0; r < model_.num_surfaces(); ++r) {
        if (!first_links_possible(s, r, eps)) continue;
        const int g = static_cast<int>(graphs_.size());
        start_of(r);
        graphs_.emplace_back(s, r, starts_[r]);
        InteractionGraph& graph = graphs_.back();
        graph.set_every_vertex_link({kWholeSurface, {}, kJudgedByPilot});
        for (int i = 0; i < static_cast<int>(graph.num_vertices()); ++i) pending.push_back({g, i, 0});
      }
    }
    if (pending.size() >= batch) {
      finish_batch(batch_first);
      batch_first = graphs_.size();
    }
  }
  finish_batch(batch_first);
  for (SurfaceState& st : surfaces_) st.graphs_in.clear();
  for (std::size_t g = 0; g < graphs_.size(); ++g) {
    surfaces_[graphs_[g].receiver_surface()].graphs_in.push_back(static_cast<int>(g));
  }
  links_now_ = count_links();
  return linked;
}

Rgb LinearSolver::gathered(const InteractionGraph& g, int i) const {
  const int s = g.shooter_surface();
  Rgb sum(0, 0, 0);
  for (const GraphLink& link : g.links(i)) {
    for (int l = 0; l < 3; ++l) {
      const float f = link.coefficients.f[l];
      if (f != 0.0f) sum += static_cast<double>(f) * shooter_value(s, link.shooter, l);
    }
  }
  // In float, the precision of the coefficients it sums, as when it was
  // stored (BENCHMARKS.md, "Tables sized by the graph's own cut").
  for (int c = 0; c < 3; ++c) sum[c] = static_cast<float>(sum[c]);
  return sum;
}

double LinearSolver::push() {
  PhaseTimer timer(stats_.seconds_push_pull);
  std::vector<double> drift(model_.num_surfaces(), 0.0);
  // Relative changes are taken against at least 1 % of the adaptation
  // luminance, as the relative norm is (docs/accuracy.md). The largest is
  // the stopping test's (docs/accuracy.md, "When the iteration stops").
  const double drift_floor = 0.01 * adaptation_;
  constexpr double kNoBound = std::numeric_limits<double>::infinity();
  unoccluded_at_.resize(graphs_.size());
  // Every graph gathers here, from the shooters' values of the last pull (a
  // Jacobi step), so no surface is pulled until every one has been pushed.
  std::vector<std::vector<Rgb>> pushed(model_.num_surfaces());
  tbb::parallel_for(0, model_.num_surfaces(), [&](int r) {
    const SurfaceState& st = surfaces_[r];
    const Material& m = model_.material(r);
    const std::size_t nv = st.radiance.size();
    std::vector<Rgb> total(nv, Rgb(0, 0, 0));
    std::vector<Rgb> contribution(nv);
    std::vector<std::uint8_t> exact(nv);
    // Paper §3, figs. 3–4: each shooter's contribution is pushed on its own,
    // by linear interpolation down R's hierarchy (vertex ids grow with depth,
    // so an edge's end points come first), except at the vertices its graph
    // computed exactly, T-vertices included.
    //
    // What is interpolated is the contribution divided by the exact
    // unoccluded form factor from all of S (docs/accuracy.md, "Energy that never
    // arrives"): the visible fraction times the radiance seen.
    // The form factor itself is far from linear near a contact or a corner
    // (it goes from 1/2 to 0 within a few element sizes), and the shooters
    // that a corner refines (the adjacent wall) and those it leaves coarse
    // (everything else) would not sum to 1 between the nodes; the ratio is
    // smooth there, and the form factor is known exactly at every vertex.
    std::vector<Rgb> ratio(nv);
    std::vector<std::uint8_t> has_ratio(nv);
    // Per missing form factor: its place in the graph's cache and its vertex.
    std::vector<std::pair<std::size_t, VertexId>> missing;
    for (int gi : st.graphs_in) {
      const InteractionGraph& g = graphs_[gi];
      UnoccludedCache& cache = unoccluded_at_[gi];
      cache.update(g, nv);
      std::vector<UnitFloat16>& unoccluded = cache.values();  // at the vertices not in g, in order
      std::fill(exact.begin(), exact.end(), 0);
      tbb::parallel_for(0, static_cast<int>(g.num_vertices()), [&](int i) {
        const VertexId v = g.vertex(i);
        contribution[v] = gathered(g, i);
        exact[v] = 1;
        const double ff = g.unoccluded(i);
        has_ratio[v] = ff > 0.0;
        ratio[v] = ff > 0.0 ? contribution[v] / ff : Rgb(0, 0, 0);
      });
      missing.clear();
      for (std::size_t v = 0, k = 0; v < nv; ++v) {
        if (exact[v]) continue;
        if (unoccluded[k].is_nan()) missing.emplace_back(k, static_cast<VertexId>(v));
        ++k;
      }
      tbb::parallel_for(std::size_t{0}, missing.size(), [&](std::size_t i) {
        const auto& [k, v] = missing[i];
        unoccluded[k] = UnitFloat16(unoccluded_form_factor(r, v, g.shooter_surface()));
      });
      for (std::size_t v = 0, k = 0; v < nv; ++v) {
        if (!exact[v]) {
          const double ff = unoccluded[k++];
          const auto& [a, b] = st.parents[v];
          if (a == kNoVertex || st.hidden[v]) {
            contribution[v] = Rgb(0, 0, 0);
            has_ratio[v] = 0;
          } else {
            has_ratio[v] = has_ratio[a] || has_ratio[b];
            ratio[v] = has_ratio[a] && has_ratio[b] ? 0.5 * (ratio[a] + ratio[b])
                                                    : (has_ratio[a] ? ratio[a] : ratio[b]);
            contribution[v] = has_ratio[v] ? ff * ratio[v] : 0.5 * (contribution[a] + contribution[b]);
          }
        }
        total[v] += contribution[v];
      }
    }
    std::vector<Rgb>& values = total;
    for (std::size_t v = 0; v < nv; ++v) {
      for (int c = 0; c < 3; ++c) values[v][c] = m.emission[c] + m.reflectance[c] * total[v][c];
      const double now = luminance(values[v]), moved = std::abs(now - luminance(st.radiance[v]));
      const double scale = std::max(now, drift_floor);
      const double relative = scale > 0.0 ? moved / scale : (moved > 0.0 ? kNoBound : 0.0);
      drift[r] = std::max(drift[r], relative);
    }
    pushed[r] = std::move(values);
  });
  tbb::parallel_for(0, model_.num_surfaces(), [&](int r) {
    surfaces_[r].radiance = std::move(pushed[r]);
    surfaces_[r].drift = drift[r];
    pull(r);
  });
  reshape_cluster_links();
  return *std::max_element(drift.begin(), drift.end());
}

bool LinearSolver::refine() {
  const double coefficient_seconds = stats_.seconds_coefficients;
  PhaseTimer timer(stats_.seconds_oracles);
  // Sized exactly: growth by doubling would leave spare room per graph.
  oracle_watch_.reserve(graphs_.size());
  oracle_watch_.resize(graphs_.size());
  shooter_watch_.reserve(graphs_.size());
  shooter_watch_.resize(graphs_.size());
  // The budget is planned on what coarsening leaves: a merged link frees
  // its own bytes, not the per-link share of everything that plan() assumes
  // each link brings.
  const std::vector<std::uint8_t> due = coarsen_due_graphs();
  if (budget_.counts_bytes()) collect_stats();
  budget_.plan(links_now_, stats_.bytes_total(),
               budget_.counts_bytes() ? waiting_first_link_bytes(budget_.room_bytes(stats_.bytes_total())) : 0);
  bool changed = refine_shooters(due);
  const std::unique_ptr<ToneMap> tone = options_.tone_map(adaptation_, brightest_);
  std::vector<PendingLink> pending;
  changed |= refine_receivers(pending, *tone);
  if (options_.checkpoint) options_.checkpoint();
  compute_coefficients(pending);
  if (options_.redraw_cluster_links) redraw_cluster_links();
  // The coefficients of the new links count as their own phase.
  stats_.seconds_oracles -= stats_.seconds_coefficients - coefficient_seconds;
  std::vector<std::vector<BFloat16>>().swap(graph_importance_);
  return changed;
}

void LinearSolver::solve(const std::function<void(int, double)>& progress) {
  const auto iteration = [&](int, bool last) {
    const std::size_t before = links_now_;
    const bool linked = link_new_shooters();
    // A surface that starts shooting gets its first links even past the cap:
    // without them its light would not reach anything.
    const std::size_t cap = budget_.cap();
    if (links_now_ > cap) stats_.links_linked_past_budget += links_now_ - std::max(before, cap);
    run_checkpoint(options_.checkpoint);
    const double change = push();
    update_spread();
    update_importance();
    run_checkpoint(options_.checkpoint);
    // The last allowed iteration only gathers, so the result is consistent.
    const bool refined = !last && refine();
    return IterationOutcome{linked || refined, change};
  };
  iterate_until_converged(options_.max_iterations, options_.tolerance, options_.checkpoint, iteration, progress,
                          stats_);
  collect_stats();
}

std::size_t LinearSolver::count_links() const {
  std::size_t n = 0;
  for (const InteractionGraph& g : graphs_) n += g.num_links();
  return n;
}

void LinearSolver::collect_stats() {
  stats_.links = count_links();
  stats_.graphs = graphs_.size();
  stats_.graph_vertices = 0;
  stats_.bytes_graphs = 0;
  stats_.bytes_links = 0;
  for (const InteractionGraph& g : graphs_) {
    stats_.graph_vertices += g.num_vertices();
    stats_.bytes_graphs += g.bytes();
    stats_.bytes_links += g.link_bytes();
  }
  for (const auto& start : starts_) stats_.bytes_graphs += start ? start->bytes() : 0;
  stats_.bytes_graphs += unoccluded_at_.capacity() * sizeof(UnoccludedCache);
  for (const UnoccludedCache& u : unoccluded_at_) stats_.bytes_graphs += u.bytes() - sizeof(u);
  for (const std::vector<float>& u : facet_spread_at_) stats_.bytes_graphs += u.capacity() * sizeof(float);
  // The importance per graph vertex is a table of the graphs' as much as
  // the form factor caches are; it is held while refine() runs (2 bytes a
  // vertex of every graph judged), and the budget planned then must see it.
  stats_.bytes_graphs += graph_importance_.capacity() * sizeof(graph_importance_[0]);
  for (const std::vector<BFloat16>& w : graph_importance_) stats_.bytes_graphs += w.capacity() * sizeof(BFloat16);
  stats_.bytes_graphs += importance_vertices_.capacity() * sizeof(importance_vertices_[0]);
  stats_.bytes_graphs += (oracle_watch_.capacity() + shooter_watch_.capacity()) * sizeof(OracleWatch);
  stats_.nodes = stats_.leaves = 0;
  stats_.bytes_geometry = stats_.bytes_hierarchy = stats_.bytes_values = 0;
  stats_.leaves_per_level.clear();
  for (int s = 0; s < model_.num_surfaces(); ++s) {
    const SurfaceHierarchy& h = model_.hierarchy(s);
    stats_.nodes += h.num_nodes();
    stats_.leaves += h.num_leaves();
    if (stats_.leaves_per_level.size() <= static_cast<std::size_t>(h.max_level())) {
      stats_.leaves_per_level.resize(h.max_level() + 1, 0);
    }
    for (NodeId n : h.leaves()) ++stats_.leaves_per_level[h.level(n)];
    stats_.bytes_geometry += h.geometry_bytes();
    stats_.bytes_hierarchy += h.hierarchy_bytes();
    const SurfaceState& st = surfaces_[s];
    // The shooters above the roots: clusters, the roots' edge codes and the outlines.
    stats_.bytes_hierarchy += st.root_edges.capacity() * sizeof(st.root_edges[0]) + st.outlines.bytes() +
                              st.root_triangles.bytes();
    stats_.bytes_hierarchy += st.clusters.bytes();
    stats_.bytes_values += st.radiance.capacity() * sizeof(Rgb) + st.parents.capacity() * sizeof(st.parents[0]) +
                           st.approach.capacity() * sizeof(Vec3) +
                           st.shooter.corners.capacity() * sizeof(st.shooter.corners[0]) +
                           (st.shaped_root_luminance.capacity() + st.shaped_cluster_luminance.capacity()) *
                               sizeof(double) +
                           (st.shooter.root_integral.capacity() + st.shooter.spread.capacity()) * sizeof(Rgb) +
                           (st.pixels.capacity() + st.deposit.capacity() + st.importance.capacity()) * sizeof(double);
  }
  stats_.world_adaptation = adaptation_;
}

void LinearStats::write_json(nlohmann::json& doc) const {
  SolverStats::write_json(doc, "vertex_values", bytes_total());
  doc.update({{"graphs", graphs},
              {"graph_vertices", graph_vertices},
              {"elements_per_level", leaves_per_level},
              {"receiver_splits", receiver_splits},
              {"receiver_judgements", receiver_judgements},
              {"shooter_judgements", shooter_judgements},
              {"shooter_refinements", shooter_refinements},
              {"cluster_links_rescaled", cluster_links_rescaled},
              {"vertex_error_refinements", vertex_error_refinements},
              {"shooter_coarsenings", shooter_coarsenings},
              {"links_linked_past_budget", links_linked_past_budget},
              {"power_left_out", power_left_out},
              {"power_left_out_for_memory", power_left_out_for_memory},
              {"surfaces_left_out_for_memory", surfaces_left_out_for_memory},
              {"oracle_adaptation", world_adaptation}});
  // Paper §5 reports graphs ≈ 30 % over what they organise.
  const std::size_t organised = bytes_geometry + bytes_hierarchy + bytes_values + bytes_links;
  doc["bytes"].update({{"graphs", bytes_graphs},
                       {"graph_overhead", organised > 0 ? static_cast<double>(bytes_graphs) /
                                                               static_cast<double>(organised)
                                                         : 0.0}});
  doc["seconds"].update(
      {{"linking", seconds_linking}, {"oracles", seconds_oracles}, {"importance", seconds_importance}});
}

std::vector<Rgb> LinearSolver::vertex_radiance(int s, const ConformingMesh& mesh) const {
  std::vector<Rgb> out(mesh.source.size());
  for (std::size_t v = 0; v < out.size(); ++v) out[v] = surfaces_[s].radiance[mesh.source[v]];
  return out;
}

double LinearSolver::row_sum(int receiver, VertexId v) const {
  double sum = 0.0;
  for (int gi : surfaces_[receiver].graphs_in) {
    const InteractionGraph& g = graphs_[gi];
    const int i = g.index_of(v);
    if (i < 0) continue;
    for (const GraphLink& l : g.links(i)) sum += l.coefficients.visible();
  }
  return sum;
}

}  // namespace lhr
