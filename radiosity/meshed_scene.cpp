#include "radiosity/meshed_scene.hpp"

#include "radiosity/sampling.hpp"

namespace lhr {

MeshedScene::MeshedScene(const Scene& scene, const MeshingOptions& meshing)
    : scene_(&scene), max_edge_(meshing.max_edge) {
  hierarchies_.reserve(scene.surfaces.size());
  const double tolerance = contact_tolerance(scene.surfaces);
  const auto contacts = find_contact_lines(scene.surfaces, tolerance);
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    hierarchies_.emplace_back(mesh_surface(scene.surfaces[s], meshing, contacts[s], tolerance));
  }
  std::vector<const TriMesh*> meshes;
  for (int s = 0; s < num_surfaces(); ++s) {
    const SurfaceHierarchy& h = hierarchies_[s];
    meshes.push_back(&h.mesh());
    std::vector<double>& roots = root_area_.emplace_back(h.num_roots());
    double total = 0.0;
    for (std::size_t f = 0; f < h.num_roots(); ++f) {
      const auto t = triangle(s, h.root(static_cast<int>(f)));
      roots[f] = 0.5 * OpenMesh::cross(t[1] - t[0], t[2] - t[0]).norm();
      total += roots[f];
    }
    surface_area_.push_back(total);
  }
  rays_ = std::make_unique<RayCaster>(meshes);
}

std::array<Vec3, 3> MeshedScene::triangle(int s, NodeId n) const {
  const SurfaceHierarchy& h = hierarchies_[s];
  const auto& c = h.corners(n);
  return {h.point(c[0]), h.point(c[1]), h.point(c[2])};
}

Vec3 MeshedScene::normal(int s, NodeId n) const {
  const auto t = triangle(s, n);
  const Vec3 c = OpenMesh::cross(t[1] - t[0], t[2] - t[0]);
  const double len = c.norm();
  return len > 0 ? c / len : Vec3(0, 0, 0);
}

Vec3 MeshedScene::centroid(int s, NodeId n) const {
  const auto t = triangle(s, n);
  return (t[0] + t[1] + t[2]) / 3.0;
}

double MeshedScene::enclosed_fraction(const Vec3& origin, const Vec3& n) const {
  const std::vector<Vec3> directions = hemisphere_probe_directions(n);
  int back = 0;
  for (const Vec3& d : directions) {
    const auto hit = rays_->intersect(origin, d);
    if (hit && OpenMesh::dot(normal(hit->surface, hierarchies_[hit->surface].root(hit->face)), d) > 0.0) ++back;
  }
  return static_cast<double>(back) / static_cast<double>(directions.size());
}

}  // namespace lhr
