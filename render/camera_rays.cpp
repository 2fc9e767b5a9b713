#include "render/camera_rays.hpp"

#include <cmath>
#include <stdexcept>

namespace lhr {

CameraRays::CameraRays(const Camera& camera) : eye_(camera.eye), width_(camera.width), height_(camera.height) {
  forward_ = camera.target - camera.eye;
  if (!(forward_.norm() > 0)) throw std::invalid_argument("camera: eye and target coincide");
  forward_.normalize();
  right_ = OpenMesh::cross(forward_, camera.up);
  if (!(right_.norm() > 1e-12)) throw std::invalid_argument("camera: up is parallel to the viewing direction");
  right_.normalize();
  up_ = OpenMesh::cross(right_, forward_);
  half_height_ = std::tan(0.5 * camera.fov_y_deg * M_PI / 180.0);
  half_width_ = half_height_ * static_cast<double>(width_) / static_cast<double>(height_);
}

Vec3 CameraRays::direction(int x, int y) const { return direction_at(x + 0.5, y + 0.5); }

Vec3 CameraRays::direction_at(double px, double py) const {
  const double sx = (2.0 * px / width_ - 1.0) * half_width_;
  const double sy = (1.0 - 2.0 * py / height_) * half_height_;
  return (forward_ + sx * right_ + sy * up_).normalized();
}

}  // namespace lhr
