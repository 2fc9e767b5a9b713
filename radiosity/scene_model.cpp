#include "radiosity/scene_model.hpp"

#include <cmath>

namespace lhr {

SceneModel::SceneModel(const Scene& scene, const MeshingOptions& meshing)
    : scene_(&scene), max_edge_(meshing.max_edge) {
  hierarchies_.reserve(scene.surfaces.size());
  const double tolerance = contact_tolerance(scene.surfaces);
  const auto contacts = find_contact_lines(scene.surfaces, tolerance);
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    hierarchies_.emplace_back(mesh_surface(scene.surfaces[s], meshing, contacts[s], tolerance));
  }
  std::vector<const TriMesh*> meshes;
  for (int s = 0; s < num_surfaces(); ++s) {
    meshes.push_back(&hierarchies_[s].mesh());
    double total = 0.0;
    for (std::size_t f = 0; f < hierarchies_[s].num_roots(); ++f) total += area(s, static_cast<NodeId>(f));
    surface_area_.push_back(total);
  }
  rays_ = std::make_unique<RayScene>(meshes);
}

std::array<Vec3, 3> SceneModel::triangle(int s, NodeId n) const {
  const SurfaceHierarchy& h = hierarchies_[s];
  const auto& c = h.corners(n);
  return {h.point(c[0]), h.point(c[1]), h.point(c[2])};
}

double SceneModel::area(int s, NodeId n) const {
  const auto t = triangle(s, n);
  return 0.5 * OpenMesh::cross(t[1] - t[0], t[2] - t[0]).norm();
}

Vec3 SceneModel::normal(int s, NodeId n) const {
  const auto t = triangle(s, n);
  const Vec3 c = OpenMesh::cross(t[1] - t[0], t[2] - t[0]);
  const double len = c.norm();
  return len > 0 ? c / len : Vec3(0, 0, 0);
}

Vec3 SceneModel::centroid(int s, NodeId n) const {
  const auto t = triangle(s, n);
  return (t[0] + t[1] + t[2]) / 3.0;
}

double SceneModel::enclosed_fraction(const Vec3& origin, const Vec3& n) const {
  // Cosine-weighted directions on a 4 x 8 grid of the hemisphere.
  constexpr int kRings = 4, kSectors = 8;
  const Vec3 t = (std::abs(n[0]) < 0.9 ? OpenMesh::cross(n, Vec3(1, 0, 0)) : OpenMesh::cross(n, Vec3(0, 1, 0))).normalized();
  const Vec3 b = OpenMesh::cross(n, t);
  int back = 0;
  for (int i = 0; i < kRings; ++i) {
    const double r = std::sqrt((i + 0.5) / kRings);
    for (int j = 0; j < kSectors; ++j) {
      const double phi = 2.0 * M_PI * (j + 0.5 * (i % 2)) / kSectors;
      const Vec3 d = r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(1.0 - r * r) * n;
      const auto hit = rays_->intersect(origin, d);
      if (hit && OpenMesh::dot(normal(hit->surface, hierarchies_[hit->surface].root(hit->face)), d) > 0.0) ++back;
    }
  }
  return static_cast<double>(back) / (kRings * kSectors);
}

}  // namespace lhr
