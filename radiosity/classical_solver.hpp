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
#include "radiosity/meshed_scene.hpp"
#include "radiosity/solver_frame.hpp"
#include "radiosity/transport.hpp"

namespace lhr {

struct ClassicalOptions {
  // A link from shooter j to receiver i is refined while L_j·F_ij, or the
  // spread of j's leaves about L_j times F_ij (how far L_j may be from what
  // i sees of j, shooter_spread.hpp), exceeds eps_bf times the brightest
  // emitted luminance; and j is split for all its receivers while the power
  // its spread may misplace over all of them together, Σ ρ_i A_i F_ij
  // spread_j, exceeds eps_bf times the emitted power.
  double eps_bf = 1e-3;
  // Elements whose edges are shorter than this (scene units) are not split;
  // 0 = h/32, less toward surfaces smaller than that (radiosity/element_floor.hpp).
  double min_edge = 0.0;
  int max_iterations = 100;
  // Stop when no link was refined and no leaf's luminance changed by more
  // than tolerance times itself, taken as at least 1 % of the scene's
  // area-weighted log-average luminance (docs/accuracy.md, "When the
  // iteration stops"): the linear method's test.
  double tolerance = 1e-4;
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

struct ClassicalStats : SolverStats {
  double seconds_refine = 0.0;  // oracle and splits
  std::size_t bytes_total() const { return bytes_geometry + bytes_hierarchy + bytes_values + bytes_links; }
  // stats.json's entries (docs/design.md §1 outputs).
  void write_json(nlohmann::json& doc) const;
};

class ClassicalSolver {
 public:
  ClassicalSolver(MeshedScene& model, const ClassicalOptions& options);

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
  struct Link {
    Element shooter;
    float form_factor;
    float oracle;  // form factor bound the BF test uses, fixed when the link is made
  };
  struct SurfaceState {
    std::vector<Rgb> radiance;  // per node
    std::vector<Rgb> gathered;  // per node
    std::vector<std::vector<Link>> links;  // per node: links this node receives
    // A cluster's radiance: its emission + reflected power / (π exposed_area).
    SurfaceClusters clusters;
    // The roots' geometry and, on a planar surface, each cluster's outline:
    // a large cluster's form factor from its outline and its shadow rays
    // drawn by cheap estimates, not every root's exact form factor
    // (docs/design.md, "Cluster outlines").
    ShooterTriangleTable roots;
    ClusterOutlines outlines;
    // How far each node's one value is from the leaves it stands for
    // (shooter_spread.hpp).
    std::vector<Rgb> node_spread;
  };
  struct PendingLink {
    Element receiver;
    Element shooter;
    float form_factor = 0.0f;
    float oracle = 0.0f;
  };

  // Per shooter element (node or cluster), the power its one value may
  // misplace summed over every link that takes it: Σ ρ_i A_i F_ij spread_j.
  struct ShooterErrors {
    std::vector<std::vector<double>> nodes;     // per surface, per node
    std::vector<std::vector<double>> clusters;  // per surface, per cluster
    double of(const Element& e) const;
  };

  void link_surfaces();
  bool refine_links();
  ShooterErrors shooter_errors() const;
  void compute_coefficients(std::vector<PendingLink>& pending);
  float coefficient(const Element& receiver, const Element& shooter, std::uint64_t& rays) const;
  double estimate_form_factor(const Element& receiver, const Element& shooter) const;
  void gather();
  // Returns the largest relative change of a leaf (ClassicalOptions::tolerance).
  double push_pull();
  void sync_node_arrays(int s);
  static bool is_cluster(const Element& e) { return e.node <= kSurfaceElement; }
  static std::size_t cluster_index(const Element& e) { return static_cast<std::size_t>(-(e.node + 2)); }
  const RootCluster& cluster(const Element& e) const { return surfaces_[e.surface].clusters.tree[cluster_index(e)]; }
  const Rgb& element_radiance(const Element& e) const;
  void update_spread(int s);
  Rgb element_spread(const Element& e) const;
  double element_area(const Element& e) const;
  std::vector<Link>& links_of(const Element& e);
  std::size_t count_links() const;
  void collect_memory_stats();

  MeshedScene& model_;
  ClassicalOptions options_;
  std::vector<SurfaceState> surfaces_;
  double max_emitted_ = 0.0;
  // Σ emitted luminance × area over the emitters: what ε_BF scales in the
  // summed test (radiance units; π left out on both sides).
  double emitted_power_ = 0.0;
  ElementFloor floor_;
  // 1 % of the area-weighted log-average luminance of the roots at the last
  // push_pull: the least a relative change is taken against.
  double change_floor_ = 0.0;
  LinkBudget budget_;
  ClassicalStats stats_;
};

}  // namespace lhr
