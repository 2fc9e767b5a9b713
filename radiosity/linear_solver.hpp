#pragma once
// The paper's method: linear hierarchical radiosity with the image-space
// refinement criterion (paper §3–5; docs/design.md §4).
//
// Values live at the vertices of every surface's quadtree (point collocation
// of a linear basis, three hat functions per triangle). Each (shooter S,
// receiver R) pair that exchanges energy has an InteractionGraph holding S's
// contribution over R exactly at the graph's vertices; R's radiance at any of
// its vertices is E + ρ Σ_graphs (that graph's contribution, pushed down by
// linear interpolation except where the graph computed it exactly). Graphs are
// created progressively (Holzschuch et al. 1994) and refined by the shooter
// oracle (§4.2) and the per-shooter receiver oracle (§4.1), both weighted by
// the image's importance. Radiance, not radiosity, is carried (B = πL).

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <unordered_map>
#include <vector>

#include "radiosity/compact_tables.hpp"
#include "radiosity/element_floor.hpp"
#include "radiosity/interaction_graph.hpp"
#include "radiosity/root_clusters.hpp"
#include "radiosity/meshed_scene.hpp"
#include "radiosity/shooter_spread.hpp"
#include "radiosity/solver_frame.hpp"
#include "radiosity/tone_map.hpp"
#include "radiosity/transport.hpp"
#include "radiosity/unoccluded_cache.hpp"

