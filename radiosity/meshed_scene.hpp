#pragma once
// A scene ready for radiosity: every surface meshed to the minimum density
// with its restricted quadtree, its material, and one Embree scene over the
// initial triangles (refinement splits flat triangles, so it never changes
// the geometry rays see).

#include <array>
#include <cmath>
#include <memory>
#include <vector>

#include "mesh/hierarchy.hpp"
#include "mesh/initial_mesh.hpp"
#include "mesh/scene.hpp"
#include "radiosity/ray_caster.hpp"

namespace lhr {

class MeshedScene {
 public:
  MeshedScene(const Scene& scene, const MeshingOptions& meshing);

  const Scene& scene() const { return *scene_; }
  int num_surfaces() const { return static_cast<int>(hierarchies_.size()); }
  SurfaceHierarchy& hierarchy(int s) { return hierarchies_[s]; }
  const SurfaceHierarchy& hierarchy(int s) const { return hierarchies_[s]; }
  const Material& material(int s) const { return scene_->materials[scene_->surfaces[s].material]; }
  const RayCaster& rays() const { return *rays_; }
  double max_edge() const { return max_edge_; }
  double surface_area(int s) const { return surface_area_[s]; }

  std::array<Vec3, 3> triangle(int s, NodeId n) const;
  // A node's area: its root's over 4^level, since a split cuts a triangle
  // into four congruent ones on the root's plane. Read on the oracles' hot
  // paths, where working it out from the corners was 3 % of a room's solve.
  double area(int s, NodeId n) const {
    const SurfaceHierarchy& h = hierarchies_[s];
    return std::ldexp(root_area_[s][static_cast<std::size_t>(h.root_face(n))], -2 * h.level(n));
  }
  Vec3 normal(int s, NodeId n) const;  // unit, front side
  Vec3 centroid(int s, NodeId n) const;

  // The fraction of a fixed set of directions over the hemisphere of unit
  // normal n whose first hit from origin is the back of a face: about 1 when
  // origin lies inside a closed object (a floor point under a box standing
  // on it), 0 in the open. Deterministic.
  double enclosed_fraction(const Vec3& origin, const Vec3& n) const;

 private:
  const Scene* scene_;
  std::vector<SurfaceHierarchy> hierarchies_;
  std::vector<double> surface_area_;
  std::vector<std::vector<double>> root_area_;  // per surface and root face
  std::unique_ptr<RayCaster> rays_;
  double max_edge_ = 0.0;
};

}  // namespace lhr
