#pragma once
// What the two radiosity methods share (docs/design.md §4): the iteration
// loop with its interrupt checks, the link and memory budget, phase timing,
// the statistics every run reports, and the shooters above each surface's
// roots. Each solver keeps only what differs: its basis, its oracles, its
// links.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "radiosity/root_clusters.hpp"
#include "radiosity/meshed_scene.hpp"

namespace lhr {

// What every solve reports; LinearStats and ClassicalStats add their own.
struct SolverStats {
  std::size_t links = 0;
  std::size_t nodes = 0;
  std::size_t leaves = 0;
  int iterations = 0;
  bool link_budget_reached = false;    // max_links stopped refinement
  bool memory_budget_reached = false;  // max_bytes stopped refinement
  std::uint64_t shadow_rays = 0;
  // The largest change of the last iteration, relative to the brightest
  // emitted luminance.
  double final_change = 0.0;
  // Memory, bytes (allocated capacity).
  std::size_t bytes_geometry = 0;   // vertex positions and initial meshes
  std::size_t bytes_hierarchy = 0;  // quadtree nodes
  std::size_t bytes_values = 0;     // per-node or per-vertex values and bookkeeping
  std::size_t bytes_links = 0;
  double seconds_coefficients = 0.0;  // form factors and visibility of new links
  double seconds_gather = 0.0;
  double seconds_push_pull = 0.0;

  // stats.json's entries for these (docs/design.md §1 outputs): the sizes,
  // "bytes" with `values_name` naming bytes_values and `bytes_total` the
  // method's whole, and "seconds".
  void write_json(nlohmann::json& doc, const char* values_name, std::size_t bytes_total) const;
};

// Adds the wall time of its scope to a phase's seconds.
class PhaseTimer {
 public:
  explicit PhaseTimer(double& seconds) : seconds_(seconds), start_(std::chrono::steady_clock::now()) {}
  PhaseTimer(const PhaseTimer&) = delete;
  PhaseTimer& operator=(const PhaseTimer&) = delete;
  ~PhaseTimer() { stop(); }
  // Ends the phase before the scope does (later calls add nothing).
  void stop() {
    if (running_) seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    running_ = false;
  }

 private:
  double& seconds_;
  std::chrono::steady_clock::time_point start_;
  bool running_ = true;
};

// The cap on the links refinement may make (docs/robustness.md, "Budgets"):
// max_links, or fewer where the memory budget is nearer.
class LinkBudget {
 public:
  LinkBudget(std::size_t max_links, std::size_t max_bytes);

  // Whether plan() needs the bytes the data takes now.
  bool counts_bytes() const { return max_bytes_ > 0; }
  std::size_t max_bytes() const { return max_bytes_; }
  // What the usable part of the byte budget has left beside `bytes_used`.
  std::size_t room_bytes(std::size_t bytes_used) const;
  // Sets the cap from the data so far: each link so far came with its share
  // of it (nodes, graph vertices, values), and the links still to make are
  // assumed to bring the same. A tenth of the budget is kept back for what
  // that misses: the step that crosses the cap and arrays growing by doubling.
  // `reserved`: bytes kept for what is not a link of refinement (the first
  // links of surfaces waiting to shoot).
  void plan(std::size_t links_now, std::size_t bytes_used, std::size_t reserved = 0);
  std::size_t cap() const { return cap_; }
  // Whether `new_links` more than `links_now` pass the cap; if so, notes in
  // `stats` which budget stopped refinement.
  bool refuses(std::size_t links_now, std::size_t new_links, SolverStats& stats) const;

 private:
  std::size_t max_links_;
  std::size_t max_bytes_;
  std::size_t cap_ = std::numeric_limits<std::size_t>::max();
  bool memory_caps_ = false;
};

// One iteration's outcome: whether it linked or refined anything, and its
// largest change in the solver's measure (linear: relative to each value;
// classical: relative to the brightest emitted luminance).
struct IterationOutcome {
  bool changed = false;
  double change = 0.0;
};

// Runs step(iteration, last) for iterations 1, 2, … up to max_iterations,
// the checkpoint before each, until one changes nothing and its change is
// below tolerance. Records iterations and final_change in `stats` and calls
// progress(iteration, change) after each.
void iterate_until_converged(int max_iterations, double tolerance, const std::function<void()>& checkpoint,
                             const std::function<IterationOutcome(int iteration, bool last)>& step,
                             const std::function<void(int, double)>& progress, SolverStats& stats);

inline void run_checkpoint(const std::function<void()>& checkpoint) {
  if (checkpoint) checkpoint();
}

// Whether surfaces a and b can exchange light at all: each has a point
// strictly in front of the other's plane (a curved surface has no plane).
bool may_exchange_light(const Surface& a, const Surface& b, double eps);

// A surface's shooters above its roots (radiosity/root_clusters.hpp): each
// root's exposure, the cluster tree built on it, and per cluster the one
// value it shoots with and how far that is from the leaves it stands for
// (shooter_spread.hpp).
struct SurfaceClusters {
  std::vector<double> root_exposure;  // per root: its fraction open to the scene
  std::vector<RootCluster> tree;      // [0] = the whole surface
  std::vector<std::int32_t> leaf_of_root;  // per root: the cluster that opens onto it
  std::vector<Rgb> radiance;          // per cluster
  std::vector<Rgb> spread;            // per cluster

  SurfaceClusters() = default;
  // Clusters of `surface` that start shooting with its emission.
  SurfaceClusters(const MeshedScene& model, int surface);
  std::size_t bytes() const;
};

}  // namespace lhr