namespace lhr {

// Where one camera pixel sees the scene: initial face `face` of surface
// `surface`, barycentrics (u, v) of that face's corners 1 and 2 in the
// surface mesh's face-vertex order (what an Embree hit reports).
struct ViewSample {
  std::int32_t surface = -1;
  std::int32_t face = -1;
  float u = 0, v = 0;
};

struct LinearOptions {
  // Receiver oracle (§4.1): split both triangles of a graph edge when the
  // display error ΔE times the pixels they cover reaches eps_pixel.
  double eps_pixel = 0.3;
  // Shooter oracle (§4.2): refine a link when its largest basis contribution,
  // reflected, relative to the world adaptation luminance, times the pixels
  // of the receiving node's hat function, exceeds eps_link. Also when the
  // error of the shooter element's own values (form factor times its spread,
  // shooter_spread.hpp), reflected, relative to the adaptation, summed over
  // the pixels of every node of the graph linked to that element, does: the
  // nodes share that error, so it is one error over all their pixels.
  double eps_link = 10.0;
  // Object-space bound on the exported values (the mesh is the product, seen
  // from anywhere): refine a link when the error of its shooter element's
  // values reaching the node (form factor times spread, reflected) exceeds
  // this fraction of the node's own radiance (at least 1 % of the
  // adaptation luminance). Near a concave edge or a contact, the node's
  // light comes from the shooter's value right next to it, which a coarse
  // element's mean cannot stand for. 0 turns the test off.
  double eps_vertex = 0.05;
  // Receiver refinement in object space, whatever the camera sees: a graph
  // edge is split when the reflected power linear interpolation misplaces
  // across it reaches this fraction of the emitted power (refine_receivers),
  // and a leaf when what a small shooter sends into it and its interpolant
  // disagree that much. Next to concave edges that error has one sign, a
  // loss, and every bounce repeats it: at 10⁻⁴ a room lit only through a
  // door lost 3 % of its light that way, and a bright closed room 1 % of its
  // lamp's power (docs/accuracy.md, "Concave junctions"). What is left of
  // it shrinks with this bound (docs/accuracy.md, "The power bound").
  double eps_power = 1e-5;
  // |V1 − V2| at or above this is a visibility change (§4.1): the oracle
  // then uses the conservative max − min.
  double vis_threshold = 0.1;
  // Elements whose edges are shorter than this (scene units) are not split;
  // 0 = h/32, less toward surfaces smaller than that (radiosity/element_floor.hpp).
  double min_edge = 0.0;
  int max_iterations = 50;
  // Stop when nothing was refined or linked and no vertex's luminance
  // changed by more than tolerance times itself, taken as at least 1 % of
  // the adaptation luminance (docs/accuracy.md, "When the iteration stops").
  double tolerance = 1e-4;
  // Progressive linking: surfaces start shooting (get graphs) brightest first,
  // until those left out carry together less than this fraction of the total
  // emitted power, so the light dropped is bounded however many small
  // surfaces the scene has.
  double link_power = 1e-4;
  // Each oracle judges a graph again only once what its verdicts read (S's
  // and R's radiance, R's importance, the tone map's adaptation) has moved
  // by this much, relative and summed over the iterations since it last did,
  // or the graph's links or the hierarchy the oracle reads changed
  // (docs/design.md, "One iteration"). 0 judges every graph at every pass.
  double oracle_drift = 0.01;
  // Merge a vertex's links to all the children of a shooter element back
  // into one when the shooter oracle would keep that link (docs/design.md,
  // "Coarsening links"); false keeps every link it opened, as the paper does.
  bool coarsen_links = true;
  // Draw every link from a cluster of a surface's roots again in every
  // iteration, from the radiance its shooter then holds. A cluster link's
  // shape factor is made from its shooter's values when it is drawn, mostly
  // in the first iterations, peaked under the lamps; the bounces even them
  // out, and the early factors keep an excess (docs/accuracy.md, "A shape
  // factor that ages"). A measuring instrument: about four times the solve's
  // time, and each cluster link keeps k² rays.
  bool redraw_cluster_links = false;
  // Rescale every link from a cluster of a surface's roots, without new
  // rays, once its shooter's radiance relative to its mean has moved by 1 %
  // from the values its shape factors were made with: the receiver's view of
  // the cluster's parts, five levels of the cluster tree down, weighed by
  // those values and by the values now (docs/accuracy.md, "A shape factor
  // that ages"). Takes out the same excess as redraw_cluster_links at a
  // small part of its cost; off by default because the losses it uncovers
  // are not yet fixed (the same section).
  bool rescale_cluster_links = false;
  // k: at least k² basis-weighted shadow rays per link, more where a node's
  // noise needs them (noise_bounded_k).
  int visibility_samples = 4;
  std::size_t max_links = 0;  // 0 = no limit
  // Memory of the radiosity data (LinearStats::bytes_total(): hierarchies,
  // vertex values, graphs, links), bytes; 0 = no limit. Refinement stops
  // before the data passes it; linking new shooters does not.
  std::size_t max_bytes = 0;
  // What the camera sees, for importance and the tone map's adaptation; empty:
  // every surface seen face-on, pixels in proportion to area.
  std::vector<ViewSample> view;
  // Display intensity M for the receiver oracle, given the log-average and
  // the largest luminance the camera sees now (recomputed each iteration).
  // Default: Tumblin–Rushmeier with the docs/design.md §4 defaults.
  std::function<std::unique_ptr<ToneMap>(double log_average, double brightest)> tone_map;
  // Called between the phases of an iteration and within the long loops
  // (radiosity/interruptible.hpp); may throw to abandon the solve (an
  // interrupted run), leaving the solver unusable.
  std::function<void()> checkpoint;
};

struct LinearStats : SolverStats {
  std::size_t graphs = 0;
  std::size_t graph_vertices = 0;
  std::vector<std::size_t> leaves_per_level;
  std::size_t links_linked_past_budget = 0;  // first links of shooters that began after the cap
  // Power of the surfaces left out of progressive linking, as a fraction of
  // the emitted power: at most link_power, and what the memory budget left
  // out (power_left_out_for_memory, from surfaces_left_out_for_memory
  // surfaces whose first links did not fit).
  double power_left_out = 0.0;
  double power_left_out_for_memory = 0.0;
  std::size_t surfaces_left_out_for_memory = 0;
  std::size_t receiver_splits = 0;  // receiver-oracle splits (graph edges)
  std::size_t receiver_judgements = 0;  // graphs the receiver oracle judged, summed over its passes
  std::size_t shooter_judgements = 0;   // graphs whose links the shooter oracle judged, summed over iterations
  std::size_t shooter_refinements = 0;  // shooter-oracle link refinements
  std::size_t cluster_links_rescaled = 0;  // LinearOptions::rescale_cluster_links
  std::size_t vertex_error_refinements = 0;  // of those, asked for by eps_vertex alone
  std::size_t shooter_coarsenings = 0;  // links merged back into their parent element
  double world_adaptation = 0.0;
  std::size_t bytes_graphs = 0;  // graph node states, vertex tables, per-graph caches and importance
  std::size_t bytes_total() const {
    return bytes_geometry + bytes_hierarchy + bytes_values + bytes_graphs + bytes_links;
  }
  double seconds_linking = 0.0;  // new graphs
  double seconds_oracles = 0.0;  // both oracles and the splits they make
  double seconds_importance = 0.0;
  // stats.json's entries (docs/design.md §1 outputs).
  void write_json(nlohmann::json& doc) const;
};

class LinearSolver {
 public:
  LinearSolver(MeshedScene& model, LinearOptions options);

  // Iterates link / gather / push / refine until converged. progress(iteration,
  // change) after each iteration when given.
  void solve(const std::function<void(int, double)>& progress = {});

