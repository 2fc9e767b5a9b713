#include "radiosity/linear_solver.hpp"

// LinearSolver's transport (paper §3): the coefficients of a link at a
// receiver vertex, the points a vertex is collocated at, and the unoccluded
// form factors push() interpolates by.

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "radiosity/form_factor.hpp"
#include "radiosity/interruptible.hpp"
#include "radiosity/sampling.hpp"

namespace lhr {
namespace {

// docs/accuracy.md, "A node's noise": the relative standard deviation the
// draws of a node's links may leave in its value, bounded as if the rays
// were independent (stratified ones usually leave less): at 2.5 σ, the 10 %
// that a node may be off by. A link draws at most kMaxNoiseK times the k of
// --visibility-samples, and values under kNoiseFloor of the adaptation (the
// relative norm's floor) are bounded as if they were that bright.
constexpr double kNodeNoise = 0.04;
constexpr int kMaxNoiseK = 4;
constexpr double kNoiseFloor = 0.01;

}  // namespace

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

ReceiverPoint LinearSolver::planar_collocation_point(int r, VertexId v) const {
  ReceiverPoint point;
  point.x = model_.hierarchy(r).point(v);
  point.normal = model_.scene().surfaces[r].normal;
  point.approach = surfaces_[r].approach[v];
  return point;
}

std::vector<LinearSolver::CollocationPoint> LinearSolver::collocation_points(int r, VertexId v) const {
  if (model_.scene().surfaces[r].planar) return {{planar_collocation_point(r, v), 1.0}};
  ReceiverPoint point;
  point.x = model_.hierarchy(r).point(v);
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

TransportCoefficients LinearSolver::coefficients(const InteractionGraph& g, int vertex, NodeId shooter, int k,
                                                 std::uint64_t draw, std::uint64_t& rays) const {
  const int r = g.receiver_surface(), s = g.shooter_surface();
  const VertexId v = g.vertex(vertex);
  TransportSampling sampling;
  sampling.k = k;
  // Surface indices are below 2³¹: the top bit tells the draws apart.
  sampling.key = sample_key((draw << 63) | (static_cast<std::uint64_t>(s) << 32) | static_cast<std::uint32_t>(r),
                            static_cast<std::uint64_t>(v), static_cast<std::uint64_t>(shooter + 2));
  // A planar receiver's one point, without the vector (this runs for every
  // link a solve makes).
  if (model_.scene().surfaces[r].planar) return transport_to(planar_collocation_point(r, v), s, shooter, sampling, rays);
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
    // docs/design.md, "Cluster outlines": seen plainly, the roots' inner
    // edges cancel even where the surface bends; otherwise each inner edge
    // is still integrated once.
    const SurfaceState& st = surfaces_[s];
    if (!st.outlines.start.empty()) {
      const TriMesh& mesh = h.mesh();
      const std::optional<double> outline =
          open_outline_form_factor(point.x, point.normal, st.root_triangles.corner,
                                   std::span<const Vec3>(mesh.points(), mesh.n_vertices()), st.outlines.of(0));
      if (outline) return *outline;
    }
    thread_local std::vector<double> per_root;
    shared_edge_form_factors(point.x, point.normal, st.root_triangles.corner, st.root_edges, approach, per_root);
    for (const double f : per_root) ff += f;
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
    const RootCluster& c = st.clusters.tree[cluster_index(shooter)];
    const ShooterTriangles triangles{&st.root_triangles, c.roots};
    // docs/accuracy.md, "A bright part that sees more": the link carries the
    // cluster's mean as this receiver weights its roots, from the luminances
    // all links from the surface stand on ("A shape factor that ages").
    assert(st.shaped_root_luminance.size() == st.root_triangles.size());
    ShooterShape shape{st.shaped_root_luminance, st.shaped_cluster_luminance[cluster_index(shooter)]};
    const ShooterShape* shape_in = &shape;
    const Surface& shooter_surface = model_.scene().surfaces[s];
    if (shooter == kWholeSurface && shooter_surface.planar) {
      // Reused across links: the input polygons are few, but allocating
      // them at every link was a few per cent of a solve.
      thread_local std::vector<std::vector<Vec3>> polygons;
      polygons.resize(shooter_surface.polygons.size());
      for (std::size_t k = 0; k < polygons.size(); ++k) {
        polygons[k].clear();
        for (int i : shooter_surface.polygons[k]) polygons[k].push_back(shooter_surface.points[i]);
      }
      return surface_transport(point, polygons, triangles, model_.rays(), sampling, rays, shape_in);
    }
    if (shooter_surface.planar && !st.outlines.start.empty()) {
      // docs/design.md, "Cluster outlines": the exact form factor from the
      // outline, the shadow rays drawn as for a whole surface.
      const TriMesh& mesh = model_.hierarchy(s).mesh();
      const std::span<const Vec3> points(mesh.points(), mesh.n_vertices());
      bool clipped = false;
      const std::optional<double> ff = outline_form_factor(point.x, point.normal, c.normal, points,
                                                           st.outlines.of(cluster_index(shooter)), &clipped);
      if (ff) {
        return planar_shooter_transport(point, *ff, triangles, model_.rays(), sampling, rays, shape_in,
                                        clipped ? ShooterHorizon::kCrossing : ShooterHorizon::kAbove);
      }
    }
    if (!shooter_surface.planar) {
      // docs/design.md, "Cluster outlines": seen plainly, a curved cluster's
      // exact form factor is its outline's too.
      const TriMesh& mesh = model_.hierarchy(s).mesh();
      const std::span<const std::array<VertexId, 2>> outline =
          st.outlines.start.empty() ? std::span<const std::array<VertexId, 2>>()
                                    : st.outlines.of(cluster_index(shooter));
      const std::optional<TransportCoefficients> seen_plainly =
          curved_cluster_transport(point, triangles, std::span<const Vec3>(mesh.points(), mesh.n_vertices()), outline,
                                   model_.rays(), sampling, rays, shape_in);
      if (seen_plainly) return *seen_plainly;
    }
    return cluster_transport(point, triangles, model_.rays(), sampling, rays, shape_in, st.root_edges);
  }
  return triangle_transport(point, model_.triangle(s, shooter), model_.rays(), sampling, rays);
}

int LinearSolver::noise_bounded_k(const InteractionGraph& g, int vertex, const GraphLink& link,
                                  const TransportCoefficients& drawn) const {
  const int k = options_.visibility_samples;
  const double phi = std::clamp(static_cast<double>(link.judged_fraction), 0.0, 1.0);
  if (!(phi > 0.0 && phi < 1.0) || k <= 0) return k;
  const int r = g.receiver_surface(), s = g.shooter_surface();
  const Rgb& rho = model_.material(r).reflectance;
  // What the link would bring unoccluded: its exact form factor times the
  // shooter's mean value, reflected.
  const int values = is_cluster_element(link.shooter) ? 1 : 3;
  double shooter = 0.0;
  for (int l = 0; l < values; ++l) {
    Rgb b = shooter_value(s, link.shooter, l);
    for (int c = 0; c < 3; ++c) b[c] *= rho[c];
    shooter += luminance(b) / values;
  }
  const double open = static_cast<double>(drawn.unoccluded) * shooter;
  // The node's value: at least what this link brings, judged.
  const VertexId v = g.vertex(vertex);
  const std::vector<Rgb>& radiance = surfaces_[r].radiance;
  const double known = static_cast<std::size_t>(v) < radiance.size() ? luminance(radiance[v]) : 0.0;
  const double value = std::max({known, phi * open, kNoiseFloor * adaptation_});
  if (!(value > 0.0)) return k;
  // docs/accuracy.md, "A node's noise": n independent rays leave a variance
  // of open² φ(1−φ)/n. Each link keeps it within kNodeNoise² · value · φ·open,
  // its share of the value, so all of a node's links together stay within
  // (kNodeNoise · value)².
  const double rays = open * (1.0 - phi) / (kNodeNoise * kNodeNoise * value);
  const double want = std::ceil(std::sqrt(rays));
  return static_cast<int>(std::clamp(want, static_cast<double>(k), static_cast<double>(kMaxNoiseK * k)));
}

void LinearSolver::compute_coefficients(std::vector<PendingLink>& pending) {
  PhaseTimer timer(stats_.seconds_coefficients);
  std::atomic<std::uint64_t> rays{0};
  interruptible_parallel_for(pending.size(), options_.checkpoint, [&](std::size_t i) {
    const PendingLink& p = pending[i];
    InteractionGraph& g = graphs_[p.graph];
    GraphLink& link = g.links(p.vertex)[p.slot];
    std::uint64_t local = 0;
    const int k = options_.visibility_samples;
    // The pilot and the second draw below share their geometry.
    const SharedLinkGeometry shared;
    TransportCoefficients drawn = coefficients(g, p.vertex, link.shooter, k, 0, local);
    const bool first = link.judged_fraction < 0.0f;
    // A first link is judged by this pilot draw, and drawn afresh below, so
    // that what the shooter oracle reads is never its own draw.
    if (first) {
      link.coefficients = drawn;
      link.judged_fraction = link.drawn_fraction();
    }
    const int more = drawn.unoccluded > 0.0f ? noise_bounded_k(g, p.vertex, link, drawn) : k;
    if (first && drawn.unoccluded > 0.0f) {
      drawn = coefficients(g, p.vertex, link.shooter, more, 1, local);
    } else if (more > k) {
      // How many rays is decided from another draw's fraction and exact
      // form factors, not from this draw: both draws are unbiased, and so
      // is their mean weighted by their rays.
      const TransportCoefficients second = coefficients(g, p.vertex, link.shooter, more, 1, local);
      const float w = static_cast<float>(k * k) / static_cast<float>(k * k + more * more);
      for (int l = 0; l < 3; ++l) drawn.f[l] = w * drawn.f[l] + (1.0f - w) * second.f[l];
    }
    link.coefficients = drawn;
    rays += local;
  });
  stats_.shadow_rays += rays.load();
}

void LinearSolver::redraw_cluster_links() {
  PhaseTimer timer(stats_.seconds_coefficients);
  std::vector<PendingLink> pending;
  for (std::size_t g = 0; g < graphs_.size(); ++g) {
    for (int v = 0; v < static_cast<int>(graphs_[g].num_vertices()); ++v) {
      const auto links = graphs_[g].links(v);
      for (std::size_t slot = 0; slot < links.size(); ++slot) {
        if (is_cluster_element(links[slot].shooter)) pending.push_back({static_cast<int>(g), v, slot});
      }
    }
  }
  std::atomic<std::uint64_t> rays{0};
  interruptible_parallel_for(pending.size(), options_.checkpoint, [&](std::size_t i) {
    const PendingLink& p = pending[i];
    InteractionGraph& g = graphs_[p.graph];
    GraphLink& link = g.links(p.vertex)[p.slot];
    if (!(link.coefficients.unoccluded > 0.0f)) return;
    std::uint64_t local = 0;
    // Never the pilot's rays, which the oracles judged the link by
    // (compute_coefficients), and k² of them in every iteration: a count
    // that followed the node's value (noise_bounded_k) would change the rays
    // from one iteration to the next, and the solve would not settle.
    const SharedLinkGeometry shared;
    link.coefficients = coefficients(g, p.vertex, link.shooter, options_.visibility_samples, 1, local);
    rays += local;
  });
  stats_.shadow_rays += rays.load();
}

namespace {

// A cluster's form factor from x as a disc of its open area facing along its
// mean normal: the weight its part of a receiver's view takes when a shape
// factor is rescaled.
double cluster_disc_form_factor(const ReceiverPoint& x, const RootCluster& part) {
  const double area = part.exposed_area > 0.0 ? part.exposed_area : part.area;
  const Vec3 d = part.centroid - x.x;
  const double r2 = d.sqrnorm();
  if (!(r2 > 0.0)) return 0.0;
  const double r = std::sqrt(r2);
  const double cos_x = std::clamp(OpenMesh::dot(x.normal, d) / r, 0.0, 1.0);
  const double cos_y = std::clamp(-OpenMesh::dot(part.normal, d) / r, 0.0, 1.0);
  return area * cos_x * cos_y / (M_PI * r2 + area);
}

}  // namespace

double LinearSolver::reshape_scale(const InteractionGraph& g, int vertex, NodeId shooter) const {
  const SurfaceState& st = surfaces_[g.shooter_surface()];
  const std::size_t top = cluster_index(shooter);
  const double was = st.shaped_cluster_luminance[top], now = luminance(st.clusters.radiance[top]);
  if (!(was > 0.0 && now > 0.0)) return 1.0;
  const int r = g.receiver_surface();
  const VertexId v = g.vertex(vertex);
  thread_local std::vector<CollocationPoint> points;
  if (model_.scene().surfaces[r].planar) {
    points.assign(1, {planar_collocation_point(r, v), 1.0});
  } else {
    points = collocation_points(r, v);
  }
  // The parts: the clusters kShapeDepth levels below, or leaf clusters above that.
  thread_local std::vector<std::pair<std::int32_t, int>> stack;
  stack.assign(1, {static_cast<std::int32_t>(top), 0});
  double seen_was = 0.0, seen_now = 0.0;
  while (!stack.empty()) {
    const auto [c, depth] = stack.back();
    stack.pop_back();
    const RootCluster& cluster = st.clusters.tree[c];
    if (cluster.first_child >= 0 && depth < kShapeDepth) {
      stack.push_back({cluster.first_child, depth + 1});
      stack.push_back({cluster.first_child + 1, depth + 1});
      continue;
    }
    double w = 0.0;
    for (const CollocationPoint& p : points) w += p.weight * cluster_disc_form_factor(p.point, cluster);
    seen_was += w * st.shaped_cluster_luminance[c];
    seen_now += w * luminance(st.clusters.radiance[c]);
  }
  if (!(seen_was > 0.0)) return 1.0;
  return (seen_now / now) / (seen_was / was);
}

void LinearSolver::reshape_cluster_links() {
  if (!options_.rescale_cluster_links && !options_.redraw_cluster_links) return;
  std::vector<std::uint8_t> due(surfaces_.size(), 0);
  bool any = false;
  for (std::size_t s = 0; s < surfaces_.size(); ++s) {
    // Links drawn again every iteration stand on the radiance now.
    due[s] = surfaces_[s].reshape_due || options_.redraw_cluster_links;
    any = any || due[s];
  }
  if (!any) return;
  if (!options_.redraw_cluster_links) {
    std::atomic<std::size_t> rescaled{0};
    tbb::parallel_for(std::size_t{0}, graphs_.size(), [&](std::size_t gi) {
      InteractionGraph& g = graphs_[gi];
      if (!due[g.shooter_surface()]) return;
      std::size_t here = 0;
      for (int v = 0; v < static_cast<int>(g.num_vertices()); ++v) {
        for (GraphLink& link : g.links(v)) {
          if (!is_cluster_element(link.shooter) || link.coefficients.f[0] == 0.0f) continue;
          link.coefficients.f[0] = static_cast<float>(link.coefficients.f[0] * reshape_scale(g, v, link.shooter));
          ++here;
        }
      }
      rescaled += here;
    });
    stats_.cluster_links_rescaled += rescaled.load();
  }
  for (std::size_t s = 0; s < surfaces_.size(); ++s) {
    if (due[s]) take_shaped_luminance(static_cast<int>(s));
  }
}

}  // namespace lhr
