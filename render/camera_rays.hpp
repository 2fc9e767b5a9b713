#pragma once
// Primary rays of the scene camera (DESIGN §3: pinhole, right-handed, vertical
// field of view over the full image height, pixel (0,0) top-left, one ray
// through each pixel centre).

#include "mesh/scene.hpp"

namespace lhr {

class CameraRays {
 public:
  explicit CameraRays(const Camera& camera);
  // Unit direction through the centre of pixel (x, y).
  Vec3 direction(int x, int y) const;
  const Vec3& origin() const { return eye_; }

 private:
  Vec3 eye_, forward_, right_, up_;
  double half_height_ = 0.0, half_width_ = 0.0;
  int width_ = 0, height_ = 0;
};

}  // namespace lhr