  // Radiance at every vertex of surface s's hierarchy (VertexId order).
  const std::vector<Rgb>& vertex_radiance(int s) const { return surfaces_[s].radiance; }
  // Per vertex of a conforming mesh of surface s: the collocated values.
  std::vector<Rgb> vertex_radiance(int s, const ConformingMesh& mesh) const;

  const LinearStats& stats() const { return stats_; }
  const std::vector<InteractionGraph>& graphs() const { return graphs_; }

  // Σ_links Σ_l F^l reaching R's vertex v through every graph that holds it
  // exactly: 1 at every vertex of a closed scene.
  double row_sum(int receiver, VertexId v) const;

 private:
  struct SurfaceState {
    std::vector<Rgb> radiance;  // per vertex
    std::vector<std::array<VertexId, 2>> parents;  // per vertex: the edge it is the midpoint of
    std::vector<Vec3> approach;  // per vertex: unit direction into the surface
    // Per vertex: 1 when the point is enclosed on both sides (a floor vertex
    // under a box): it receives nothing, whatever its neighbours receive.
    std::vector<std::uint8_t> hidden;
    SurfaceClusters clusters;  // a cluster's radiance: the mean over it
    std::vector<std::array<std::int32_t, 3>> root_edges;  // root_corner_edges
    ShooterTriangleTable root_triangles;                   // per root, for cluster links
    // The area-weighted centre of its roots: where the receiver oracle
    // takes a small shooter's light to come from (every oracle pass of
    // every graph summed it anew, a twentieth of a room's solve).
    Vec3 centre{0, 0, 0};
    ClusterOutlines outlines;                              // planar surfaces only
    // What each node shoots with and how far that is from the radiance it
    // stands for; the same bound for each cluster's mean (shooter_spread.hpp).
    LinearShooterValues shooter;
    // docs/accuracy.md, "A shape factor that ages": the luminances, per root
    // and per cluster, that the shape factors of its cluster links stand on,
    // its values at the last pull. With rescale_cluster_links they are kept
    // until its radiance relative to its mean has moved from them by
    // kShapeDrift; every cluster link from it is then rescaled to the
    // radiance it holds, which they become (reshape_cluster_links).
    std::vector<double> shaped_root_luminance;
    std::vector<double> shaped_cluster_luminance;
    bool reshape_due = false;
    std::vector<double> pixels;      // per node: image pixels it covers
    std::vector<double> deposit;     // per node: importance its links carried back to it
    std::vector<double> importance;  // per node: pixels plus what reflection makes of it elsewhere
    // This iteration: the largest relative change of its radiance (push) and
    // of its nodes' importance (carry_importance_back), what both oracles'
    // verdicts on its graphs can move with.
    double drift = std::numeric_limits<double>::infinity();
    std::size_t synced_nodes = 0;
    bool shooting = false;
    // Its first links did not fit in the memory budget: it waits for good
    // (the room only shrinks), and refinement keeps no room for it.
    bool left_out_for_memory = false;
    std::vector<int> graphs_in;  // graphs with this surface as receiver
  };
  struct PendingLink {
    int graph;
    int vertex;
    std::size_t slot;
  };

