#include "radiosity/classical_solver.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <optional>
#include <span>

#include <nlohmann/json.hpp>

#include "radiosity/form_factor.hpp"
#include "radiosity/interruptible.hpp"
#include "radiosity/sampling.hpp"
#include "radiosity/shooter_spread.hpp"
#include "radiosity/tone_map.hpp"
#include "mesh/triangle_geometry.hpp"

namespace lhr {

namespace {

// New links finished at a time in refine_links(): enough for every core.
constexpr std::size_t kPendingChunk = std::size_t{1} << 16;

// At most this many root centres stand for a cluster in a link's visibility
// estimate (its form factor is exact over all its triangles).
constexpr std::size_t kSurfaceSamples = 16;
// Refinement passes per iteration: each pass goes one level deeper.
constexpr int kMaxRefinePasses = 40;

}  // namespace

ClassicalSolver::ClassicalSolver(MeshedScene& model, const ClassicalOptions& options)
    : model_(model), options_(options), floor_(model, options.min_edge), budget_(options.max_links, options.max_bytes) {
  surfaces_.resize(model_.num_surfaces());
  for (int s = 0; s < model_.num_surfaces(); ++s) {
    max_emitted_ = std::max(max_emitted_, luminance(model_.material(s).emission));
    emitted_power_ += luminance(model_.material(s).emission) * model_.surface_area(s);
  }
  for (int s = 0; s < model_.num_surfaces(); ++s) {
    sync_node_arrays(s);
    SurfaceState& st = surfaces_[s];
    st.clusters = SurfaceClusters(model_, s);
    if (model_.scene().surfaces[s].planar) {
      const SurfaceHierarchy& h = model_.hierarchy(s);
      std::vector<std::array<Vec3, 3>> corners(h.num_roots());
      for (std::size_t root = 0; root < corners.size(); ++root) corners[root] = model_.triangle(s, static_cast<NodeId>(root));
      st.roots = ShooterTriangleTable(corners);
      st.outlines = cluster_outlines(h, st.clusters.tree, root_corner_edges(h));
    }
  }
}

void ClassicalSolver::sync_node_arrays(int s) {
  SurfaceState& st = surfaces_[s];
  const SurfaceHierarchy& h = model_.hierarchy(s);
  const std::size_t old_size = st.radiance.size();
  const std::size_t n = h.num_nodes();
  if (n == old_size) return;
  st.radiance.resize(n, Rgb(0, 0, 0));
  st.gathered.resize(n, Rgb(0, 0, 0));
  st.links.resize(n);
  // Constant elements: a new child starts with its parent's radiance (push);
  // a new root is unlit until the first push-pull.
  for (std::size_t i = old_size; i < n; ++i) {
    const NodeId parent = h.parent(static_cast<NodeId>(i));
    st.radiance[i] = parent == kNoNode ? model_.material(s).emission : st.radiance[parent];
  }
}

const Rgb& ClassicalSolver::element_radiance(const Element& e) const {
  const SurfaceState& st = surfaces_[e.surface];
  return is_cluster(e) ? st.clusters.radiance[cluster_index(e)] : st.radiance[e.node];
}

void ClassicalSolver::update_spread(int s) {
  SurfaceState& st = surfaces_[s];
  st.node_spread = constant_node_spread(model_.hierarchy(s), st.radiance);
  SurfaceClusters& clusters = st.clusters;
  clusters.spread = cluster_spread(clusters.tree, clusters.radiance, clusters.root_exposure, st.node_spread,
                                   [&](NodeId root) { return std::array<Rgb, 1>{st.radiance[root]}; });
}

Rgb ClassicalSolver::element_spread(const Element& e) const {
  const SurfaceState& st = surfaces_[e.surface];
  if (is_cluster(e)) {
    const std::size_t c = cluster_index(e);
    return c < st.clusters.spread.size() ? st.clusters.spread[c] : Rgb(0, 0, 0);
  }
  return static_cast<std::size_t>(e.node) < st.node_spread.size() ? st.node_spread[e.node] : Rgb(0, 0, 0);
}

double ClassicalSolver::element_area(const Element& e) const {
  return is_cluster(e) ? cluster(e).area : model_.area(e.surface, e.node);
}

std::vector<ClassicalSolver::Link>& ClassicalSolver::links_of(const Element& e) {
  return surfaces_[e.surface].links[e.node];
}

std::size_t ClassicalSolver::count_links() const {
  std::size_t n = 0;
  for (const SurfaceState& st : surfaces_) {
    for (const auto& l : st.links) n += l.size();
  }
  return n;
}

void ClassicalSolver::link_surfaces() {
  const Scene& scene = model_.scene();
  const double eps = 1e-9 * model_.rays().diagonal();
  std::vector<PendingLink> pending;
  // Finished in batches of about kPendingChunk × 16 pairs, in the order of
  // one pass: all pairs at once were 24 bytes each before any was judged (a
  // thousand boxes: 1.2 GB, most of it the floor's roots and every box).
  const auto finish = [&] {
    compute_coefficients(pending);
    for (const PendingLink& p : pending) {
      if (p.form_factor > 0.0f) links_of(p.receiver).push_back({p.shooter, p.form_factor, p.oracle});
    }
    pending.clear();
  };
  for (int r = 0; r < model_.num_surfaces(); ++r) {
    for (int s = 0; s < model_.num_surfaces(); ++s) {
      if (pending.size() >= 16 * kPendingChunk) finish();
      // A planar surface does not light itself; a curved one does. Its
      // elements see the faces through their own centre edge-on (form
      // factor 0), so a link never carries an element's own light back.
      // A black receiver reflects nothing: links to it would carry nothing,
      // and its uniform field would still be refined (a closed cube of
      // lights alone made 224 M links in 6 minutes; docs/robustness.md).
      if ((r == s && scene.surfaces[r].planar) || !(max_channel(model_.material(r).reflectance) > 0)) continue;
      const Surface& receiver = scene.surfaces[r];
      const Surface& shooter = scene.surfaces[s];
      if (!may_exchange_light(shooter, receiver, eps)) continue;
      // Receivers start at the roots: receiving links live on leaves only
      // (see refine_links), shooters start as whole surfaces.
      for (std::size_t f = 0; f < model_.hierarchy(r).num_roots(); ++f) {
        pending.push_back({{r, static_cast<NodeId>(f)}, {s, kSurfaceElement}, 0.0f});
      }
    }
  }
  finish();
}

float ClassicalSolver::coefficient(const Element& receiver, const Element& shooter, std::uint64_t& rays) const {
  // Receivers are always quadtree nodes (links live on leaves): the form
  // factor is evaluated exactly (Lambert) at the receiver's centre against
  // every triangle of the shooter and scaled by the clear fraction of shadow
  // rays from receiver samples to shooter samples.
  struct Point {
    Vec3 p, n;
  };
  const auto element_key = [](const Element& e) {
    return (static_cast<std::uint64_t>(e.surface) << 32) | static_cast<std::uint32_t>(e.node + 2);
  };
  const std::uint64_t key = sample_key(element_key(receiver), element_key(shooter));
  const int k = std::max(1, options_.visibility_samples);

  const Vec3 x = model_.centroid(receiver.surface, receiver.node);
  const Vec3 nx = model_.normal(receiver.surface, receiver.node);
  std::vector<Point> receiver_vis;
  const auto receiver_triangle = model_.triangle(receiver.surface, receiver.node);
  for (const TriangleSample& ts : stratified_triangle_samples(k, sample_key(key, 1))) {
    receiver_vis.push_back({at(receiver_triangle, ts), nx});
  }
  const RayCaster& scene = model_.rays();
  std::vector<ShadowRay> segments;
  std::vector<double> weights;
  // Only sample pairs that face each other carry energy; a pair behind
  // either plane (the part of a floor triangle under a block, seen from the
  // block's side) has no form factor and must not count as occlusion.
  const auto add_pair = [&](const Point& a, const Point& b, double weight = 1.0) {
    if (OpenMesh::dot(a.n, b.p - a.p) > 0.0 && OpenMesh::dot(b.n, a.p - b.p) > 0.0) {
      segments.push_back({scene.lift(a.p, a.n), scene.lift(b.p, b.n)});
      weights.push_back(weight);
    }
  };
  double ff = 0.0;
  if (is_cluster(shooter)) {
    // Visibility weighted by form factor: shadow rays go to roots drawn in
    // proportion to their share of the cluster's form factor (systematic
    // sampling), so hidden or back-facing parts of a large shooter (floor
    // under a block) do not dilute the visible fraction of the parts that
    // carry the energy.
    const RootCluster& c = cluster(shooter);
    const SurfaceState& st = surfaces_[shooter.surface];
    std::vector<double> cumulative;
    // A planar cluster wholly above the receiver's horizon: its exact form
    // factor from its outline, its rays drawn by the roots' cheap estimates
    // and each weighed by its root's exact form factor over its estimate,
    // so that the visible fraction is the exact-weighted one it was when
    // every root's exact form factor drew the rays. On a panel of 20 000
    // lamps those form factors were most of the solve.
    const std::size_t count = std::max<std::size_t>(receiver_vis.size(), kSurfaceSamples);
    // Where the rays land on most of the roots anyway, each root's exact form
    // factor costs no more than the outline, the estimates and the roots hit.
    bool estimated = false;
    if (c.roots.size() >= 4 * count && !st.outlines.start.empty() &&
        !st.outlines.of(cluster_index(shooter)).empty()) {
      const TriMesh& mesh = model_.hierarchy(shooter.surface).mesh();
      bool clipped = false;
      const std::optional<double> outline_ff =
          outline_form_factor(x, nx, c.normal, std::span<const Vec3>(mesh.points(), mesh.n_vertices()),
                              st.outlines.of(cluster_index(shooter)), &clipped);
      if (outline_ff && !clipped) {
        drawing_form_factor_sums(x, nx, ShooterTriangles{&st.roots, c.roots}, cumulative);
        if (cumulative.back() > 0.0) {
          ff = *outline_ff;
          estimated = true;
        }
      }
    }
    if (!estimated) {
      cumulative.clear();
      cumulative.reserve(c.roots.size());
      for (NodeId r : c.roots) {
        ff += point_triangle_form_factor(x, nx, model_.triangle(shooter.surface, r));
        cumulative.push_back(ff);
      }
    }
    if (!(ff > 0.0)) return 0.0f;
    const double offset = unit_double(sample_key(key, 3));
    std::size_t weighed_root = c.roots.size();
    double root_weight = 1.0;
    for (std::size_t i = 0; i < count; ++i) {
      const double u = (static_cast<double>(i) + offset) / static_cast<double>(count) * cumulative.back();
      const std::size_t j = std::min(static_cast<std::size_t>(std::lower_bound(cumulative.begin(), cumulative.end(), u) -
                                                              cumulative.begin()),
                                     c.roots.size() - 1);
      const NodeId r = c.roots[j];
      const auto triangle = model_.triangle(shooter.surface, r);
      double weight = 1.0;
      if (estimated) {
        // Systematic draws come in root order: a root drawn again is the last one.
        if (j != weighed_root) {
          const double drawn = cumulative[j] - (j > 0 ? cumulative[j - 1] : 0.0);
          root_weight = drawn > 0.0 ? point_triangle_form_factor(x, nx, triangle) / drawn : 0.0;
          weighed_root = j;
        }
        weight = root_weight;
      }
      const TriangleSample ts = uniform_triangle_sample(sample_key(key, 4 + i));
      add_pair(receiver_vis[i % receiver_vis.size()], {at(triangle, ts), model_.normal(shooter.surface, r)}, weight);
    }
  } else {
    const auto tri = model_.triangle(shooter.surface, shooter.node);
    ff = point_triangle_form_factor(x, nx, tri);
    if (!(ff > 0.0)) return 0.0f;
    const Vec3 n = model_.normal(shooter.surface, shooter.node);
    const auto shooter_samples = stratified_triangle_samples(k, sample_key(key, 2));
    const std::size_t pairs = std::max(receiver_vis.size(), shooter_samples.size());
    for (std::size_t i = 0; i < pairs; ++i) {
      add_pair(receiver_vis[i % receiver_vis.size()], {at(tri, shooter_samples[i % shooter_samples.size()]), n});
    }
  }
  // Every sample pair straddles a plane: nothing says the facing part is hidden.
  if (segments.empty()) return static_cast<float>(ff);
  std::vector<std::uint8_t> blocked(segments.size());
  scene.occluded(segments, blocked);
  rays += segments.size();
  double clear = 0.0, all = 0.0;
  for (std::size_t i = 0; i < blocked.size(); ++i) {
    all += weights[i];
    clear += blocked[i] ? 0.0 : weights[i];
  }
  if (!(all > 0.0)) return static_cast<float>(ff);
  return static_cast<float>(ff * clear / all);
}

void ClassicalSolver::compute_coefficients(std::vector<PendingLink>& pending) {
  PhaseTimer timer(stats_.seconds_coefficients);
  std::atomic<std::uint64_t> rays{0};
  interruptible_parallel_for(pending.size(), options_.checkpoint, [&](std::size_t i) {
    std::uint64_t local = 0;
    PendingLink& p = pending[i];
    p.form_factor = coefficient(p.receiver, p.shooter, local);
    p.oracle = static_cast<float>(std::max<double>(p.form_factor, estimate_form_factor(p.receiver, p.shooter)));
    rays += local;
  });
  stats_.shadow_rays += rays.load();
}

double ClassicalSolver::estimate_form_factor(const Element& receiver, const Element& shooter) const {
  // Hanrahan's oracle: the form factor of a disc of the shooter's area seen
  // from the receiver's centre, A cosθi cosθj / (π r² + A).
  const Vec3 ci = model_.centroid(receiver.surface, receiver.node);
  const Vec3 cj = is_cluster(shooter) ? cluster(shooter).centroid : model_.centroid(shooter.surface, shooter.node);
  const Vec3 ni = model_.normal(receiver.surface, receiver.node);
  const Vec3 nj = is_cluster(shooter) ? cluster(shooter).normal : model_.normal(shooter.surface, shooter.node);
  const double a = element_area(shooter);
  const auto disc = [&](const Vec3& x, double& cos_i, double& cos_j) {
    const Vec3 d = cj - x;
    const double r2 = d.sqrnorm();
    const double r = std::sqrt(r2);
    cos_i = r > 0 ? std::max(0.0, OpenMesh::dot(ni, d) / r) : 0.0;
    cos_j = r > 0 ? std::max(0.0, -OpenMesh::dot(nj, d) / r) : 0.0;
    return a / (M_PI * r2 + a);
  };
  double cos_i = 0.0, cos_j = 0.0;
  if (!((cj - ci).sqrnorm() > 0)) return 1.0;
  const double bound = disc(ci, cos_i, cos_j);
  // Near-contact elements (one's centre at the other's horizon) keep a
  // bound that does not vanish: use the unclipped cosines' magnitudes.
  double estimate = std::max(bound * cos_i * cos_j, (cos_i == 0.0 || cos_j == 0.0) ? 0.5 * bound : 0.0);
  // The centre misses a shooter that is smaller than the receiver and close
  // to it: a small light just above a large element puts all its power into
  // a spot away from the centre (docs/design.md §5, small lights). The disc seen from the
  // receiver's point nearest the shooter's centre catches it; it adds
  // nothing where that point is on the shooter's horizon (elements in
  // contact, already covered above).
  if (!(a < model_.area(receiver.surface, receiver.node))) return estimate;
  const double near = disc(closest_point(cj, model_.triangle(receiver.surface, receiver.node)), cos_i, cos_j);
  return std::max(estimate, near * cos_i * cos_j);
}

bool ClassicalSolver::refine_links() {
  const double coefficient_seconds = stats_.seconds_coefficients;
  PhaseTimer timer(stats_.seconds_refine);
  const double threshold = options_.eps_bf * max_emitted_;
  // Links on a node split since they were made (as a shooter) go down to its
  // four children in this pass whatever the budget: they count as made.
  std::size_t links_now = count_links();
  for (int s = 0; s < model_.num_surfaces(); ++s) {
    const SurfaceHierarchy& h = model_.hierarchy(s);
    const auto& links = surfaces_[s].links;
    for (NodeId n = 0; n < static_cast<NodeId>(links.size()); ++n) {
      if (!links[n].empty() && !h.is_leaf(n)) links_now += 3 * links[n].size();
    }
  }
  if (budget_.counts_bytes()) collect_memory_stats();
  budget_.plan(links_now, stats_.bytes_total());
  std::vector<PendingLink> pending;
  bool changed = false;
  // New links wait in `pending` for their coefficients, at more bytes each
  // than a finished link; a pass that pushes most receivers down would list
  // every link there at once, uncounted by --max-memory. They are finished
  // in chunks instead, once the receiver that made them has its own list
  // back: no node takes its links twice, and each link's coefficient
  // depends on its two elements only, so the result is the same.
  const auto finish_pending = [&] {
    compute_coefficients(pending);
    for (const PendingLink& p : pending) {
      if (p.form_factor > 0.0f) links_of(p.receiver).push_back({p.shooter, p.form_factor, p.oracle});
    }
    pending.clear();
  };

  // The floor depends on the other end of the link (radiosity/element_floor.hpp).
  const auto splittable = [&](const Element& e, int partner) {
    return is_cluster(e) || floor_.allows_split(model_.area(e.surface, e.node), e.surface, partner);
  };
  const auto split_node = [&](const Element& e) {
    SurfaceHierarchy& h = model_.hierarchy(e.surface);
    if (h.is_leaf(e.node)) {
      h.split(e.node);
      sync_node_arrays(e.surface);
    }
  };
  // Links a shooter split adds: its children for it, and a leaf split as a
  // shooter then hands the links it receives to its four children.
  const auto shooter_split_adds = [&](const Element& e) -> std::size_t {
    if (is_cluster(e)) {
      const RootCluster& c = cluster(e);
      return (c.first_child >= 0 ? 2 : c.roots.size()) - 1;
    }
    return 3 + (model_.hierarchy(e.surface).is_leaf(e.node) ? 3 * surfaces_[e.surface].links[e.node].size() : 0);
  };
  const auto children_of = [&](const Element& e) {
    std::vector<Element> out;
    if (is_cluster(e)) {
      const RootCluster& c = cluster(e);
      if (c.first_child >= 0) {
        out.push_back({e.surface, -(c.first_child + 2)});
        out.push_back({e.surface, -(c.first_child + 1 + 2)});
      } else {
        for (NodeId r : c.roots) out.push_back({e.surface, r});
      }
      return out;
    }
    split_node(e);
    for (int c = 0; c < 4; ++c) out.push_back({e.surface, model_.hierarchy(e.surface).child(e.node, c)});
    return out;
  };

  const ShooterErrors misplaced = shooter_errors();
  const double misplaced_threshold = options_.eps_bf * emitted_power_;
  for (int s = 0; s < model_.num_surfaces(); ++s) {
    // Nodes created during this pass have no links yet: the pass goes one level deeper at most.
    const NodeId count = static_cast<NodeId>(model_.hierarchy(s).num_nodes());
    for (NodeId n = 0; n < count; ++n) {
      if (surfaces_[s].links[n].empty()) continue;
      const Element receiver{s, n};
      const std::vector<Link> list = std::move(links_of(receiver));
      // Receiving links live on leaves. A leaf's links then partition what
      // it sees, evaluated at one point, so in a closed scene its row sums
      // to 1 and the furnace holds at every element; coefficients kept on a
      // coarse ancestor were evaluated away from the leaf and break that.
      // A receiver split (by its links, a forced split, or as a shooter)
      // therefore hands all its links to its children.
      bool push_down = !model_.hierarchy(s).is_leaf(n);
      std::vector<Link> kept;
      std::vector<PendingLink> local;
      for (const Link& link : list) {
        if (push_down || budget_.refuses(links_now, 1, stats_)) {
          kept.push_back(link);
          continue;
        }
        // Hanrahan's BF, and the error of the shooter's one value for what
        // this receiver sees of it (shooter_spread.hpp): F times its spread.
        const double transfer =
            std::max(luminance(element_radiance(link.shooter)), luminance(element_spread(link.shooter))) * link.oracle;
        // Below the scene's floor (toward a small partner, or across a thin
        // surface) a split must also move power: what the link may get
        // wrong over its receiver, transfer × area, against eps_bf of the
        // emitted power. A small light's spot passes; a sliver 10⁴ times
        // longer than wide, whose floor is an eighth of its width, no
        // longer splits into 10⁵ elements that change nothing
        // (docs/accuracy.md, "Splits below the scene's floor").
        const bool moves_power = transfer * element_area(receiver) > misplaced_threshold;
        const auto may_split = [&](const Element& e, int partner) {
          return splittable(e, partner) &&
                 (is_cluster(e) || moves_power || !floor_.below_scene_floor(model_.area(e.surface, e.node)));
        };
        const bool can_receiver = may_split(receiver, link.shooter.surface);
        const bool can_shooter = may_split(link.shooter, s);
        // The shooter's one value misplaces too much power over all the
        // receivers that take it together (docs/accuracy.md, "The classical
        // method's whole-surface links"): only its own children can help.
        const bool misplaces = can_shooter && misplaced.of(link.shooter) > misplaced_threshold;
        if (!(transfer > threshold || misplaces) || (!can_receiver && !can_shooter)) {
          kept.push_back(link);
          continue;
        }
        // Hanrahan: split the larger of the two. The budget is asked for what
        // the split adds: a receiver hands every link it holds to four
        // children, a shooter is replaced by its children.
        const bool split_receiver = transfer > threshold && can_receiver &&
                                    (!can_shooter || element_area(receiver) >= element_area(link.shooter));
        const std::size_t added =
            split_receiver ? 3 * (list.size() + local.size()) : shooter_split_adds(link.shooter);
        if (budget_.refuses(links_now, added, stats_)) {
          kept.push_back(link);
          continue;
        }
        if (split_receiver) {
          push_down = true;
          kept.push_back(link);
        } else {
          const std::vector<Element> children = children_of(link.shooter);
          for (const Element& child : children) local.push_back({receiver, child, 0.0f});
          links_now += added;
        }
      }
      if (push_down) {
        changed = true;
        const std::vector<Element> children = children_of(receiver);
        for (const Link& link : kept) {
          for (const Element& child : children) pending.push_back({child, link.shooter, 0.0f});
        }
        for (const PendingLink& p : local) {
          for (const Element& child : children) pending.push_back({child, p.shooter, 0.0f});
        }
        links_now += 3 * (kept.size() + local.size());
        kept.clear();
      } else {
        changed |= !local.empty();
        pending.insert(pending.end(), local.begin(), local.end());
      }
      links_of(receiver) = std::move(kept);
      if (pending.size() >= kPendingChunk) finish_pending();
      if (options_.checkpoint && n % 1024 == 0) options_.checkpoint();
    }
  }
  finish_pending();
  // The coefficients of the new links count as their own phase.
  stats_.seconds_refine -= stats_.seconds_coefficients - coefficient_seconds;
  return changed;
}

ClassicalSolver::ShooterErrors ClassicalSolver::shooter_errors() const {
  ShooterErrors out;
  out.nodes.resize(surfaces_.size());
  out.clusters.resize(surfaces_.size());
  for (std::size_t s = 0; s < surfaces_.size(); ++s) {
    out.nodes[s].assign(surfaces_[s].radiance.size(), 0.0);
    out.clusters[s].assign(surfaces_[s].clusters.tree.size(), 0.0);
  }
  // What a link misplaces is at most F × the shooter's spread, reflected by
  // the receiver over its area (a leaf's spread is 0: it stands for itself).
  for (int s = 0; s < model_.num_surfaces(); ++s) {
    const double rho = luminance(model_.material(s).reflectance);
    const SurfaceState& st = surfaces_[s];
    for (NodeId n = 0; n < static_cast<NodeId>(st.links.size()); ++n) {
      const double weight = rho * model_.area(s, n);
      for (const Link& l : st.links[n]) {
        const double error = weight * l.form_factor * luminance(element_spread(l.shooter));
        if (!(error > 0.0)) continue;
        if (is_cluster(l.shooter)) {
          out.clusters[l.shooter.surface][cluster_index(l.shooter)] += error;
        } else {
          out.nodes[l.shooter.surface][l.shooter.node] += error;
        }
      }
    }
  }
  return out;
}

double ClassicalSolver::ShooterErrors::of(const Element& e) const {
  if (is_cluster(e)) return clusters[e.surface][cluster_index(e)];
  const std::vector<double>& v = nodes[e.surface];
  // A node split in this pass has no links yet, hence no error of its own.
  return static_cast<std::size_t>(e.node) < v.size() ? v[e.node] : 0.0;
}

void ClassicalSolver::gather() {
  PhaseTimer timer(stats_.seconds_gather);
  for (int s = 0; s < model_.num_surfaces(); ++s) {
    SurfaceState& st = surfaces_[s];
    const auto sum = [&](const std::vector<Link>& links) {
      Rgb g(0, 0, 0);
      for (const Link& l : links) g += static_cast<double>(l.form_factor) * element_radiance(l.shooter);
      return g;
    };
    tbb::parallel_for(std::size_t{0}, st.links.size(), [&](std::size_t n) { st.gathered[n] = sum(st.links[n]); });
  }
}

double ClassicalSolver::push_pull() {
  PhaseTimer timer(stats_.seconds_push_pull);
  std::vector<double> change(model_.num_surfaces(), 0.0);
  tbb::parallel_for(0, model_.num_surfaces(), [&](int s) {
    SurfaceState& st = surfaces_[s];
    const SurfaceHierarchy& h = model_.hierarchy(s);
    const Material& m = model_.material(s);
    // Hanrahan's PushPull for constant elements: gathered radiance flows down
    // unchanged, leaves add emission and reflect, parents take the mean of
    // their four equal-area children.
    const auto visit = [&](const auto& self, NodeId n, const Rgb& from_above) -> Rgb {
      const Rgb total = from_above + st.gathered[n];
      Rgb value;
      if (h.is_leaf(n)) {
        for (int c = 0; c < 3; ++c) value[c] = m.emission[c] + m.reflectance[c] * total[c];
        const double now = luminance(value), moved = std::abs(now - luminance(st.radiance[n]));
        const double scale = std::max(now, change_floor_);
        change[s] = std::max(change[s], scale > 0.0 ? moved / scale : 0.0);
      } else {
        value = Rgb(0, 0, 0);
        for (int c = 0; c < 4; ++c) value += self(self, h.child(n, c), total);
        value *= 0.25;
      }
      st.radiance[n] = value;
      return value;
    };
    for (std::size_t f = 0; f < h.num_roots(); ++f) visit(visit, static_cast<NodeId>(f), Rgb(0, 0, 0));
    for (std::size_t i = 0; i < st.clusters.tree.size(); ++i) {
      // Reflected power goes to the exposed area; emission is a property of
      // every point (a closed-off part of a lamp shines into the back of
      // what covers it).
      const RootCluster& c = st.clusters.tree[i];
      Rgb reflected(0, 0, 0);
      for (NodeId r : c.roots) reflected += model_.area(s, r) * (st.radiance[r] - m.emission);
      Rgb& value = st.clusters.radiance[i];
      value = m.emission;
      if (c.exposed_area > 0) value += reflected / c.exposed_area;
    }
    update_spread(s);
  });
  // As the linear method's floor, with the scene seen face-on for a camera.
  constexpr double kDelta = 1e-6;  // as the images' log-average (render/)
  double log_sum = 0.0, area = 0.0;
  for (int s = 0; s < model_.num_surfaces(); ++s) {
    const SurfaceHierarchy& h = model_.hierarchy(s);
    for (std::size_t f = 0; f < h.num_roots(); ++f) {
      const double a = model_.area(s, static_cast<NodeId>(f));
      log_sum += a * std::log(kDelta + std::max(0.0, luminance(surfaces_[s].radiance[f])));
      area += a;
    }
  }
  change_floor_ = area > 0.0 ? 0.01 * std::exp(log_sum / area) : 0.0;
  return *std::max_element(change.begin(), change.end());
}

void ClassicalSolver::solve(const std::function<void(int, double)>& progress) {
  link_surfaces();
  push_pull();  // leaves start at their emission
  const auto iteration = [&](int, bool) {
    bool refined = false;
    for (int pass = 0; pass < kMaxRefinePasses; ++pass) {
      run_checkpoint(options_.checkpoint);
      if (!refine_links()) break;
      refined = true;
    }
    run_checkpoint(options_.checkpoint);
    gather();
    return IterationOutcome{refined, push_pull()};
  };
  iterate_until_converged(options_.max_iterations, options_.tolerance, options_.checkpoint, iteration, progress,
                          stats_);
  stats_.links = count_links();
  collect_memory_stats();
}

void ClassicalStats::write_json(nlohmann::json& doc) const {
  SolverStats::write_json(doc, "element_values", bytes_total());
  doc["seconds"]["refine"] = seconds_refine;
}

void ClassicalSolver::collect_memory_stats() {
  stats_.nodes = 0;
  stats_.leaves = 0;
  stats_.bytes_geometry = stats_.bytes_hierarchy = stats_.bytes_values = stats_.bytes_links = 0;
  for (int s = 0; s < model_.num_surfaces(); ++s) {
    const SurfaceHierarchy& h = model_.hierarchy(s);
    const SurfaceState& st = surfaces_[s];
    stats_.nodes += h.num_nodes();
    stats_.leaves += h.num_leaves();
    stats_.bytes_geometry += h.geometry_bytes();
    stats_.bytes_hierarchy += h.hierarchy_bytes();
    // The shooters above the roots count with the hierarchy, as in LinearSolver.
    stats_.bytes_hierarchy += st.clusters.bytes() + st.roots.bytes() + st.outlines.bytes();
    stats_.bytes_values += (st.radiance.capacity() + st.gathered.capacity() + st.node_spread.capacity()) * sizeof(Rgb) +
                           st.links.capacity() * sizeof(std::vector<Link>);
    for (const auto& l : st.links) stats_.bytes_links += l.capacity() * sizeof(Link);
  }
}

double ClassicalSolver::row_sum(int s, NodeId n) const {
  const SurfaceState& st = surfaces_[s];
  double sum = 0.0;
  for (NodeId a = n; a != kNoNode; a = model_.hierarchy(s).parent(a)) {
    for (const Link& l : st.links[a]) sum += l.form_factor;
  }
  return sum;
}

std::vector<Rgb> ClassicalSolver::vertex_radiance(int s, const ConformingMesh& mesh) const {
  std::vector<Rgb> sum(mesh.mesh.n_vertices(), Rgb(0, 0, 0));
  std::vector<double> weight(mesh.mesh.n_vertices(), 0.0);
  for (const auto fh : mesh.mesh.faces()) {
    const double a = mesh.mesh.calc_face_area(fh);
    const Rgb& value = surfaces_[s].radiance[mesh.leaf[fh.idx()]];
    for (const auto vh : mesh.mesh.fv_range(fh)) {
      sum[vh.idx()] += a * value;
      weight[vh.idx()] += a;
    }
  }
  for (std::size_t v = 0; v < sum.size(); ++v) {
    if (weight[v] > 0) sum[v] /= weight[v];
  }
  return sum;
}

}  // namespace lhr
