#pragma once
// Classical hierarchical radiosity (Hanrahan, Salzman, Aupperle 1991): the
// constant-element baseline the paper's method is charted against (docs/design.md §4
// "Classical HR baseline").
//
// Elements are the quadtree nodes of every surface and, above its roots, a
// binary tree of root clusters whose top is the whole surface (the input
// polygon of Hanrahan's method): shooters start as whole surfaces and open
// up only as far as the BF test asks.
//
// A cluster shoots with its power spread over its exposed area, not its
// whole area: parts of a surface closed off by others (the floor under a
// block, the ceiling above a lamp hung just below it) gather nothing and
// are seen by no receiver, so an area average would dim what the
// receivers do see and lose that share of the surface's power (measured
// on the Cornell box: 2.7 % of the emitted power). Which parts are closed
// off: root_exposure() in radiosity/root_clusters.hpp.
//
// Radiance, not radiosity, is carried: L = Le + ρ Σ F L (B = πL, same form).

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "radiosity/element_floor.hpp"
#include "radiosity/scene_model.hpp"

namespace lhr {

struct ClassicalOptions {
  // A link from shooter j to receiver i is refined while L_j·F_ij, or the
  // spread of j's leaves about L_j times F_ij (how far L_j may be from what
  // i sees of j, shooter_spread.hpp), exceeds eps_bf times the brightest
  // emitted luminance.
  double eps_bf = 1e-3;
  // Elements whose edges are shorter than this (scene units) are not split;
  // 0 = h/32, less toward surfaces smaller than that (radiosity/element_floor.hpp).
  double min_edge = 0.0;
  int max_iterations = 100;
  // Stop when no link was refined and no leaf radiance changed by more than
  // tolerance times the brightest emitted luminance.
  double tolerance = 1e-5;
  int visibility_samples = 4;  // k: k² shadow rays per element link
  std::size_t max_links = 0;   // 0 = no limit
  // Memory of the radiosity data (ClassicalStats::bytes_total()), bytes;
  // 0 = no limit. Refinement stops before the data passes it.
  std::size_t max_bytes = 0;
  // Called between phases and within the long loops (radiosity/
  // interruptible.hpp); may throw to abandon the solve (an interrupted run),
  // leaving the solver unusable.
  std::function<void()> checkpoint = {};
};

struct ClassicalStats {
  std::size_t links = 0;
  std::size_t leaves = 0;
  std::size_t nodes = 0;
  int iterations = 0;
  bool link_budget_reached = false;    // max_links stopped refinement
  bool memory_budget_reached = false;  // max_bytes stopped refinement
  std::uint64_t shadow_rays = 0;
  double seconds_refine = 0.0;        // oracle and splits
  double seconds_coefficients = 0.0;  // form factors and visibility of new links
  double seconds_gather = 0.0;
  double seconds_push_pull = 0.0;
  double final_change = 0.0;  // relative to the brightest emitted luminance
  // Memory, bytes (allocated capacity), as LinearStats counts it.
  std::size_t bytes_geometry = 0;   // vertex positions and initial meshes
  std::size_t bytes_hierarchy = 0;  // quadtree nodes
  std::size_t bytes_values = 0;     // per-node radiance, gathered value, link list header; root clusters
  std::size_t bytes_links = 0;
  std::size_t bytes_total() const { return bytes_geometry + bytes_hierarchy + bytes_values + bytes_links; }
};

class ClassicalSolver {
 public:
  ClassicalSolver(SceneModel& model, const ClassicalOptions& options);

  // Iterates refine / gather / push-pull until converged. progress(iteration,
  // change) is called after each iteration when given.
  void solve(const std::function<void(int, double)>& progress = {});

  // Radiance of a leaf (or any node) of surface s.
  const Rgb& radiance(int s, NodeId n) const { return surfaces_[s].radiance[n]; }
  // Σ F·L over the links node n receives (links live on leaves): the
  // irradiance of a leaf divided by π, before reflection.
  const Rgb& gathered(int s, NodeId n) const { return surfaces_[s].gathered[n]; }
  // Per vertex of a conforming mesh of surface s: area-weighted average of
  // the leaves around it (constant elements have no vertex values of their own).
  std::vector<Rgb> vertex_radiance(int s, const ConformingMesh& mesh) const;

  const ClassicalStats& stats() const { return stats_; }

  // Σ of the coefficients that reach node n of surface s through its own,
  // its ancestors' and its surface's links: 1 in a closed scene (furnace).
  double row_sum(int s, NodeId n) const;

 private:
  // Element::node ≥ 0 is a quadtree node; node ≤ -2 is root cluster −(node+2),
  // cluster 0 (kSurfaceElement) being the whole surface.
  static constexpr NodeId kSurfaceElement = -2;
  struct Element {
    std::int32_t surface;
    NodeId node;
  };
  struct RootCluster {
    std::vector<NodeId> roots;
    std::int32_t first_child = -1;  // two consecutive child clusters, or -1: children are the roots
    double area = 0.0;
    Vec3 centroid{0, 0, 0};
    Vec3 normal{0, 0, 0};  // unit mean normal
    double exposed_area = 0.0;  // area of its points that are not closed off
    Rgb radiance{0, 0, 0};      // emission + reflected power / (π exposed_area)
  };
  struct Link {
    Element shooter;
    float form_factor;
    float oracle;  // form factor bound the BF test uses, fixed when the link is made
  };
  struct SurfaceState {
    std::vector<Rgb> radiance;  // per node
    std::vector<Rgb> gathered;  // per node
    std::vector<std::vector<Link>> links;  // per node: links this node receives
    std::vector<RootCluster> clusters;  // [0] = the whole surface
    // How far each node's and each cluster's one value is from the leaves it
    // stands for (shooter_spread.hpp).
    std::vector<Rgb> node_spread;
    std::vector<Rgb> cluster_spread;
    std::vector<double> root_exposure;  // per root, root_exposure()
  };
  struct PendingLink {
    Element receiver;
    Element shooter;
    float form_factor = 0.0f;
    float oracle = 0.0f;
  };

  void link_surfaces();
  bool refine_links();
  void compute_coefficients(std::vector<PendingLink>& pending);
  float coefficient(const Element& receiver, const Element& shooter, std::uint64_t& rays) const;
  double estimate_form_factor(const Element& receiver, const Element& shooter) const;
  void gather();
  double push_pull();
  void sync_node_arrays(int s);
  void build_clusters(int s, const std::vector<double>& root_exposure);
  static bool is_cluster(const Element& e) { return e.node <= kSurfaceElement; }
  const RootCluster& cluster(const Element& e) const { return surfaces_[e.surface].clusters[-(e.node + 2)]; }
  const Rgb& element_radiance(const Element& e) const;
  void update_spread(int s);
  Rgb element_spread(const Element& e) const;
  double element_area(const Element& e) const;
  std::vector<Link>& links_of(const Element& e);
  std::size_t count_links() const;
  void collect_memory_stats();

  SceneModel& model_;
  ClassicalOptions options_;
  std::vector<SurfaceState> surfaces_;
  double max_emitted_ = 0.0;
  ElementFloor floor_;
  ClassicalStats stats_;
};

}  // namespace lhr