  // The initial vertices vertex v is interpolated from, following the
  // midpoint parents: 1 on an initial vertex, 2 on an initial edge, 3 inside
  // an initial face. Their count is returned.
  static int initial_ancestors(const std::vector<std::array<VertexId, 2>>& parents, VertexId v,
                               std::array<VertexId, 3>& ancestors);
  void sync_vertices(int s);
  bool link_new_shooters();
  // Whether shooter s gets a graph on receiver r when it starts.
  bool first_links_possible(int s, int r, double eps) const;
  const InteractionGraph::Start& start_of(int r);
  // An upper bound on the bytes shooter s's first links keep.
  std::size_t first_link_bytes(int s, double eps);
  // What the first links of the surfaces waiting to shoot will take, worked
  // out until it reaches `enough`.
  std::size_t waiting_first_link_bytes(std::size_t enough);
  // Clears starts[s] for the dimmer shooters whose first links the memory
  // budget cannot hold (`waiting`: power and surface, dimmest first); returns
  // their power.
  double leave_out_past_the_budget(const std::vector<std::pair<double, int>>& waiting, std::vector<bool>& starts);
  void compute_coefficients(std::vector<PendingLink>& pending);
  // LinearOptions::redraw_cluster_links: every cluster link's own draw
  // again, from its shooter's radiance now.
  void redraw_cluster_links();
  // Each shooter's radiance as its cluster links' shape factors take it:
  // at every pull, or with rescale_cluster_links at its first light and
  // again, with every cluster link from it rescaled, once the pull has
  // marked it reshape_due.
  static constexpr double kShapeDrift = 0.01;
  static constexpr int kShapeDepth = 5;
  void take_shaped_luminance(int s);
  void reshape_cluster_links();
  // A cluster link's shape factor rescaled from the shooter's shaped
  // luminances to its radiance now, as the receiver at `vertex` sees its
  // parts (clusters kShapeDepth levels down) without occlusion.
  double reshape_scale(const InteractionGraph& g, int vertex, NodeId shooter) const;
  // One draw of a link's coefficients with k² rays per shooter triangle;
  // draws with different `draw` numbers are independent.
  TransportCoefficients coefficients(const InteractionGraph& g, int vertex, NodeId shooter, int k,
                                     std::uint64_t draw, std::uint64_t& rays) const;
  // The k a link is drawn with so that the noise of all of a node's links
  // stays within kNodeNoise of its value (docs/accuracy.md, "A node's noise").
  int noise_bounded_k(const InteractionGraph& g, int vertex, const GraphLink& link,
                      const TransportCoefficients& drawn) const;
  // One face of a curved surface that a node lies on, seen from inside it.
  struct ReceiverSide {
    Vec3 normal;
    Vec3 approach;
    double weight;
  };
  std::vector<ReceiverSide> receiver_sides(int r, VertexId v) const;
  // The points R's vertex v is collocated at, with their weights (one for a
  // planar receiver, one per side on a curved one).
  struct CollocationPoint {
    ReceiverPoint point;
    double weight;
  };
  std::vector<CollocationPoint> collocation_points(int r, VertexId v) const;
  // The one point of a vertex of a planar R.
  ReceiverPoint planar_collocation_point(int r, VertexId v) const;
  // Exact form factor from all of surface s to R's vertex v, ignoring
  // occlusion: what coefficients() would sum to over any complete cut of s
  // with every shadow ray clear.
  double unoccluded_form_factor(int r, VertexId v, int s) const;
  double unoccluded_form_factor(const ReceiverPoint& point, int s) const;
  // On a curved R, how far apart the faces around vertex v see s: the
  // spread (max − min) of their unoccluded form factors over the node's
  // mean. 0 for a node inside one face (docs/accuracy.md, "Facet edges").
  double facet_spread(int r, VertexId v, int s) const;
  TransportCoefficients transport_to(const ReceiverPoint& point, int s, NodeId shooter,
                                     const TransportSampling& sampling, std::uint64_t& rays) const;
  // S's contribution at graph g's vertex i before reflection: Σ_links Σ_l
  // F^l B_j^l from the shooter's values of the last pull.
  Rgb gathered(const InteractionGraph& g, int i) const;
  // Gathers every graph and pushes (docs/design.md §4, "Interaction graphs").
  // Returns the largest relative change of a vertex (`drift`).
  double push();
  void update_importance();
  void carry_importance_back();
  double node_importance(int s, NodeId n) const;
  bool refine();
  // Marks the graphs whose links the shooter oracle judges this iteration
  // and coarsens their links (coarsen_links).
  std::vector<std::uint8_t> coarsen_due_graphs();
  // Refines the links of the graphs `due` marks.
  bool refine_shooters(const std::vector<std::uint8_t>& due);
  // One pass of refine_shooters() over the given links; appends the links it
  // makes (without coefficients) to created.
  bool split_shooters(const std::vector<PendingLink>& candidates, std::vector<PendingLink>& created);
  // The shooter oracle's measures of one link at graph g's vertex i (it
  // must have an importance): what the link carries, reflected, relative
  // to the adaptation and times the vertex's importance (against
  // eps_link), and its shooter's representation error reaching the vertex
  // with what eps_vertex allows there.
  struct LinkJudgement {
    double seen = 0.0;
    double own_error = 0.0;
    double own_allowed = 0.0;
  };
  LinkJudgement judge_link(int g, int i, const GraphLink& link) const;
  // The element whose children shooter element e is one of (a quadtree
  // parent, the cluster that opens onto a root, a cluster's parent), or
  // kNoNode for the whole surface.
  NodeId parent_element(int s, NodeId e) const;
  // The link to `parent` that the links at `slots` of `links` (all of its
  // children, nothing else) add up to; none if they are not all of them.
  std::optional<GraphLink> merged_link(int s, NodeId parent, std::span<const GraphLink> links,
                                       std::span<const std::size_t> slots) const;
  // Merges graph g's links back into their parent where the shooter oracle
  // would keep it.
  struct Coarsening {
    std::size_t merges = 0;
    std::size_t links_removed = 0;
  };
  Coarsening coarsen_links(int g);
  bool refine_receivers(std::vector<PendingLink>& pending, const ToneMap& tone);
  class ReceiverTests;
  std::vector<NodeId> receiver_leaves_to_split(int graph, const ToneMap& tone);
  bool split_receiver_leaves(int graph, const std::vector<NodeId>& to_split, std::vector<PendingLink>& pending);
  void seed_vertices(int graph, const std::vector<InteractionGraph::NewVertex>& created,
                     std::vector<PendingLink>& pending);
  Rgb shooter_value(int s, NodeId element, int l) const;
  void pull(int s);
  void update_spread();
  double representation_error(int s, const GraphLink& link, const Rgb& rho) const;
  std::unordered_map<std::uint64_t, double> shared_representation_error(const std::vector<PendingLink>& links) const;
  // The floor depends on the other end of the interaction (ElementFloor).
  bool splittable(int s, NodeId element, int partner) const;
  std::vector<NodeId> children(int s, NodeId element);
  std::size_t count_links() const;
  void collect_stats();

