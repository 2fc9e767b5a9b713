#include "mesh/scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lhr {

Bounds scene_bounds(const Scene& scene) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  Bounds b{Vec3(kInf, kInf, kInf), Vec3(-kInf, -kInf, -kInf)};
  bool any = false;
  for (const Surface& s : scene.surfaces) {
    for (const Vec3& p : s.points) {
      b.min.minimize(p);
      b.max.maximize(p);
      any = true;
    }
  }
  if (!any) return Bounds{};
  return b;
}

Camera framing_camera(const Scene& scene) {
  const Bounds b = scene_bounds(scene);
  const Vec3 centre = 0.5 * (b.min + b.max);
  const double radius = std::max(0.5 * b.diagonal(), 1e-12);
  Camera camera;
  camera.fov_y_deg = 45.0;
  // Back off along +z (then a little up) far enough for the bounding sphere
  // to fit the vertical field of view.
  const double distance = radius / std::sin(0.5 * camera.fov_y_deg * M_PI / 180.0);
  const Vec3 direction = Vec3(0.0, 0.25, 1.0).normalized();
  camera.target = centre;
  camera.eye = centre + distance * direction;
  camera.up = Vec3(0, 1, 0);
  return camera;
}

}  // namespace lhr
