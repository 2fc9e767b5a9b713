#include "radiosity/root_clusters.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "radiosity/sampling.hpp"

namespace lhr {

std::vector<RootCluster> build_root_clusters(const MeshedScene& model, int s, const std::vector<double>& root_exposure,
                                            std::size_t leaf_roots) {
  std::vector<RootCluster> clusters;
  RootCluster top;
  for (std::size_t f = 0; f < model.hierarchy(s).num_roots(); ++f) top.roots.push_back(static_cast<NodeId>(f));
  clusters.push_back(std::move(top));
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    Vec3 lo(1e300, 1e300, 1e300), hi(-1e300, -1e300, -1e300), centroid(0, 0, 0), normal(0, 0, 0);
    double area = 0.0, exposed = 0.0;
    for (NodeId r : clusters[c].roots) {
      const double a = model.area(s, r);
      exposed += a * root_exposure[r];
      const Vec3 p = model.centroid(s, r);
      lo.minimize(p);
      hi.maximize(p);
      centroid += a * p;
      normal += a * model.normal(s, r);
      area += a;
    }
    clusters[c].area = area;
    clusters[c].exposed_area = exposed;
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
    left.parent = right.parent = static_cast<std::int32_t>(c);
    left.roots.assign(roots.begin(), middle);
    right.roots.assign(middle, roots.end());
    clusters[c].first_child = static_cast<std::int32_t>(clusters.size());
    clusters.push_back(std::move(left));
    clusters.push_back(std::move(right));
  }
  return clusters;
}

std::vector<double> root_exposure(const MeshedScene& model, int s) {
  constexpr int kPoints = 4;      // k² points per root
  constexpr int kDirections = 4;  // rays tried per point
  const RayCaster& rays = model.rays();
  std::vector<double> exposure(model.hierarchy(s).num_roots(), 1.0);
  tbb::parallel_for(std::size_t{0}, exposure.size(), [&](std::size_t r) {
    const NodeId root = static_cast<NodeId>(r);
    const auto triangle = model.triangle(s, root);
    const Vec3 n = model.normal(s, root);
    const Vec3 t1 =
        (std::abs(n[0]) < 0.9 ? OpenMesh::cross(n, Vec3(1, 0, 0)) : OpenMesh::cross(n, Vec3(0, 1, 0))).normalized();
    const Vec3 t2 = OpenMesh::cross(n, t1);
    const std::uint64_t key = sample_key(static_cast<std::uint64_t>(s), r, 0xE0);
    const auto points = stratified_triangle_samples(kPoints, key);
    std::size_t closed = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Vec3 origin = rays.lift(at(triangle, points[i]), n);
      bool all_back = true;
      for (int d = 0; d < kDirections && all_back; ++d) {
        const double u = unit_double(sample_key(key, i, 2 * d + 1));
        const double phi = 2.0 * M_PI * unit_double(sample_key(key, i, 2 * d + 2));
        const Vec3 dir = std::sqrt(u) * (std::cos(phi) * t1 + std::sin(phi) * t2) + std::sqrt(1.0 - u) * n;
        const std::optional<RayHit> hit = rays.intersect(origin, dir);
        all_back = hit && OpenMesh::dot(model.normal(hit->surface, hit->face), dir) > 0.0;
      }
      closed += all_back ? 1 : 0;
    }
    exposure[r] = 1.0 - static_cast<double>(closed) / static_cast<double>(points.size());
  });
  return exposure;
}

std::vector<std::array<std::int32_t, 3>> root_corner_edges(const SurfaceHierarchy& h) {
  const TriMesh& mesh = h.mesh();
  std::vector<std::array<std::int32_t, 3>> out(h.num_roots());
  for (std::size_t f = 0; f < h.num_roots(); ++f) {
    const auto& c = h.corners(h.root(static_cast<int>(f)));
    for (int k = 0; k < 3; ++k) {
      const auto he = mesh.find_halfedge(OpenMesh::VertexHandle(c[k]), OpenMesh::VertexHandle(c[(k + 1) % 3]));
      if (!he.is_valid()) throw std::logic_error("root_corner_edges: a root's edge is not in the initial mesh");
      out[f][k] = 2 * mesh.edge_handle(he).idx() + (he.idx() & 1);
    }
  }
  return out;
}

ClusterOutlines cluster_outlines(const SurfaceHierarchy& h, const std::vector<RootCluster>& clusters,
                                 const std::vector<std::array<std::int32_t, 3>>& corner_edges,
                                 std::size_t min_roots) {
  // An outline edge with its edge id, sorted by id: the two copies of an
  // edge two parts share meet in the merge and both go.
  struct Edge {
    std::int32_t id;
    std::array<VertexId, 2> ends;
  };
  std::vector<std::vector<Edge>> outline(clusters.size());
  const auto merge = [](const std::vector<Edge>& a, const std::vector<Edge>& b) {
    std::vector<Edge> out;
    out.reserve(a.size() + b.size());
    std::size_t i = 0, j = 0;
    while (i < a.size() || j < b.size()) {
      if (j == b.size() || (i < a.size() && a[i].id < b[j].id)) {
        out.push_back(a[i++]);
      } else if (i == a.size() || b[j].id < a[i].id) {
        out.push_back(b[j++]);
      } else {
        ++i;
        ++j;
      }
    }
    return out;
  };
  // Children come after their parent, so from the back every child is done
  // before its parent needs it.
  for (std::size_t c = clusters.size(); c-- > 0;) {
    const RootCluster& cluster = clusters[c];
    if (cluster.first_child >= 0) {
      const auto left = static_cast<std::size_t>(cluster.first_child);
      outline[c] = merge(outline[left], outline[left + 1]);
      if (clusters[left].roots.size() < min_roots) outline[left] = {};
      if (clusters[left + 1].roots.size() < min_roots) outline[left + 1] = {};
      continue;
    }
    std::vector<Edge> all;
    for (NodeId r : cluster.roots) {
      const auto& corners = h.corners(r);
      for (int k = 0; k < 3; ++k) all.push_back({corner_edges[r][k] >> 1, {corners[k], corners[(k + 1) % 3]}});
    }
    std::sort(all.begin(), all.end(), [](const Edge& a, const Edge& b) { return a.id < b.id; });
    for (std::size_t i = 0; i < all.size();) {
      std::size_t j = i;
      while (j < all.size() && all[j].id == all[i].id) ++j;
      if (j - i == 1) outline[c].push_back(all[i]);
      i = j;
    }
  }
  ClusterOutlines out;
  out.start.reserve(clusters.size() + 1);
  out.start.push_back(0);
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    if (clusters[c].roots.size() >= min_roots) {
      for (const Edge& e : outline[c]) out.edges.push_back(e.ends);
    }
    out.start.push_back(static_cast<std::uint32_t>(out.edges.size()));
  }
  return out;
}

}  // namespace lhr
