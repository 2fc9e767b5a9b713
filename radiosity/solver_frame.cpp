#include "radiosity/solver_frame.hpp"

#include <algorithm>

#include <nlohmann/json.hpp>

namespace lhr {

namespace {

// Share of max_bytes the link cap plans to fill (LinkBudget::plan).
constexpr double kMemoryBudgetUsable = 0.9;

// Whether a planar surface has a point strictly in front of the other's plane.
bool some_point_in_front(const Surface& a, const Surface& b, double eps) {
  if (!b.planar) return true;
  const Vec3& origin = b.points.front();
  return std::any_of(a.points.begin(), a.points.end(),
                     [&](const Vec3& p) { return OpenMesh::dot(b.normal, p - origin) > eps; });
}

}  // namespace

void SolverStats::write_json(nlohmann::json& doc, const char* values_name, std::size_t bytes_total) const {
  doc["elements"] = leaves;
  doc["links"] = links;
  doc["nodes"] = nodes;
  doc["iterations"] = iterations;
  doc["link_budget_reached"] = link_budget_reached;
  doc["memory_budget_reached"] = memory_budget_reached;
  doc["final_change"] = final_change;
  doc["shadow_rays"] = shadow_rays;
  nlohmann::json& bytes = doc["bytes"];
  bytes["geometry"] = bytes_geometry;
  bytes["hierarchy"] = bytes_hierarchy;
  bytes[values_name] = bytes_values;
  bytes["links"] = bytes_links;
  bytes["total"] = bytes_total;
  nlohmann::json& seconds = doc["seconds"];
  seconds["coefficients"] = seconds_coefficients;
  seconds["gather"] = seconds_gather;
  seconds["push_pull"] = seconds_push_pull;
}

LinkBudget::LinkBudget(std::size_t max_links, std::size_t max_bytes)
    : max_links_(max_links > 0 ? max_links : std::numeric_limits<std::size_t>::max()),
      max_bytes_(max_bytes),
      cap_(max_links_) {}

std::size_t LinkBudget::room_bytes(std::size_t bytes_used) const {
  const double usable = kMemoryBudgetUsable * static_cast<double>(max_bytes_);
  return static_cast<double>(bytes_used) < usable ? static_cast<std::size_t>(usable - static_cast<double>(bytes_used))
                                                   : 0;
}

void LinkBudget::plan(std::size_t links_now, std::size_t bytes_used, std::size_t reserved) {
  cap_ = max_links_;
  memory_caps_ = false;
  if (max_bytes_ == 0) return;
  const double per_link = static_cast<double>(bytes_used) / static_cast<double>(std::max<std::size_t>(links_now, 1));
  const double usable = kMemoryBudgetUsable * static_cast<double>(max_bytes_);
  const double held = static_cast<double>(bytes_used) + static_cast<double>(reserved);
  const std::size_t room = held < usable ? static_cast<std::size_t>((usable - held) / per_link) : 0;
  if (links_now + room < cap_) {
    cap_ = links_now + room;
    memory_caps_ = true;
  }
}

bool LinkBudget::refuses(std::size_t links_now, std::size_t new_links, SolverStats& stats) const {
  if (links_now + new_links <= cap_) return false;
  (memory_caps_ ? stats.memory_budget_reached : stats.link_budget_reached) = true;
  return true;
}

void iterate_until_converged(int max_iterations, double tolerance, const std::function<void()>& checkpoint,
                             const std::function<IterationOutcome(int, bool)>& step,
                             const std::function<void(int, double)>& progress, SolverStats& stats) {
  for (int it = 1; it <= max_iterations; ++it) {
    run_checkpoint(checkpoint);
    const IterationOutcome outcome = step(it, it == max_iterations);
    stats.iterations = it;
    stats.final_change = outcome.change;
    if (progress) progress(it, outcome.change);
    if (!outcome.changed && outcome.change < tolerance) break;
  }
}

bool may_exchange_light(const Surface& a, const Surface& b, double eps) {
  return some_point_in_front(a, b, eps) && some_point_in_front(b, a, eps);
}

SurfaceClusters::SurfaceClusters(const MeshedScene& model, int surface)
    : root_exposure(lhr::root_exposure(model, surface)),
      tree(build_root_clusters(model, surface, root_exposure)),
      radiance(tree.size(), model.material(surface).emission) {
  leaf_of_root.assign(root_exposure.size(), -1);
  for (std::size_t c = 0; c < tree.size(); ++c) {
    if (tree[c].first_child >= 0) continue;
    for (NodeId root : tree[c].roots) leaf_of_root[root] = static_cast<std::int32_t>(c);
  }
}

std::size_t SurfaceClusters::bytes() const {
  std::size_t total = root_exposure.capacity() * sizeof(double) + tree.capacity() * sizeof(RootCluster) +
                      leaf_of_root.capacity() * sizeof(std::int32_t) +
                      (radiance.capacity() + spread.capacity()) * sizeof(Rgb);
  for (const RootCluster& c : tree) total += c.roots.capacity() * sizeof(NodeId);
  return total;
}

}  // namespace lhr
