#pragma once
// Primary rays of the scene camera (docs/design.md §3: pinhole, right-handed, vertical
// field of view over the full image height, pixel (0,0) top-left, one ray
// through each pixel centre).

#include "mesh/scene.hpp"

namespace lhr {

class CameraRays {
 public:
  explicit CameraRays(const Camera& camera);
  // Unit direction through the centre of pixel (x, y).
  Vec3 direction(int x, int y) const;
  // Unit direction through image point (px, py) in pixel units: pixel (x, y)
  // covers [x, x+1) × [y, y+1), so (x+0.5, y+0.5) is its centre.
  Vec3 direction_at(double px, double py) const;
  const Vec3& origin() const { return eye_; }

 private:
  Vec3 eye_, forward_, right_, up_;
  double half_height_ = 0.0, half_width_ = 0.0;
  int width_ = 0, height_ = 0;
};

}  // namespace lhr
