#include "radiosity/root_clusters.hpp"

#include <algorithm>

namespace lhr {

std::vector<RootCluster> build_root_clusters(const SceneModel& model, int s, std::size_t leaf_roots) {
  std::vector<RootCluster> clusters;
  RootCluster top;
  for (std::size_t f = 0; f < model.hierarchy(s).num_roots(); ++f) top.roots.push_back(static_cast<NodeId>(f));
  clusters.push_back(std::move(top));
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    Vec3 lo(1e300, 1e300, 1e300), hi(-1e300, -1e300, -1e300), centroid(0, 0, 0), normal(0, 0, 0);
    double area = 0.0;
    for (NodeId r : clusters[c].roots) {
      const double a = model.area(s, r);
      const Vec3 p = model.centroid(s, r);
      lo.minimize(p);
      hi.maximize(p);
      centroid += a * p;
      normal += a * model.normal(s, r);
      area += a;
    }
    clusters[c].area = area;
    clusters[c].centroid = area > 0 ? centroid / area : centroid;
    clusters[c].normal = normal.norm() > 0 ? normal.normalized() : normal;
    if (clusters[c].roots.size() <= leaf_roots) continue;
    const Vec3 extent = hi - lo;
    const int axis = extent[0] >= extent[1] && extent[0] >= extent[2] ? 0 : (extent[1] >= extent[2] ? 1 : 2);
    std::vector<NodeId> roots = clusters[c].roots;
    const auto middle = roots.begin() + static_cast<std::ptrdiff_t>(roots.size() / 2);
    std::nth_element(roots.begin(), middle, roots.end(), [&](NodeId a, NodeId b) {
      const double ka = model.centroid(s, a)[axis], kb = model.centroid(s, b)[axis];
      return ka < kb || (ka == kb && a < b);
    });
    RootCluster left, right;
    left.roots.assign(roots.begin(), middle);
    right.roots.assign(middle, roots.end());
    clusters[c].first_child = static_cast<std::int32_t>(clusters.size());
    clusters.push_back(std::move(left));
    clusters.push_back(std::move(right));
  }
  return clusters;
}

}  // namespace lhr