  MeshedScene& model_;
  LinearOptions options_;
  std::vector<SurfaceState> surfaces_;
  std::vector<InteractionGraph> graphs_;
  // Per receiver surface, what its graphs start from (shared by them all).
  std::vector<std::shared_ptr<const InteractionGraph::Start>> starts_;
  // Per graph and graph vertex: the importance of its hat function over the
  // graph's leaves (what a change of S's contribution there is worth).
  // Summed in double and kept in 16 bits (BFloat16, within 0.4 %): it only
  // weighs the shooter oracle's threshold, and a double a graph vertex was
  // 11 MB of the four rooms' graph tables, a float 5.4 MB. Held only while
  // refine() runs, for the graphs the shooter oracle judges then: kept
  // between iterations for every graph it was a quarter of the two rooms'
  // graph tables (BENCHMARKS.md, "Graph storage under 30 %").
  std::vector<std::vector<BFloat16>> graph_importance_;
  // Graph gi's vertex importance from its leaves as they are now and its
  // receiver's node importance.
  void vertex_importance(int gi, std::vector<BFloat16>& out) const;
  // Per graph, its vertices when the importance was last worked out: the
  // importance carried back is theirs (a vertex made since has no links
  // judged by it yet), as when every graph's table was kept.
  std::vector<std::uint32_t> importance_vertices_;
  // Per graph, at the receiver vertices that are not graph vertices, filled
  // when push() first needs it: the unoccluded form factor from the graph's
  // shooter (at a graph vertex the links sum to it).
  std::vector<UnoccludedCache> unoccluded_at_;
  // Per graph and receiver vertex of a curved receiver, filled when
  // refine_receivers() first needs it: facet_spread() (NaN until computed).
  std::vector<std::vector<float>> facet_spread_at_;
  // docs/design.md, "One iteration": each oracle judges a graph again only
  // once what it reads has drifted by oracle_drift since it last did, or the
  // graph's links or a hierarchy it reads have changed. Per graph and
  // oracle: the drift since then (infinite: judge) and the node count then
  // of the hierarchy it reads (R's for the receiver oracle, S's for the
  // shooter oracle).
  struct OracleWatch {
    float drift = std::numeric_limits<float>::infinity();
    std::uint32_t nodes = 0;
    // Adds an iteration's drift; true, and the watch starts again, when the
    // graph is to be judged.
    bool due(double moved, std::uint32_t nodes_now, double threshold) {
      drift += static_cast<float>(moved);
      if (drift < threshold && nodes == nodes_now) return false;
      *this = {0.0f, nodes_now};
      return true;
    }
  };
  // What a graph's verdicts read has moved by this iteration: R's and S's
  // radiance and R's importance (their surfaces' drift) and the tone map's.
  double graph_drift(const InteractionGraph& g) const {
    return surfaces_[g.receiver_surface()].drift + surfaces_[g.shooter_surface()].drift + tone_drift_;
  }
  std::vector<OracleWatch> oracle_watch_;   // the receiver oracle's
  std::vector<OracleWatch> shooter_watch_;  // the shooter oracle's
  double tone_drift_ = std::numeric_limits<double>::infinity();  // adaptation and brightest, this iteration
  double max_emitted_ = 0.0;
  double total_emitted_power_ = 0.0;
  ElementFloor floor_;
  double adaptation_ = 1.0;  // log-average luminance the camera sees
  double brightest_ = 1.0;
  std::size_t links_now_ = 0;
  // Refinement makes no link beyond its cap.
  LinkBudget budget_;
  LinearStats stats_;
};

}  // namespace lhr
