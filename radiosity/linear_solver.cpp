#include "radiosity/linear_solver.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <unordered_map>

#include "radiosity/form_factor.hpp"
#include "radiosity/interruptible.hpp"
#include "radiosity/receiver_oracle.hpp"
#include "radiosity/sampling.hpp"
#include "radiosity/shooter_spread.hpp"

namespace lhr {

namespace {

// eps_vertex and the facet-edge test compare with at least this fraction of
// the adaptation luminance, so that nodes in the dark do not refine without
// bound (the relative norm floors its errors at 1 % of the mean alike).
constexpr double kRelativeErrorFloor = 0.01;

// The initial vertices a node is interpolated from, following the midpoint
// parents: 1 on an initial vertex, 2 on an initial edge, 3 inside an
// initial face. Their count is returned.
int initial_ancestors(const std::vector<std::array<VertexId, 2>>& parents, VertexId v,
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


using Clock = std::chrono::steady_clock;

// Share of max_bytes the link cap plans to fill (update_link_cap).
constexpr double kMemoryBudgetUsable = 0.9;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Receiver refinement in object space: a graph edge is split when the power
// linear interpolation misplaces across it reaches this fraction of the
// emitted power (refine_receivers). Next to concave edges that error has one
// sign, a loss, and every bounce repeats it; at 10⁻⁴ a room lit only
// through a door lost 3 % of its light that way, and a bright closed room
// 1 % of its lamp's power (docs/accuracy.md, "Concave junctions").
constexpr double kPowerTolerance = 1e-5;
// A graph leaf whose receiver node another graph has split already is split
// here too when, along one of its edges, what this graph's shooter sends per
// unit of unoccluded form factor changes by more than this fraction of the
// larger end (refine_receivers; docs/accuracy.md, "Interpolated visibility").
constexpr double kDoubtfulInterpolation = 0.25;
// Shooter-oracle passes per iteration: each pass opens links one level deeper.
constexpr int kMaxShooterPasses = 24;
// Without a camera every surface is seen face-on, this many pixels in all,
// shared in proportion to area.
constexpr double kDefaultViewPixels = 512.0 * 512.0;

// Whether a planar surface has a point strictly in front of the other's plane.
bool some_point_in_front(const Surface& a, const Surface& b, double eps) {
  if (!b.planar) return true;
  const Vec3& origin = b.points.front();
  return std::any_of(a.points.begin(), a.points.end(),
                     [&](const Vec3& p) { return OpenMesh::dot(b.normal, p - origin) > eps; });
}

// Barycentric coordinates of p (in the triangle's plane) in t.
std::array<double, 3> barycentric(const Vec3& p, const std::array<Vec3, 3>& t) {
  const Vec3 e1 = t[1] - t[0], e2 = t[2] - t[0], d = p - t[0];
  const double a = OpenMesh::dot(e1, e1), b = OpenMesh::dot(e1, e2), c = OpenMesh::dot(e2, e2);
  const double p1 = OpenMesh::dot(d, e1), p2 = OpenMesh::dot(d, e2);
  const double det = a * c - b * b;
  if (!(det > 0)) return {1.0, 0.0, 0.0};
  const double u = (c * p1 - b * p2) / det, v = (a * p2 - b * p1) / det;
  return {1.0 - u - v, u, v};
}

double max_channel(const Rgb& c) { return std::max({c[0], c[1], c[2]}); }

std::uint64_t element_key(int graph, NodeId element) {
  return (static_cast<std::uint64_t>(graph) << 32) | static_cast<std::uint32_t>(element);
}

}  // namespace

LinearSolver::LinearSolver(SceneModel& model, LinearOptions options)
    : model_(model), options_(std::move(options)), floor_(model, options_.min_edge) {
  if (!options_.tone_map) {
    options_.tone_map = [](double adaptation, double) {
      TumblinRushmeierParams p;
      p.world_adaptation = adaptation;
      return std::make_unique<TumblinRushmeierToneMap>(p);
    };
  }
  surfaces_.resize(model_.num_surfaces());
  for (int s = 0; s < model_.num_surfaces(); ++s) {
    const Material& m = model_.material(s);
    max_emitted_ = std::max(max_emitted_, luminance(m.emission));
    total_emitted_power_ += M_PI * model_.surface_area(s) * luminance(m.emission);
    SurfaceState& st = surfaces_[s];
    st.root_exposure = root_exposure(model_, s);
    st.clusters = build_root_clusters(model_, s, st.root_exposure);
    st.root_edges = root_corner_edges(model_.hierarchy(s));
    if (model_.scene().surfaces[s].planar) st.outlines = cluster_outlines(model_.hierarchy(s), st.clusters, st.root_edges);
    st.cluster_radiance.assign(st.clusters.size(), m.emission);
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
  const RayScene& rays = model_.rays();
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
  return model_.hierarchy(s).level(e) < SurfaceHierarchy::kMaxLevel && floor_.allows_split(model_.area(s, e), partner);
}

std::vector<NodeId> LinearSolver::children(int s, NodeId e) {
  std::vector<NodeId> out;
  if (is_cluster_element(e)) {
    const RootCluster& c = surfaces_[s].clusters[cluster_index(e)];
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
  if (is_cluster_element(e)) return l == 0 ? st.cluster_radiance[cluster_index(e)] : Rgb(0, 0, 0);
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
  // Each root's mean luminance, for the shape factor of every cluster link made
  // before the next pull (docs/accuracy.md, "A bright part that sees more").
  st.root_luminance.resize(st.shooter.root_integral.size());
  for (std::size_t root = 0; root < st.root_luminance.size(); ++root) {
    st.root_luminance[root] = node_area[root] > 0 ? luminance(st.shooter.root_integral[root]) / node_area[root] : 0.0;
  }
  for (std::size_t c = 0; c < st.clusters.size(); ++c) {
    const RootCluster& cluster = st.clusters[c];
    const bool open = cluster.exposed_area > 0;
    Rgb weighted(0, 0, 0);
    for (NodeId root : cluster.roots) weighted += (open ? st.root_exposure[root] : 1.0) * st.shooter.root_integral[root];
    st.cluster_radiance[c] = weighted / std::max(open ? cluster.exposed_area : cluster.area, 1e-300);
  }
}

void LinearSolver::update_spread() {
  const auto start = Clock::now();
  tbb::parallel_for(0, model_.num_surfaces(), [&](int s) {
    SurfaceState& st = surfaces_[s];
    st.cluster_spread = cluster_spread(st.clusters, st.cluster_radiance, st.root_exposure, st.shooter.spread,
                                       [&](NodeId root) { return st.shooter.corners[root]; });
  });
  stats_.seconds_push_pull += seconds_since(start);
}

double LinearSolver::representation_error(int s, const GraphLink& link, const Rgb& rho) const {
  // docs/design.md §4, shooter oracle: the paper's test weighs what a link carries,
  // not how wrong its shooter's values may be for this receiver; the link's
  // transfer is off by at most its form factor times the element's spread
  // (a whole floor's mean for a block face that sees only the floor's dark
  // front; a coarse triangle's corners across a shadow inside it).
  const SurfaceState& st = surfaces_[s];
  const bool cluster = is_cluster_element(link.shooter);
  const std::vector<Rgb>& spreads = cluster ? st.cluster_spread : st.shooter.spread;
  const std::size_t index = cluster ? static_cast<std::size_t>(cluster_index(link.shooter))
                                    : static_cast<std::size_t>(link.shooter);
  if (index >= spreads.size()) return 0.0;
  Rgb error = static_cast<double>(link.coefficients.visible()) * spreads[index];
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

bool LinearSolver::link_new_shooters() {
  const auto start = Clock::now();
  const Scene& scene = model_.scene();
  const double eps = 1e-9 * model_.rays().diagonal();
  std::vector<PendingLink> pending;
  // Surfaces not yet shooting, dimmest first: those whose powers sum to less
  // than link_power of the emitted power stay out for now. A threshold on
  // each surface alone would drop the light of every small surface of a
  // furnished room (hundreds of chair legs and shelf sides, each below it).
  std::vector<std::pair<double, int>> waiting;
  for (int s = 0; s < model_.num_surfaces(); ++s) {
    const double power = M_PI * model_.surface_area(s) * luminance(surfaces_[s].cluster_radiance[0]);
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
  stats_.power_left_out = total_emitted_power_ > 0 ? kept_out / total_emitted_power_ : 0.0;
  const std::size_t first_new = graphs_.size();
  for (int s = 0; s < model_.num_surfaces(); ++s) {
    SurfaceState& st = surfaces_[s];
    if (!starts[s]) continue;
    st.shooting = true;
    for (int r = 0; r < model_.num_surfaces(); ++r) {
      // A planar surface does not light itself; a curved one does (the inside
      // of a sphere lights the rest of it). A black receiver reflects nothing.
      if ((r == s && scene.surfaces[s].planar) || !(max_channel(model_.material(r).reflectance) > 0)) continue;
      if (!some_point_in_front(scene.surfaces[s], scene.surfaces[r], eps) ||
          !some_point_in_front(scene.surfaces[r], scene.surfaces[s], eps)) {
        continue;
      }
      const int g = static_cast<int>(graphs_.size());
      graphs_.emplace_back(s, r, model_.hierarchy(r));
      InteractionGraph& graph = graphs_.back();
      for (int i = 0; i < static_cast<int>(graph.num_vertices()); ++i) {
        graph.links(i).push_back({kWholeSurface, {}});
        pending.push_back({g, i, 0});
      }
    }
  }
  stats_.seconds_linking += seconds_since(start);
  compute_coefficients(pending);
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
  // The per-graph form factor cache moves with its graph. Graphs linked in
  // earlier iterations keep their index: the per-graph importance refers to
  // them by it until the next importance pass.
  unoccluded_at_.resize(graphs_.size());
  facet_spread_at_.resize(graphs_.size());
  std::size_t kept = first_new;
  for (std::size_t g = first_new; g < graphs_.size(); ++g) {
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
  for (SurfaceState& st : surfaces_) st.graphs_in.clear();
  for (std::size_t g = 0; g < graphs_.size(); ++g) {
    surfaces_[graphs_[g].receiver_surface()].graphs_in.push_back(static_cast<int>(g));
  }
  links_now_ = count_links();
  return !pending.empty();
}

std::vector<LinearSolver::ReceiverSide> LinearSolver::receiver_sides(int r, VertexId v) const {
  // docs/design.md §4 "Linear basis, point collocation", curved surfaces: the
  // geometry is the faceted initial mesh, so a node on an initial vertex or
  // edge has no single normal. Its hat function spans every initial face
  // whose closure holds it, and each face sees the scene from its own plane;
  // the node's value is the mean of the one-sided limits taken from inside
  // those faces, weighted by how much of the node's neighbourhood each face
  // is (its angle at an initial vertex; equal halves on an initial edge). A
  // mean of face normals instead would make a closed surface's row sums
  // fall short of 1 at every vertex (the faces through x are seen edge-on).
  const SurfaceState& st = surfaces_[r];
  const SurfaceHierarchy& h = model_.hierarchy(r);
  const TriMesh& mesh = h.mesh();
  const Vec3 x = h.point(v);
  std::array<VertexId, 3> ancestors{kNoVertex, kNoVertex, kNoVertex};
  const int found = initial_ancestors(st.parents, v, ancestors);
  std::vector<ReceiverSide> sides;
  for (const auto fh : mesh.vf_range(OpenMesh::VertexHandle(ancestors[0]))) {
    const auto& k = h.corners(h.root(fh.idx()));
    const bool holds = std::all_of(ancestors.begin(), ancestors.begin() + found, [&](VertexId a) {
      return std::find(k.begin(), k.end(), a) != k.end();
    });
    if (!holds) continue;
    const NodeId root = h.root(fh.idx());
    ReceiverSide side;
    side.normal = model_.normal(r, root);
    const Vec3 inward = model_.centroid(r, root) - x;
    side.approach = inward.norm() > 0 ? inward / inward.norm() : Vec3(0, 0, 0);
    side.weight = 1.0;
    if (found == 1) {
      const int c = static_cast<int>(std::find(k.begin(), k.end(), ancestors[0]) - k.begin());
      const Vec3 a = h.point(k[(c + 1) % 3]) - x, b = h.point(k[(c + 2) % 3]) - x;
      side.weight = std::atan2(OpenMesh::cross(a, b).norm(), OpenMesh::dot(a, b));
    }
    if (side.normal.sqrnorm() > 0 && side.weight > 0) sides.push_back(side);
  }
  return sides;
}

std::vector<LinearSolver::CollocationPoint> LinearSolver::collocation_points(int r, VertexId v) const {
  const Surface& surface = model_.scene().surfaces[r];
  ReceiverPoint point;
  point.x = model_.hierarchy(r).point(v);
  if (surface.planar) {
    point.normal = surface.normal;
    point.approach = surfaces_[r].approach[v];
    return {{point, 1.0}};
  }
  const std::vector<ReceiverSide> sides = receiver_sides(r, v);
  double total_weight = 0.0;
  for (const ReceiverSide& side : sides) total_weight += side.weight;
  std::vector<CollocationPoint> out;
  out.reserve(sides.size());
  for (const ReceiverSide& side : sides) {
    point.normal = side.normal;
    point.approach = side.approach;
    out.push_back({point, side.weight / total_weight});
  }
  return out;
}

TransportCoefficients LinearSolver::coefficients(const InteractionGraph& g, int vertex, NodeId shooter,
                                                 std::uint64_t& rays) const {
  const int r = g.receiver_surface(), s = g.shooter_surface();
  const VertexId v = g.vertex(vertex);
  TransportSampling sampling;
  sampling.k = options_.visibility_samples;
  sampling.key = sample_key((static_cast<std::uint64_t>(s) << 32) | static_cast<std::uint32_t>(r),
                            static_cast<std::uint64_t>(v), static_cast<std::uint64_t>(shooter + 2));
  const std::vector<CollocationPoint> points = collocation_points(r, v);
  if (points.size() == 1) return transport_to(points.front().point, s, shooter, sampling, rays);
  std::array<double, 3> f{0.0, 0.0, 0.0};
  double unoccluded = 0.0;
  for (const CollocationPoint& p : points) {
    const TransportCoefficients c = transport_to(p.point, s, shooter, sampling, rays);
    for (int l = 0; l < 3; ++l) f[l] += p.weight * c.f[l];
    unoccluded += p.weight * c.unoccluded;
  }
  TransportCoefficients out;
  for (int l = 0; l < 3; ++l) out.f[l] = static_cast<float>(f[l]);
  out.unoccluded = static_cast<float>(unoccluded);
  return out;
}

double LinearSolver::unoccluded_form_factor(const ReceiverPoint& point, int s) const {
  const Surface& shooter = model_.scene().surfaces[s];
  const SurfaceHierarchy& h = model_.hierarchy(s);
  const Vec3* approach = point.approach.sqrnorm() > 0 ? &point.approach : nullptr;
  double ff = 0.0;
  if (shooter.planar) {
    std::vector<Vec3> polygon;
    for (const auto& indices : shooter.polygons) {
      polygon.clear();
      for (int i : indices) polygon.push_back(shooter.points[i]);
      ff += point_polygon_form_factor(point.x, point.normal, polygon, approach);
    }
  } else {
    for (std::size_t root = 0; root < h.num_roots(); ++root) {
      ff += point_triangle_form_factor(point.x, point.normal, model_.triangle(s, static_cast<NodeId>(root)), approach);
    }
  }
  return ff;
}

double LinearSolver::unoccluded_form_factor(int r, VertexId v, int s) const {
  double total = 0.0;
  for (const CollocationPoint& p : collocation_points(r, v)) total += p.weight * unoccluded_form_factor(p.point, s);
  return total;
}

double LinearSolver::facet_spread(int r, VertexId v, int s) const {
  const std::vector<CollocationPoint> points = collocation_points(r, v);
  if (points.size() < 2) return 0.0;
  double mean = 0.0, lo = std::numeric_limits<double>::infinity(), hi = 0.0;
  for (const CollocationPoint& p : points) {
    const double ff = unoccluded_form_factor(p.point, s);
    mean += p.weight * ff;
    lo = std::min(lo, ff);
    hi = std::max(hi, ff);
  }
  return mean > 0.0 ? (hi - lo) / mean : 0.0;
}

TransportCoefficients LinearSolver::transport_to(const ReceiverPoint& point, int s, NodeId shooter,
                                                 const TransportSampling& sampling, std::uint64_t& rays) const {
  if (is_cluster_element(shooter)) {
    const SurfaceState& st = surfaces_[s];
    const RootCluster& c = st.clusters[cluster_index(shooter)];
    std::vector<std::array<Vec3, 3>> triangles;
    triangles.reserve(c.roots.size());
    for (NodeId root : c.roots) triangles.push_back(model_.triangle(s, root));
    // docs/accuracy.md, "A bright part that sees more": the link carries the
    // cluster's mean as this receiver weights its roots, from the radiance
    // the cluster holds now.
    const bool open = c.exposed_area > 0;
    std::vector<double> value, openness;
    value.reserve(c.roots.size());
    openness.reserve(c.roots.size());
    for (NodeId root : c.roots) {
      const bool pulled = static_cast<std::size_t>(root) < st.root_luminance.size();
      value.push_back(pulled ? st.root_luminance[root] : 0.0);
      openness.push_back(open ? st.root_exposure[root] : 1.0);
    }
    ShooterShape shape{value, openness, luminance(st.cluster_radiance[cluster_index(shooter)])};
    const ShooterShape* shape_in = st.root_luminance.empty() ? nullptr : &shape;
    const Surface& shooter_surface = model_.scene().surfaces[s];
    if (shooter == kWholeSurface && shooter_surface.planar) {
      std::vector<std::vector<Vec3>> polygons;
      for (const auto& polygon : shooter_surface.polygons) {
        polygons.emplace_back();
        for (int i : polygon) polygons.back().push_back(shooter_surface.points[i]);
      }
      return surface_transport(point, polygons, triangles, model_.rays(), sampling, rays, shape_in);
    }
    if (shooter_surface.planar && !st.outlines.start.empty()) {
      // docs/design.md, "Cluster outlines": the exact form factor from the
      // outline, the shadow rays drawn as for a whole surface.
      const TriMesh& mesh = model_.hierarchy(s).mesh();
      const std::span<const Vec3> points(mesh.points(), mesh.n_vertices());
      const std::optional<double> ff =
          outline_form_factor(point.x, point.normal, c.normal, points, st.outlines.of(cluster_index(shooter)));
      if (ff) return planar_shooter_transport(point, *ff, triangles, model_.rays(), sampling, rays, shape_in, true);
    }
    std::vector<std::array<std::int32_t, 3>> edges;
    edges.reserve(c.roots.size());
    for (NodeId root : c.roots) edges.push_back(st.root_edges[root]);
    return cluster_transport(point, triangles, model_.rays(), sampling, rays, shape_in, edges);
  }
  return triangle_transport(point, model_.triangle(s, shooter), model_.rays(), sampling, rays);
}

void LinearSolver::compute_coefficients(std::vector<PendingLink>& pending) {
  const auto start = Clock::now();
  std::atomic<std::uint64_t> rays{0};
  interruptible_parallel_for(pending.size(), options_.checkpoint, [&](std::size_t i) {
    const PendingLink& p = pending[i];
    InteractionGraph& g = graphs_[p.graph];
    GraphLink& link = g.links(p.vertex)[p.slot];
    std::uint64_t local = 0;
    link.coefficients = coefficients(g, p.vertex, link.shooter, local);
    rays += local;
  });
  stats_.shadow_rays += rays.load();
  stats_.seconds_coefficients += seconds_since(start);
}

void LinearSolver::gather() {
  const auto start = Clock::now();
  unoccluded_at_.resize(graphs_.size());
  tbb::parallel_for(std::size_t{0}, graphs_.size(), [&](std::size_t gi) {
    InteractionGraph& g = graphs_[gi];
    const int s = g.shooter_surface();
    // The unoccluded form factor at the graph's own nodes comes with the
    // links; push() needs it there as the base of what it interpolates.
    std::vector<float>& unoccluded = unoccluded_at_[gi];
    const std::size_t nv = surfaces_[g.receiver_surface()].radiance.size();
    if (unoccluded.size() < nv) unoccluded.resize(nv, std::numeric_limits<float>::quiet_NaN());
    for (int i = 0; i < static_cast<int>(g.num_vertices()); ++i) {
      Rgb sum(0, 0, 0);
      double ff = 0.0;
      for (const GraphLink& link : g.links(i)) {
        ff += link.coefficients.unoccluded;
        for (int l = 0; l < 3; ++l) {
          const float f = link.coefficients.f[l];
          if (f != 0.0f) sum += static_cast<double>(f) * shooter_value(s, link.shooter, l);
        }
      }
      g.gathered(i) = sum;
      unoccluded[g.vertex(i)] = static_cast<float>(ff);
    }
  });
  stats_.seconds_gather += seconds_since(start);
}

double LinearSolver::push() {
  const auto start = Clock::now();
  std::vector<double> change(model_.num_surfaces(), 0.0);
  unoccluded_at_.resize(graphs_.size());
  tbb::parallel_for(0, model_.num_surfaces(), [&](int r) {
    SurfaceState& st = surfaces_[r];
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
    std::vector<VertexId> missing;
    for (int gi : st.graphs_in) {
      const InteractionGraph& g = graphs_[gi];
      std::vector<float>& unoccluded = unoccluded_at_[gi];
      if (unoccluded.size() < nv) unoccluded.resize(nv, std::numeric_limits<float>::quiet_NaN());
      std::fill(exact.begin(), exact.end(), 0);
      for (int i = 0; i < static_cast<int>(g.num_vertices()); ++i) {
        const VertexId v = g.vertex(i);
        contribution[v] = g.gathered(i);
        exact[v] = 1;
        const double ff = unoccluded[v];  // set by gather()
        has_ratio[v] = ff > 0.0;
        ratio[v] = ff > 0.0 ? contribution[v] / ff : Rgb(0, 0, 0);
      }
      missing.clear();
      for (std::size_t v = 0; v < nv; ++v) {
        if (!exact[v] && std::isnan(unoccluded[v])) missing.push_back(static_cast<VertexId>(v));
      }
      tbb::parallel_for(std::size_t{0}, missing.size(), [&](std::size_t i) {
        unoccluded[missing[i]] = static_cast<float>(unoccluded_form_factor(r, missing[i], g.shooter_surface()));
      });
      for (std::size_t v = 0; v < nv; ++v) {
        if (!exact[v]) {
          const auto& [a, b] = st.parents[v];
          if (a == kNoVertex || st.hidden[v]) {
            contribution[v] = Rgb(0, 0, 0);
            has_ratio[v] = 0;
          } else {
            has_ratio[v] = has_ratio[a] || has_ratio[b];
            ratio[v] = has_ratio[a] && has_ratio[b] ? 0.5 * (ratio[a] + ratio[b])
                                                    : (has_ratio[a] ? ratio[a] : ratio[b]);
            contribution[v] = has_ratio[v] ? static_cast<double>(unoccluded[v]) * ratio[v]
                                           : 0.5 * (contribution[a] + contribution[b]);
          }
        }
        total[v] += contribution[v];
      }
    }
    for (std::size_t v = 0; v < nv; ++v) {
      Rgb value;
      for (int c = 0; c < 3; ++c) value[c] = m.emission[c] + m.reflectance[c] * total[v][c];
      change[r] = std::max(change[r], std::abs(luminance(value) - luminance(st.radiance[v])));
      st.radiance[v] = value;
    }
    pull(r);
  });
  stats_.seconds_push_pull += seconds_since(start);
  return *std::max_element(change.begin(), change.end());
}

void LinearSolver::update_importance() {
  const auto start = Clock::now();
  double total_area = 0.0;
  for (int s = 0; s < model_.num_surfaces(); ++s) total_area += model_.surface_area(s);
  for (int s = 0; s < model_.num_surfaces(); ++s) {
    SurfaceState& st = surfaces_[s];
    const SurfaceHierarchy& h = model_.hierarchy(s);
    st.pixels.assign(h.num_nodes(), 0.0);
    if (options_.view.empty()) {
      for (std::size_t n = 0; n < h.num_nodes(); ++n) {
        st.pixels[n] = kDefaultViewPixels * model_.area(s, static_cast<NodeId>(n)) / total_area;
      }
    }
  }
  constexpr double kDelta = 1e-6;  // as the images' log-average (render/)
  if (options_.view.empty()) {
    // Seen face-on: the area-weighted log-average over the initial triangles.
    double log_sum = 0.0;
    brightest_ = 0.0;
    for (int s = 0; s < model_.num_surfaces(); ++s) {
      const SurfaceHierarchy& h = model_.hierarchy(s);
      for (std::size_t f = 0; f < h.num_roots(); ++f) {
        const auto& k = h.corners(static_cast<NodeId>(f));
        double lum = 0.0;
        for (VertexId v : k) lum += luminance(surfaces_[s].radiance[v]) / 3.0;
        log_sum += model_.area(s, static_cast<NodeId>(f)) / total_area * std::log(kDelta + std::max(0.0, lum));
        brightest_ = std::max(brightest_, lum);
      }
    }
    adaptation_ = std::exp(log_sum);
    if (!(adaptation_ > kDelta)) adaptation_ = max_emitted_ > 0 ? max_emitted_ : 1.0;
    if (!(brightest_ > 0)) brightest_ = adaptation_;
    carry_importance_back();
    stats_.seconds_importance += seconds_since(start);
    return;
  }
  // Each pixel counts for every node on the way down to the leaf it sees
  // (paper §4: a node's importance is the share of the image it covers);
  // the leaf's interpolated luminance feeds the tone map's adaptation.
  double log_sum = 0.0;
  brightest_ = 0.0;
  for (const ViewSample& sample : options_.view) {
    SurfaceState& st = surfaces_[sample.surface];
    const SurfaceHierarchy& h = model_.hierarchy(sample.surface);
    const TriMesh& mesh = h.mesh();
    std::array<Vec3, 3> face;
    int k = 0;
    for (const auto vh : mesh.fv_range(mesh.face_handle(sample.face))) face[k++] = mesh.point(vh);
    const Vec3 p = (1.0 - sample.u - sample.v) * face[0] + static_cast<double>(sample.u) * face[1] +
                   static_cast<double>(sample.v) * face[2];
    NodeId n = h.root(sample.face);
    st.pixels[n] += 1.0;
    std::array<double, 3> b = barycentric(p, model_.triangle(sample.surface, n));
    while (!h.is_leaf(n)) {
      // Child c < 3 is the corner region where weight c exceeds ½. A
      // child's corners are its parent's corners and edge midpoints
      // (SurfaceHierarchy::corners), so its weights follow from the
      // parent's: 2b with 1 taken from corner c, or 1 − 2b in the centre.
      int c = 3;
      for (int i = 0; i < 3; ++i) {
        if (b[i] >= 0.5) c = i;
      }
      n = h.child(n, c);
      st.pixels[n] += 1.0;
      for (int i = 0; i < 3; ++i) b[i] = c == 3 ? 1.0 - 2.0 * b[i] : 2.0 * b[i] - (i == c ? 1.0 : 0.0);
    }
    const auto& corners = h.corners(n);
    double lum = 0.0;
    for (int i = 0; i < 3; ++i) lum += std::clamp(b[i], 0.0, 1.0) * luminance(st.radiance[corners[i]]);
    log_sum += std::log(kDelta + std::max(0.0, lum));
    brightest_ = std::max(brightest_, lum);
  }
  adaptation_ = std::exp(log_sum / static_cast<double>(options_.view.size()));
  if (!(adaptation_ > kDelta)) adaptation_ = max_emitted_ > 0 ? max_emitted_ : 1.0;
  if (!(brightest_ > 0)) brightest_ = adaptation_;
  carry_importance_back();
  stats_.seconds_importance += seconds_since(start);
}

double LinearSolver::node_importance(int s, NodeId n) const {
  const std::vector<double>& importance = surfaces_[s].importance;
  return static_cast<std::size_t>(n) < importance.size() ? importance[n] : 0.0;
}

void LinearSolver::carry_importance_back() {
  // docs/design.md §4 "Importance": what the camera sees of a receiver node is worth
  // ρ F^l of it at the shooter's element (the same links, read backwards);
  // one bounce per iteration, from the previous iteration's importance, so
  // it converges with the radiance (ρ Σ F < 1).
  // What cluster links carry is summed per cluster first and shared out to
  // the cluster's roots by area once, not once per link: a top cluster has
  // every root of its surface.
  std::vector<std::vector<double>> cluster_deposit(model_.num_surfaces());
  for (int s = 0; s < model_.num_surfaces(); ++s) {
    surfaces_[s].deposit.assign(model_.hierarchy(s).num_nodes(), 0.0);
    cluster_deposit[s].assign(surfaces_[s].clusters.size(), 0.0);
  }
  for (std::size_t gi = 0; gi < graph_importance_.size() && gi < graphs_.size(); ++gi) {
    const InteractionGraph& g = graphs_[gi];
    const int s = g.shooter_surface();
    SurfaceState& shooter = surfaces_[s];
    const double rho = luminance(model_.material(g.receiver_surface()).reflectance);
    for (std::size_t i = 0; i < graph_importance_[gi].size(); ++i) {
      const double worth = rho * graph_importance_[gi][i];
      if (!(worth > 0)) continue;
      for (const GraphLink& l : g.links(static_cast<int>(i))) {
        const double amount = worth * l.coefficients.visible();
        if (!(amount > 0)) continue;
        if (!is_cluster_element(l.shooter)) {
          shooter.deposit[l.shooter] += amount;
          continue;
        }
        cluster_deposit[s][cluster_index(l.shooter)] += amount;
      }
    }
  }
  for (int s = 0; s < model_.num_surfaces(); ++s) {
    SurfaceState& st = surfaces_[s];
    for (std::size_t ci = 0; ci < st.clusters.size(); ++ci) {
      const double amount = cluster_deposit[s][ci];
      if (!(amount > 0)) continue;
      const RootCluster& c = st.clusters[ci];
      for (NodeId root : c.roots) st.deposit[root] += amount * model_.area(s, root) / c.area;
    }
  }
  // A node's importance: its pixels, what was deposited on it or below it,
  // and its area's share (a quarter per level) of what was deposited above.
  for (int s = 0; s < model_.num_surfaces(); ++s) {
    SurfaceState& st = surfaces_[s];
    const SurfaceHierarchy& h = model_.hierarchy(s);
    const std::size_t n = h.num_nodes();
    std::vector<double> below(st.deposit), above(n, 0.0);
    for (std::size_t k = n; k-- > 0;) {  // children have larger ids than their parent
      const NodeId parent = h.parent(static_cast<NodeId>(k));
      if (parent != kNoNode) below[parent] += below[k];
    }
    st.importance.assign(n, 0.0);
    for (std::size_t k = 0; k < n; ++k) {
      const NodeId parent = h.parent(static_cast<NodeId>(k));
      if (parent != kNoNode) above[k] = 0.25 * (above[parent] + st.deposit[parent]);
      st.importance[k] = st.pixels[k] + above[k] + below[k];
    }
  }
  graph_importance_.assign(graphs_.size(), {});
  for (std::size_t gi = 0; gi < graphs_.size(); ++gi) {
    const InteractionGraph& g = graphs_[gi];
    const int r = g.receiver_surface();
    const SurfaceHierarchy& h = model_.hierarchy(r);
    graph_importance_[gi].assign(g.num_vertices(), 0.0);
    for (NodeId leaf : g.leaves()) {
      for (VertexId v : h.corners(leaf)) graph_importance_[gi][g.index_of(v)] += node_importance(r, leaf) / 3.0;
    }
  }
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
    for (const GraphLink& l : g.links(nv.seed)) links.push_back({l.shooter, {}});
    for (std::size_t t = 0; t < links.size(); ++t) pending.push_back({gi, nv.index, t});
    links_now_ += links.size();
    g.links(nv.index) = std::move(links);
  }
}

bool LinearSolver::refine_shooters() {
  // Paper §4.2: a link whose largest basis contribution, reflected and seen by
  // the camera, is significant is replaced by links from the shooter's
  // children, recursively (a pass per level). The first pass takes the
  // links graph by graph, in the order a list of all of them would have:
  // such a list is as large as the links themselves and would double the
  // memory --max-memory bounds (docs/robustness.md).
  if (options_.checkpoint) options_.checkpoint();
  bool changed = false;
  std::vector<PendingLink> created;
  std::vector<PendingLink> candidates;
  for (std::size_t gi = 0; gi < graphs_.size(); ++gi) {
    const InteractionGraph& g = graphs_[gi];
    candidates.clear();
    for (int i = 0; i < static_cast<int>(g.num_vertices()); ++i) {
      for (std::size_t t = 0; t < g.links(i).size(); ++t) candidates.push_back({static_cast<int>(gi), i, t});
    }
    changed |= split_shooters(candidates, created);
  }
  compute_coefficients(created);
  candidates = std::move(created);
  for (int pass = 1; pass < kMaxShooterPasses && !candidates.empty(); ++pass) {
    if (options_.checkpoint) options_.checkpoint();
    std::vector<PendingLink> next;
    changed |= split_shooters(candidates, next);
    compute_coefficients(next);
    candidates = std::move(next);
  }
  return changed;
}

bool LinearSolver::split_shooters(const std::vector<PendingLink>& candidates, std::vector<PendingLink>& created) {
  bool changed = false;
  const std::vector<std::vector<double>>& importance = graph_importance_;
  const auto shared = shared_representation_error(candidates);
  for (const PendingLink& p : candidates) {
    InteractionGraph& g = graphs_[p.graph];
    const int s = g.shooter_surface();
    if (static_cast<std::size_t>(p.graph) >= importance.size() ||
        static_cast<std::size_t>(p.vertex) >= importance[p.graph].size()) {
      continue;
    }
    const GraphLink link = g.links(p.vertex)[p.slot];
    if (!splittable(s, link.shooter, g.receiver_surface())) continue;
    const Rgb& rho = model_.material(g.receiver_surface()).reflectance;
    double largest = 0.0;
    for (int l = 0; l < 3; ++l) {
      Rgb transfer = static_cast<double>(link.coefficients.f[l]) * shooter_value(s, link.shooter, l);
      for (int c = 0; c < 3; ++c) transfer[c] *= rho[c];
      largest = std::max(largest, luminance(transfer));
    }
    // Or the element's own representation is off, over every node sharing it.
    const double shared_error = shared.at(element_key(p.graph, link.shooter));
    const auto own_error_too_large = [&] {
      if (!(options_.eps_vertex > 0)) return false;
      // A node made in this refinement pass has no value yet: the floor
      // stands for it until the next push.
      const std::vector<Rgb>& values = surfaces_[g.receiver_surface()].radiance;
      const VertexId v = g.vertex(p.vertex);
      const double own = static_cast<std::size_t>(v) < values.size() ? luminance(values[v]) : 0.0;
      const double floor = kRelativeErrorFloor * adaptation_;
      return representation_error(s, link, rho) > options_.eps_vertex * std::max(own, floor);
    };
    const bool seen = largest / adaptation_ * importance[p.graph][p.vertex] > options_.eps_link ||
                      shared_error / adaptation_ > options_.eps_link;
    const bool own = !seen && own_error_too_large();
    if (!seen && !own) continue;
    if (over_budget(3)) continue;
    const std::vector<NodeId> kids = children(s, link.shooter);
    std::vector<GraphLink>& links = g.links(p.vertex);
    links[p.slot] = {kids[0], {}};
    created.push_back(p);
    for (std::size_t c = 1; c < kids.size(); ++c) {
      created.push_back({p.graph, p.vertex, links.size()});
      links.push_back({kids[c], {}});
    }
    links_now_ += kids.size() - 1;
    ++stats_.shooter_refinements;
    if (own) ++stats_.vertex_error_refinements;
    changed = true;
  }
  return changed;
}

bool LinearSolver::refine_receivers(std::vector<PendingLink>& pending, const ToneMap& tone) {
  bool changed = false;
  for (std::size_t gi = 0; gi < graphs_.size(); ++gi) {
    InteractionGraph& g = graphs_[gi];
    const int r = g.receiver_surface();
    SurfaceHierarchy& h = model_.hierarchy(r);
    const SurfaceState& st = surfaces_[r];
    const Rgb& rho = model_.material(r).reflectance;
    // Per graph vertex: S's reflected contribution, everything else, and the
    // fraction of S it sees.
    const auto own = [&](int i) {
      Rgb c = g.gathered(i);
      for (int k = 0; k < 3; ++k) c[k] *= rho[k];
      return luminance(c);
    };
    const auto visibility = [&](int i) {
      double visible = 0.0, unoccluded = 0.0;
      for (const GraphLink& l : g.links(i)) {
        visible += l.coefficients.visible();
        unoccluded += l.coefficients.unoccluded;
      }
      return unoccluded > 0 ? visible / unoccluded : 0.0;
    };
    const ReceiverOracle oracle(tone, options_.vis_threshold);
    // A shooter smaller than a receiver leaf can light a spot inside it that
    // none of its vertices sees (a small light close to R, between
    // vertices): S's contribution is then zero at all of them, and so is
    // every difference the edge tests below look at. What S sends into the
    // leaf, taken as from a point source at S's centre, must then agree
    // with the interpolant's power to kPowerTolerance of the emitted power.
    // (A curved S has no one normal to shoot along: left to the edge tests.)
    const int s = g.shooter_surface();
    const double shooter_area = model_.surface_area(s);
    Rgb reflected_exitance = surfaces_[s].cluster_radiance[0];
    for (int k = 0; k < 3; ++k) reflected_exitance[k] *= rho[k];
    const double shooter_power = shooter_area * luminance(reflected_exitance);
    Vec3 shooter_centre(0, 0, 0);
    if (shooter_area > 0) {
      for (std::size_t f = 0; f < model_.hierarchy(s).num_roots(); ++f) {
        shooter_centre += model_.area(s, static_cast<NodeId>(f)) * model_.centroid(s, static_cast<NodeId>(f));
      }
      shooter_centre /= shooter_area;
    }
    const Vec3& shooter_normal = model_.scene().surfaces[s].normal;
    const auto misses_small_shooter = [&](NodeId leaf) {
      const double area = model_.area(r, leaf);
      if (!model_.scene().surfaces[s].planar || !(area > shooter_area) || !(shooter_power > 0)) return false;
      const double sent =
          shooter_power * point_triangle_form_factor(shooter_centre, shooter_normal, model_.triangle(r, leaf));
      double interpolated = 0.0;
      for (VertexId v : h.corners(leaf)) interpolated += area / 3.0 * own(g.index_of(v));
      return M_PI * std::abs(sent - interpolated) >= kPowerTolerance * total_emitted_power_;
    };
    // A vertex another graph has made is a vertex of the exported mesh, and
    // this graph's share there is interpolated: the contribution over the
    // exact unoccluded form factor, taken as linear between the edge's ends
    // (push). Next to an occluder it is not: along an 8 cm table apron below
    // the top's overhang, or across a window pane beside its reveals, the
    // part of the room in view grows fast, then levels off, and the
    // interpolant fell 5-12 % short of it. Where the ends of an edge
    // disagree that much and the leaf matters to the image, the split costs
    // no new receiver nodes and makes those vertices exact here as well.
    const std::vector<float>* unoccluded = gi < unoccluded_at_.size() ? &unoccluded_at_[gi] : nullptr;
    const auto sent_per_form_factor = [&](VertexId v) {
      const int i = g.index_of(v);
      if (i < 0 || unoccluded == nullptr || static_cast<std::size_t>(v) >= unoccluded->size()) return 0.0;
      const double ff = (*unoccluded)[v];
      return ff > 0.0 ? luminance(g.gathered(i)) / ff : 0.0;
    };
    const auto interpolation_doubtful = [&](NodeId leaf) {
      if (h.is_leaf(leaf) || !(node_importance(r, leaf) > 0.0)) return false;
      const auto& c = h.corners(leaf);
      for (int k = 0; k < 3; ++k) {
        const double a = sent_per_form_factor(c[k]), b = sent_per_form_factor(c[(k + 1) % 3]);
        if (std::abs(a - b) > kDoubtfulInterpolation * std::max(a, b)) return true;
      }
      return false;
    };
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
    const bool curved = !model_.scene().surfaces[r].planar;
    std::vector<float>* facet_spread_cache = nullptr;
    if (curved) {
      if (facet_spread_at_.size() < graphs_.size()) facet_spread_at_.resize(graphs_.size());
      facet_spread_cache = &facet_spread_at_[gi];
      if (facet_spread_cache->size() < st.radiance.size()) {
        facet_spread_cache->resize(st.radiance.size(), std::numeric_limits<float>::quiet_NaN());
      }
    }
    const auto facet_jump_shows = [&](NodeId leaf) {
      const double pixels = node_importance(r, leaf);
      if (facet_spread_cache == nullptr || pixels < options_.eps_pixel) return false;
      for (VertexId v : h.corners(leaf)) {
        const int i = g.index_of(v);
        if (i < 0) continue;
        const double b = own(i);
        if (!(b > 0.0)) continue;
        float& spread = (*facet_spread_cache)[v];
        if (std::isnan(spread)) spread = static_cast<float>(facet_spread(r, v, s));
        const double half_jump = 0.5 * b * spread;
        const double total = luminance(st.radiance[v]);
        const double error = std::min(1.0, half_jump / std::max(total, kRelativeErrorFloor * adaptation_));
        if (ReceiverOracle::refines(error, pixels, options_.eps_pixel)) return true;
      }
      return false;
    };
    std::vector<NodeId> to_split;
    std::vector<OracleEdge> edges;
    for (NodeId leaf : g.leaves()) {
      if (misses_small_shooter(leaf) && splittable(r, leaf, s)) to_split.push_back(leaf);
      if ((interpolation_doubtful(leaf) || facet_jump_shows(leaf)) && splittable(r, leaf, s)) {
        to_split.push_back(leaf);
        continue;
      }
      edges.clear();
      oracle_edges(g, h, leaf, edges);
      for (const OracleEdge& e : edges) {
        const NodeId across = e.right;
        std::array<int, 4> idx{};
        for (int i = 0; i < 4; ++i) idx[i] = g.index_of(e.vertex[i]);
        const std::array<double, 4> w = edge_weights(h.point(e.vertex[0]), h.point(e.vertex[1]),
                                                     h.point(e.vertex[2]), h.point(e.vertex[3]));
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
        const double misplaced = 0.5 * std::abs(second_difference) * (model_.area(r, leaf) + model_.area(r, across));
        const bool by_power = M_PI * misplaced >= kPowerTolerance * total_emitted_power_;
        // ΔE is a display difference, at most 1: too few pixels cannot reach ε_pixel.
        const double pixels = node_importance(r, leaf) + node_importance(r, across);
        if (!by_power && pixels < options_.eps_pixel) continue;
        EdgeValues edge;
        edge.weights = w;
        for (int i = 0; i < 4; ++i) {
          edge.own[i] = own(idx[i]);
          edge.total[i] = luminance(st.radiance[g.vertex(idx[i])]);
        }
        edge.visibility_1 = visibility(idx[0]);
        edge.visibility_2 = visibility(idx[1]);
        if (!by_power && !ReceiverOracle::refines(oracle.display_error(edge), pixels, options_.eps_pixel)) continue;
        if (!splittable(r, leaf, g.shooter_surface()) || !splittable(r, across, g.shooter_surface())) continue;
        to_split.push_back(leaf);
        to_split.push_back(across);
      }
    }
    std::vector<InteractionGraph::NewVertex> created;
    for (NodeId n : to_split) {
      // A split seeds its new vertices (at most 3 unless the restriction
      // splits neighbours too) with the links of a corner.
      std::size_t seeded = 0;
      for (VertexId v : h.corners(n)) {
        if (const int i = g.index_of(v); i >= 0) seeded = std::max(seeded, g.links(i).size());
      }
      if (over_budget(3 * seeded)) break;
      const std::size_t before = created.size();
      if (g.split(n, h, created)) {
        ++stats_.receiver_splits;
        changed = true;
        sync_vertices(r);
        seed_vertices(static_cast<int>(gi), {created.begin() + static_cast<std::ptrdiff_t>(before), created.end()},
                      pending);
      }
    }
  }
  return changed;
}

void LinearSolver::update_link_cap() {
  link_cap_ = options_.max_links > 0 ? options_.max_links : std::numeric_limits<std::size_t>::max();
  memory_caps_ = false;
  if (options_.max_bytes == 0) return;
  collect_stats();
  const std::size_t used = stats_.bytes_total();
  // Each link so far came with its share of the data (nodes, graph vertices,
  // values); the links still to make are assumed to bring the same. A tenth
  // of the budget is kept back for what that misses: the step that crosses
  // the cap and arrays growing by doubling.
  const double per_link = static_cast<double>(used) / static_cast<double>(std::max<std::size_t>(links_now_, 1));
  const double usable = kMemoryBudgetUsable * static_cast<double>(options_.max_bytes);
  const std::size_t room =
      static_cast<double>(used) < usable ? static_cast<std::size_t>((usable - static_cast<double>(used)) / per_link) : 0;
  if (links_now_ + room < link_cap_) {
    link_cap_ = links_now_ + room;
    memory_caps_ = true;
  }
}

bool LinearSolver::over_budget(std::size_t new_links) {
  if (links_now_ + new_links <= link_cap_) return false;
  (memory_caps_ ? stats_.memory_budget_reached : stats_.link_budget_reached) = true;
  return true;
}

bool LinearSolver::refine() {
  const auto start = Clock::now();
  update_link_cap();
  const double coefficient_seconds = stats_.seconds_coefficients;
  bool changed = refine_shooters();
  const std::unique_ptr<ToneMap> tone = options_.tone_map(adaptation_, brightest_);
  std::vector<PendingLink> pending;
  changed |= refine_receivers(pending, *tone);
  if (options_.checkpoint) options_.checkpoint();
  compute_coefficients(pending);
  stats_.seconds_oracles += seconds_since(start) - (stats_.seconds_coefficients - coefficient_seconds);
  return changed;
}

void LinearSolver::solve(const std::function<void(int, double)>& progress) {
  const double scale = max_emitted_ > 0 ? max_emitted_ : 1.0;
  const auto checkpoint = [this] {
    if (options_.checkpoint) options_.checkpoint();
  };
  // The memory cap needs links to measure bytes per link: refine() sets it.
  link_cap_ = options_.max_links > 0 ? options_.max_links : std::numeric_limits<std::size_t>::max();
  for (int it = 1; it <= options_.max_iterations; ++it) {
    checkpoint();
    const std::size_t before = links_now_;
    const bool linked = link_new_shooters();
    // A surface that starts shooting gets its first links even past the cap:
    // without them its light would not reach anything.
    if (links_now_ > link_cap_) stats_.links_linked_past_budget += links_now_ - std::max(before, link_cap_);
    checkpoint();
    gather();
    const double change = push() / scale;
    update_spread();
    update_importance();
    checkpoint();
    // The last allowed iteration only gathers, so the result is consistent.
    const bool refined = it < options_.max_iterations && refine();
    stats_.iterations = it;
    stats_.final_change = change;
    if (progress) progress(it, change);
    if (!linked && !refined && change < options_.tolerance) break;
  }
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
  for (const std::vector<float>& u : unoccluded_at_) stats_.bytes_graphs += u.capacity() * sizeof(float);
  for (const std::vector<float>& u : facet_spread_at_) stats_.bytes_graphs += u.capacity() * sizeof(float);
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
    stats_.bytes_hierarchy += st.root_edges.capacity() * sizeof(st.root_edges[0]) + st.outlines.bytes();
    for (const RootCluster& c : st.clusters) stats_.bytes_hierarchy += sizeof(RootCluster) + c.roots.capacity() * sizeof(NodeId);
    stats_.bytes_values += st.radiance.capacity() * sizeof(Rgb) + st.parents.capacity() * sizeof(st.parents[0]) +
                           st.approach.capacity() * sizeof(Vec3) +
                           st.shooter.corners.capacity() * sizeof(st.shooter.corners[0]) +
                           st.root_luminance.capacity() * sizeof(double) +
                           (st.shooter.root_integral.capacity() + st.shooter.spread.capacity() +
                            st.cluster_spread.capacity()) * sizeof(Rgb) +
                           (st.pixels.capacity() + st.deposit.capacity() + st.importance.capacity()) * sizeof(double);
  }
  stats_.world_adaptation = adaptation_;
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
