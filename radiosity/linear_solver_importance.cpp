#include "radiosity/linear_solver.hpp"

// LinearSolver's importance (paper §4; docs/design.md §4 "Importance"): the
// pixels each node covers, the adaptation luminance the camera sees, and
// what reflection makes of them on the shooters.

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace lhr {

namespace {

// Without a camera every surface is seen face-on, this many pixels in all,
// shared in proportion to area.
constexpr double kDefaultViewPixels = 512.0 * 512.0;

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

}  // namespace

void LinearSolver::update_importance() {
  PhaseTimer timer(stats_.seconds_importance);
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
  const double adaptation_before = adaptation_, brightest_before = brightest_;
  // What the receiver oracle's tone map moved by (docs/design.md, "One iteration").
  const auto note_tone_drift = [&] {
    tone_drift_ = std::abs(adaptation_ - adaptation_before) / adaptation_ +
                  std::abs(brightest_ - brightest_before) / brightest_;
  };
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
    note_tone_drift();
    carry_importance_back();
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
  note_tone_drift();
  carry_importance_back();
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
    cluster_deposit[s].assign(surfaces_[s].clusters.tree.size(), 0.0);
  }
  // Each graph's vertex importance from the last iteration's node importance,
  // made here per graph rather than kept between iterations (docs/design.md,
  // "Graph storage"), and carried from the vertices the graph had then.
  // A graph deposits only on its shooter: the shooters are carried to in
  // parallel, each from its graphs in graph order, as one loop would.
  std::vector<std::vector<int>> by_shooter(model_.num_surfaces());
  for (std::size_t gi = 0; gi < graphs_.size() && gi < importance_vertices_.size(); ++gi) {
    by_shooter[graphs_[gi].shooter_surface()].push_back(static_cast<int>(gi));
  }
  tbb::parallel_for(0, model_.num_surfaces(), [&](int s) {
    SurfaceState& shooter = surfaces_[s];
    std::vector<BFloat16> importance;
    for (const int gi : by_shooter[s]) {
      const InteractionGraph& g = graphs_[gi];
      const double rho = luminance(model_.material(g.receiver_surface()).reflectance);
      vertex_importance(gi, importance);
      const std::size_t carried = std::min<std::size_t>(importance_vertices_[gi], importance.size());
      for (std::size_t i = 0; i < carried; ++i) {
        const double worth = rho * importance[i];
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
  });
  for (int s = 0; s < model_.num_surfaces(); ++s) {
    SurfaceState& st = surfaces_[s];
    for (std::size_t ci = 0; ci < st.clusters.tree.size(); ++ci) {
      const double amount = cluster_deposit[s][ci];
      if (!(amount > 0)) continue;
      const RootCluster& c = st.clusters.tree[ci];
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
    std::vector<double> before(n, 0.0);
    std::copy_n(st.importance.begin(), std::min(n, st.importance.size()), before.begin());
    st.importance.assign(n, 0.0);
    // A node's pixels matter to the receiver oracle from ε_pixel on.
    const double floor = std::max(options_.eps_pixel, 1e-12);
    double drift = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
      const NodeId parent = h.parent(static_cast<NodeId>(k));
      if (parent != kNoNode) above[k] = 0.25 * (above[parent] + st.deposit[parent]);
      st.importance[k] = st.pixels[k] + above[k] + below[k];
      drift = std::max(drift, std::abs(st.importance[k] - before[k]) / std::max(st.importance[k], floor));
    }
    st.drift = std::max(st.drift, drift);
  }
  importance_vertices_.resize(graphs_.size());
  for (std::size_t gi = 0; gi < graphs_.size(); ++gi) {
    importance_vertices_[gi] = static_cast<std::uint32_t>(graphs_[gi].num_vertices());
  }
}

void LinearSolver::vertex_importance(int gi, std::vector<BFloat16>& out) const {
  const InteractionGraph& g = graphs_[gi];
  const int r = g.receiver_surface();
  const SurfaceHierarchy& h = model_.hierarchy(r);
  const std::size_t known = surfaces_[r].importance.size();
  thread_local std::vector<double> sum;
  sum.assign(g.num_vertices(), 0.0);
  for (NodeId leaf : g.leaves(h)) {
    // A leaf made since the node importance was last worked out has its
    // area's share of its nearest ancestor's, a quarter per level.
    NodeId n = leaf;
    double share = 1.0;
    while (static_cast<std::size_t>(n) >= known && h.parent(n) != kNoNode) {
      n = h.parent(n);
      share *= 0.25;
    }
    const double importance = share * node_importance(r, n) / 3.0;
    for (VertexId v : h.corners(leaf)) sum[g.index_of(v)] += importance;
  }
  out.resize(sum.size());
  for (std::size_t i = 0; i < sum.size(); ++i) out[i] = BFloat16(sum[i]);
}

}  // namespace lhr
